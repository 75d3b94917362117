"""The server's counters as a :class:`~workcell.protocol.api.Diagnostics` body."""

from __future__ import annotations

import time

from workcell.protocol.api import ClientDiagnostics, Diagnostics, SimDiagnostics
from workcell.server.client import Client
from workcell.server.conductor import Conductor
from workcell.server.seats import Seats


def diagnostics(seats: Seats, process_cpu_s: float) -> Diagnostics:
    seated = [
        (c, conductor.seat) for conductor in seats.conductors.values() for c in conductor.clients
    ]
    everyone = seated + [(c, None) for c in seats.unseated]
    clients = tuple(_client(c, seat) for c, seat in sorted(everyone, key=lambda x: x[0].id))
    sims = tuple(s for s in map(sim_diagnostics, seats.conductors.values()) if s is not None)
    first = sim_diagnostics(seats.first)
    return Diagnostics(process_cpu_s=round(process_cpu_s, 6), clients=clients, sim=first, sims=sims)


def _client(client: Client, seat: str | None) -> ClientDiagnostics:
    return ClientDiagnostics(
        client=client.id,
        role=client.role,
        received=client.stats.received,
        errors=dict(client.stats.errors),
        states_sent=client.stats.states_sent,
        states_dropped=client.stats.states_dropped,
        seat=seat,
    )


def sim_diagnostics(conductor: Conductor) -> SimDiagnostics | None:
    session = conductor.session
    if session is None:
        return None
    stats = session.pacing
    period = session.config.world.control_substeps * session.config.world.timestep
    wall = time.monotonic() - stats.started - stats.paused_s if stats.steps else 0.0
    overall = round(stats.steps * period / wall, 4) if wall > 0 else 0.0
    recent = round(stats.recent_real_time_factor, 4)
    return SimDiagnostics(
        session_id=session.session_id,
        control_period_s=period,
        steps=stats.steps,
        late_steps=stats.late_steps,
        dropped_s=round(stats.dropped_s, 6),
        max_step_ms=round(stats.max_step_s * 1000.0, 3),
        real_time_factor=recent if recent > 0 else overall,
        seat=conductor.seat,
        cores=round(stats.recent_cores, 3),
        paused_s=round(stats.paused_s, 3),
    )
