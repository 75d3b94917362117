"""The server's seats: up to ``--sessions`` sessions at once, each with its own operator,
its own simulation and its own spectators.

A client says who it wants to be in its hello; this module gives it a seat (a
:class:`~workcell.server.conductor.Conductor`) and routes its messages there:

- an operator holding a resume token takes back the seat it dropped;
- any other operator gets the first seat with no operator (and none reserved for a
  dropped one), or a new seat while the server has fewer than ``max_sessions``; when every
  seat has an operator it watches instead, told so by a ``server_full`` error;
- a spectator watches the seat its hello names, or the first.

With a study (``workcell serve --study``), a participant's invite leads to the seat named
by their participant id and to no other: they drive it (or watch it from a second tab), and
its sessions follow their plan; any other seat (the admin's, a page without an invite)
starts no session, so the study's store holds its participants' planned sessions only.
Then ``max_sessions`` bounds the sessions running at once:
a participant who would start one more hears ``server_full`` and may start again later.
Within that bound, a start waits in line while the machine has no headroom for one more
session at real time (:mod:`workcell.server.admission`, :mod:`workcell.server.waiting_line`).

Seat "1" always exists (what a one-session server has); a later seat goes once it is idle
(no client, no session, no operator's place kept), so seat names are not reused while
anyone could still mean them. With more than one seat, every session records into a shard
of its own, merged into the store when it ends (:mod:`workcell.server.shards`). Each
session runs in a process of its own, or in a Ray actor with ``--ray``
(:mod:`workcell.server.session_actor`).
"""

from __future__ import annotations

import asyncio
import itertools
import secrets

from workcell.protocol import messages as m
from workcell.server.admission import AdmissionRule, Measured
from workcell.server.auth import ADMIN, Principal
from workcell.server.client import Client
from workcell.server.conductor import Conductor
from workcell.server.options import ServerOptions
from workcell.server.session_process import SessionProcess
from workcell.server.session_relay import SessionFactory
from workcell.server.session_settings import SessionPlanner
from workcell.server.shards import SessionShards
from workcell.server.study_desk import Refusal, StudyDesk
from workcell.server.waiting_line import WaitingLine
from workcell.session.config import SessionConfig


class Seats:
    def __init__(
        self,
        options: ServerOptions,
        desk: StudyDesk | None = None,
        launch: SessionFactory = SessionProcess,
    ) -> None:
        self.options = options
        self.desk = desk
        self.launch = launch
        """Makes every seat's sessions: in processes of their own, or in Ray actors
        (:class:`~workcell.server.session_actor.RaySessions`, ``--ray``)."""
        self.shards = (
            SessionShards(options.store, options.key_file) if options.max_sessions > 1 else None
        )
        self.conductors: dict[str, Conductor] = {}
        self.unseated: set[Client] = set()
        self._seat_of: dict[Client, Conductor] = {}
        self._numbers = itertools.count(1)
        self.line = WaitingLine(
            AdmissionRule.of_machine(options.admit_cores, options.admit_min_real_time_factor),
            self.measured,
        )
        """Starts waiting for headroom (:mod:`workcell.server.admission`)."""
        self._add()

    @property
    def first(self) -> Conductor:
        return next(iter(self.conductors.values()))

    def of(self, client: Client) -> Conductor | None:
        """The seat ``client`` drives or watches (None before its hello)."""
        return self._seat_of.get(client)

    @property
    def operators(self) -> int:
        return sum(c.operator is not None for c in self.conductors.values())

    # --- connections ------------------------------------------------------------------------

    def connected(self, client: Client) -> None:
        self.unseated.add(client)

    def disconnected(self, client: Client) -> None:
        self.unseated.discard(client)
        conductor = self._seat_of.pop(client, None)
        if conductor is not None:
            conductor.disconnected(client)
        self._tidy()

    def measured(self) -> list[Measured | None]:
        """Each running or starting session's recent figures (None: not yet measured)."""
        figures: list[Measured | None] = []
        for conductor in self.conductors.values():
            if not conductor.busy:
                continue
            pacing = conductor.session.pacing if conductor.session is not None else None
            if pacing is None or pacing.recent_real_time_factor <= 0:
                figures.append(None)
            else:
                figures.append(Measured(pacing.recent_real_time_factor, pacing.recent_cores))
        return figures

    @property
    def running(self) -> int:
        """Sessions running or starting."""
        return sum(c.session is not None or c.starting for c in self.conductors.values())

    async def hello(self, client: Client, hello: m.Hello, principal: Principal = ADMIN) -> None:
        if client.role is not None:
            client.refuse("protocol", "hello: already said; send it once per connection")
            return
        self._tidy()
        if principal.participant is not None:
            await self._participant_hello(client, hello, principal.participant)
            return
        if hello.seat is not None and hello.seat not in self.conductors:
            seats = ", ".join(self.conductors)
            client.refuse(
                "invalid_value", f"hello.seat = {hello.seat!r}: no such seat; seats now: {seats}"
            )
            return
        conductor = self._seat_for(hello)
        granted = await self._seat(client, conductor, hello)
        if hello.role == "operator" and granted == "spectator":
            client.send(m.Error(code="server_full", message=self._full_message(conductor)))

    async def _participant_hello(self, client: Client, hello: m.Hello, participant: str) -> None:
        if hello.seat not in (None, participant):
            client.refuse(
                "not_allowed",
                f"hello.seat = {hello.seat!r}: your invite opens only your own seat, {participant}",
            )
            return
        conductor = self.conductors.get(participant) or self._add(participant)
        granted = await self._seat(client, conductor, hello)
        if hello.role == "operator" and granted == "spectator":
            message = (
                "your session is driven from another connection (another tab or device); "
                "you are watching it; close that one and reload to drive here"
            )
            client.send(m.Error(code="not_allowed", message=message))

    async def _seat(self, client: Client, conductor: Conductor, hello: m.Hello) -> m.Role | None:
        """Put ``client`` at ``conductor``'s seat and welcome it there; the role granted."""
        self.unseated.discard(client)
        self._seat_of[client] = conductor
        conductor.connected(client)
        return await conductor.hello(client, hello)

    def _seat_for(self, hello: m.Hello) -> Conductor:
        named = self.conductors.get(hello.seat) if hello.seat is not None else None
        if hello.role != "operator":
            return named or self.first
        own = [c for c in self.conductors.values() if not isinstance(c.planner, ParticipantPlanner)]
        if hello.resume_token is not None:
            for conductor in own:
                kept = conductor.resume_token
                if kept is not None and secrets.compare_digest(
                    hello.resume_token.encode(), kept.encode()
                ):
                    return conductor
        for conductor in own:
            if conductor.operator is None and conductor.resume_token is None:
                return conductor
        if len(own) < self.options.max_sessions:
            return self._add()
        return named or self.first

    def _full_message(self, watched: Conductor) -> str:
        most = self.options.max_sessions
        held = "the one seat has" if most == 1 else f"all {most} seats have"
        return (
            f"server full: {held} an operator (workcell serve --sessions {most}); you are "
            f"watching seat {watched.seat}; connect again later to drive"
        )

    def _add(self, participant: str | None = None) -> Conductor:
        seat = participant or str(next(self._numbers))
        planner: SessionPlanner | None = None
        if participant is not None and self.desk is not None:
            planner = ParticipantPlanner(self, self.desk, participant)
        elif self.desk is not None:  # the admin's (or a page's without an invite)
            planner = InvitesOnly(self.desk)
        line = self.line if self.options.admission else None
        conductor = Conductor(self.options, seat, self.shards, planner, self.launch, line=line)
        self.conductors[seat] = conductor
        return conductor

    def _tidy(self) -> None:
        """Idle seats other than the first go."""
        first = self.first
        for seat, conductor in list(self.conductors.items()):
            if conductor is not first and conductor.idle:
                del self.conductors[seat]

    # --- shutdown ---------------------------------------------------------------------------

    def quit(self) -> None:
        self.line.close()
        for conductor in list(self.conductors.values()):
            conductor.quit()

    async def shutdown(self) -> None:
        await asyncio.gather(*(c.shutdown() for c in list(self.conductors.values())))

    def finish(self, timeout: float) -> bool:
        """Wait (blocking) until every stopping session has closed its trial and store."""
        return all([c.finish(timeout) for c in list(self.conductors.values())])

    def close_clients(self) -> None:
        for client in list(self.unseated):
            client.close()
        for conductor in list(self.conductors.values()):
            conductor.close_clients()

    def merge_leftovers(self) -> list[str]:
        """Shards an earlier run left (a killed server) into the store (blocking)."""
        return self.shards.merge_leftovers() if self.shards else []


class ParticipantPlanner:
    """A participant's seat: each session is the next of their plan, started while the
    server runs fewer than ``max_sessions``."""

    def __init__(self, seats: Seats, desk: StudyDesk, participant: str) -> None:
        self.seats = seats
        self.desk = desk
        self.participant = participant

    async def plan(self, start: m.StartSession) -> SessionConfig | Refusal:
        most = self.seats.options.max_sessions
        others = self.seats.running - 1  # this seat is starting
        if others >= most:
            return Refusal(
                "server_full",
                f"server full: {others} sessions are running, the most this server runs at "
                f"once (workcell serve --sessions {most}); start again in a minute",
            )
        return await asyncio.to_thread(self.desk.next_session, self.participant, start.consent)


class InvitesOnly:
    """A seat of a study server that is not a participant's: it records nothing, so that
    every session in the study's store is a planned session of a participant."""

    def __init__(self, desk: StudyDesk) -> None:
        self.desk = desk

    async def plan(self, start: m.StartSession) -> SessionConfig | Refusal:
        return Refusal(
            "not_allowed",
            f"start_session: this server runs study {self.desk.study.name} and records only "
            "its participants' planned sessions; a session starts from a participant's "
            "invite link (the admin page lists them)",
        )
