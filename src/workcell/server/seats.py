"""The server's seats: up to ``--sessions`` sessions at once, each with its own operator,
its own simulation and its own spectators.

A client says who it wants to be in its hello; this module gives it a seat (a
:class:`~workcell.server.conductor.Conductor`) and routes its messages there:

- an operator holding a resume token takes back the seat it dropped;
- any other operator gets the first seat with no operator (and none reserved for a
  dropped one), or a new seat while the server has fewer than ``max_sessions``; when every
  seat has an operator it watches instead, told so by a ``server_full`` error;
- a spectator watches the seat its hello names, or the first.

Seat "1" always exists (what a one-session server has); a later seat goes once it is idle
(no client, no session, no operator's place kept), so seat names are not reused while
anyone could still mean them. With more than one seat, every session records into a shard
of its own, merged into the store when it ends (:mod:`workcell.server.shards`).
"""

from __future__ import annotations

import asyncio
import itertools
import secrets

from workcell.protocol import messages as m
from workcell.server.client import Client
from workcell.server.conductor import Conductor
from workcell.server.options import ServerOptions
from workcell.server.shards import SessionShards


class Seats:
    def __init__(self, options: ServerOptions) -> None:
        self.options = options
        self.shards = SessionShards(options.store) if options.max_sessions > 1 else None
        self.conductors: dict[str, Conductor] = {}
        self.unseated: set[Client] = set()
        self._seat_of: dict[Client, Conductor] = {}
        self._numbers = itertools.count(1)
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

    async def hello(self, client: Client, hello: m.Hello) -> None:
        if client.role is not None:
            client.refuse("protocol", "hello: already said; send it once per connection")
            return
        self._tidy()
        if hello.seat is not None and hello.seat not in self.conductors:
            seats = ", ".join(self.conductors)
            client.refuse(
                "invalid_value", f"hello.seat = {hello.seat!r}: no such seat; seats now: {seats}"
            )
            return
        conductor = self._seat_for(hello)
        self.unseated.discard(client)
        self._seat_of[client] = conductor
        conductor.connected(client)
        granted = await conductor.hello(client, hello)
        if hello.role == "operator" and granted == "spectator":
            client.send(m.Error(code="server_full", message=self._full_message(conductor)))

    def _seat_for(self, hello: m.Hello) -> Conductor:
        named = self.conductors.get(hello.seat) if hello.seat is not None else None
        if hello.role != "operator":
            return named or self.first
        if hello.resume_token is not None:
            for conductor in self.conductors.values():
                kept = conductor.resume_token
                if kept is not None and secrets.compare_digest(
                    hello.resume_token.encode(), kept.encode()
                ):
                    return conductor
        for conductor in self.conductors.values():
            if conductor.operator is None and conductor.resume_token is None:
                return conductor
        if len(self.conductors) < self.options.max_sessions:
            return self._add()
        return named or self.first

    def _full_message(self, watched: Conductor) -> str:
        most = self.options.max_sessions
        held = "the one seat has" if most == 1 else f"all {most} seats have"
        return (
            f"server full: {held} an operator (workcell serve --sessions {most}); you are "
            f"watching seat {watched.seat}; connect again later to drive"
        )

    def _add(self) -> Conductor:
        seat = str(next(self._numbers))
        conductor = Conductor(self.options, seat, self.shards)
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
