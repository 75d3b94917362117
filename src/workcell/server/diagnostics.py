"""The server's counters as a :class:`~workcell.protocol.api.Diagnostics` body."""

from __future__ import annotations

import time

from workcell.protocol.api import ClientDiagnostics, Diagnostics, SimDiagnostics
from workcell.server.conductor import Conductor


def diagnostics(conductor: Conductor, process_cpu_s: float) -> Diagnostics:
    clients = tuple(
        ClientDiagnostics(
            client=c.id,
            role=c.role,
            received=c.stats.received,
            errors=dict(c.stats.errors),
            states_sent=c.stats.states_sent,
            states_dropped=c.stats.states_dropped,
        )
        for c in sorted(conductor.clients, key=lambda c: c.id)
    )
    session = conductor.session
    sim = None
    if session is not None:
        stats = session.pacing
        period = session.config.world.control_substeps * session.config.world.timestep
        wall = time.monotonic() - stats.started if stats.steps else 0.0
        sim = SimDiagnostics(
            session_id=session.session_id,
            control_period_s=period,
            steps=stats.steps,
            late_steps=stats.late_steps,
            dropped_s=round(stats.dropped_s, 6),
            max_step_ms=round(stats.max_step_s * 1000.0, 3),
            real_time_factor=round(stats.steps * period / wall, 4) if wall > 0 else 0.0,
        )
    return Diagnostics(process_cpu_s=round(process_cpu_s, 6), clients=clients, sim=sim)
