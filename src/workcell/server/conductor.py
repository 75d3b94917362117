"""One seat of the server: its session, who controls it and who watches.

Runs on the event loop. One client at a time is the seat's operator; every other client of
the seat is a spectator. A dropped operator keeps its place for the grace period and takes
it back with its resume token; past the grace period the running trial ends
``client_lost``. :class:`~workcell.server.seats.Seats` gives each client its seat.
"""

from __future__ import annotations

import asyncio
import dataclasses
import logging
import secrets
from pathlib import Path
from typing import Any

from workcell.errors import WorkcellError
from workcell.protocol import messages as m
from workcell.protocol.codec import encode
from workcell.record.errors import StoreError
from workcell.server.client import Client
from workcell.server.options import ServerOptions
from workcell.server.scene import idle_scene
from workcell.server.session_listener import SessionListener
from workcell.server.session_process import SessionProcess
from workcell.server.session_relay import RelayedSession, SessionArgs, SessionFactory
from workcell.server.session_settings import SessionPlanner, session_settings
from workcell.server.shards import SessionShards
from workcell.server.waiting_line import WaitingLine
from workcell.session.config import SessionConfig

logger = logging.getLogger(__name__)

LINK_DROPPED = "link dropped: the operator's connection closed"
"""The reason of the ``hand_back`` recorded when the person who took over disconnects."""


class Conductor:
    def __init__(
        self,
        options: ServerOptions,
        seat: str = "1",
        shards: SessionShards | None = None,
        planner: SessionPlanner | None = None,
        launch: SessionFactory = SessionProcess,
        *,
        line: WaitingLine | None = None,
    ) -> None:
        self.options = options
        self.line = line
        """Where a start waits while the machine has no headroom (None: never waits)."""
        self.seat = seat
        self.planner = planner
        self.launch = launch
        """Makes the seat's sessions: each in a process of its own, or in a Ray actor."""
        self.shards = shards
        """Where sessions record when the server has several seats (None: the store)."""
        self.store: Path = options.store
        """Where the running (or last) session records."""
        self.clients: set[Client] = set()
        self.operator: Client | None = None
        self.resume_token: str | None = None
        self.session: RelayedSession | None = None
        self.quitting = False
        self._loop: asyncio.AbstractEventLoop | None = None
        self._grace: asyncio.TimerHandle | None = None
        self._starting = False
        self._idle_scene: m.Scene | None = None
        self._paused_event: str | None = None
        """The running trial's ``paused`` event while it stands paused (sent to a client
        that connects meanwhile)."""
        self.sessions_started = 0

    # --- connections ------------------------------------------------------------------------

    def connected(self, client: Client) -> None:
        self._loop = asyncio.get_running_loop()
        self.clients.add(client)

    def disconnected(self, client: Client) -> None:
        self.clients.discard(client)
        if self.line is not None:
            self.line.leave(client)
        if client is not self.operator:
            return
        self.operator = None
        if self.session is None or self.quitting:
            self.resume_token = None
            return
        self.session.operator.new_link()  # no input arrives: the base stops, arms freeze
        if self.session.args.config.driver != "person":  # a person driving hands back
            self.session.request_driving(False, LINK_DROPPED)
        loop = asyncio.get_running_loop()
        self._grace = loop.call_later(self.options.grace_s, self._grace_over)

    def _grace_over(self) -> None:
        self._grace = None
        if self.operator is None and self.session is not None:
            self.resume_token = None
            self.session.request_stop("client_lost")

    # --- messages ---------------------------------------------------------------------------

    async def hello(self, client: Client, hello: m.Hello) -> m.Role | None:
        """Welcome ``client`` in the role it may have; that role (None: refused)."""
        if client.role is not None:
            client.refuse("protocol", "hello: already said; send it once per connection")
            return None
        role: m.Role = "spectator"
        token = None
        wants = hello.role == "operator"
        if wants and self.operator is None and self._may_resume(hello.resume_token):
            role = "operator"
            self._take_control(client)
            token = self.resume_token
        client.role = role
        session = self.session
        client.send(
            m.Welcome(
                protocol=m.PROTOCOL_VERSION,
                role=role,
                session_id=session.session_id if session else None,
                resume_token=token,
                grace_s=self.options.grace_s,
                seat=self.seat,
            )
        )
        if session is not None:
            client.send(self._started_message(session))
        client.send(session.scene if session and session.scene else await self._default_scene())
        if session is not None and self._paused_event is not None:
            client.send_text(self._paused_event)  # a client that comes in mid-pause hears it
        return role

    def _may_resume(self, offered: str | None) -> bool:
        """The seat is free, or reserved for the dropped operator holding ``offered``."""
        if self.resume_token is None:
            return True
        return offered is not None and secrets.compare_digest(
            offered.encode(), self.resume_token.encode()
        )

    def _take_control(self, client: Client) -> None:
        if self._grace is not None:
            self._grace.cancel()
            self._grace = None
        self.operator = client
        self.resume_token = secrets.token_urlsafe(24)
        if self.session is not None:
            self.session.operator.new_link()

    async def start_session(self, client: Client, start: m.StartSession) -> None:
        if client is not self.operator:
            client.refuse("not_allowed", "start_session: only the operator starts a session")
            return
        if self.busy:
            client.refuse("not_allowed", "start_session: a session is running; stop it first")
            return
        if self.line is None or self.line.admit(self, client, start):
            await self.begin(client, start)

    @property
    def busy(self) -> bool:
        """A session runs or starts at this seat."""
        return self.session is not None or self._starting

    async def begin(self, client: Client, start: m.StartSession) -> None:
        """Start the session now (admitted): tell every client, or ``client`` why not."""
        if self.busy or client is not self.operator:
            return  # the seat started otherwise, or its operator left while waiting
        self._starting = True
        try:
            session = await self._start(client, start)
        finally:  # whatever happened, the seat is not left starting
            self._starting = False
        if session is None:
            return
        self.session = session
        self.sessions_started += 1
        self.broadcast(self._started_message(session))
        if session.scene is not None:
            self.broadcast(session.scene)
        await session.serve()  # its States and events follow session_started

    async def _start(self, client: Client, start: m.StartSession) -> RelayedSession | None:
        """The started session, or None once ``client`` has heard why not: any failure on
        the way (a setting, the store, the session's process dying) is one error."""
        session: RelayedSession | None = None
        try:
            config = await session_settings(self.planner, client, start)
            if config is None:
                return None
            self.store = self.shards.new_shard() if self.shards else self.options.store
            options = self.options
            args = SessionArgs(
                config, self.store, options.state_hz, options.max_catch_up_s, options.key_file
            )
            session = self.launch(args, SessionListener(self))
            await asyncio.to_thread(session.start)
            return session
        except WorkcellError as error:  # e.g. the store is another process's
            client.refuse("not_allowed", f"start_session: {error}")
        except Exception as error:
            logger.exception("seat %s: a session failed to start", self.seat)
            client.refuse(
                "not_allowed",
                f"start_session: the session failed to start ({type(error).__name__}: "
                f"{error}); the seat is free to start again",
            )
        if session is not None and session.running:
            session.kill()  # it started but could not be taken on
        return None

    @property
    def starting(self) -> bool:
        return self._starting

    def input(self, client: Client, message: m.Input) -> None:
        if client is not self.operator:
            client.refuse("not_allowed", "input: only the operator drives; you are a spectator")
            return
        if self.session is None:
            return  # inputs between sessions have nothing to drive
        if not self.session.operator.submit(message):
            client.refuse("protocol", f"input.seq = {message.seq}: older than the last input")

    def act(self, client: Client, message: m.Act) -> None:
        if client is not self.operator:
            client.refuse("not_allowed", f"act: only the operator acts ({message.action})")
        elif self.session is None:
            client.refuse("not_allowed", f"act: no session is running ({message.action})")
        else:
            self.session.request_action(message.action, message.source)

    def drive(self, client: Client, message: m.TakeOver | m.HandBack) -> None:
        """The person takes control from the session's driver or hands it back."""
        if client is not self.operator:
            client.refuse("not_allowed", f"{message.type}: only the operator drives")
        elif self.session is None:
            client.refuse("not_allowed", f"{message.type}: no session is running")
        elif self.session.args.config.driver == "person":
            client.refuse(
                "not_allowed",
                f"{message.type}: this session's driver is the person (driver = person); "
                "only a session driven by expert or policy:PATH can be taken over",
            )
        else:
            person = isinstance(message, m.TakeOver)
            self.session.request_driving(person, message.reason.strip())

    def frame_stats(self, client: Client, message: m.FrameStats) -> None:
        """The operator's drawing figures go into the record; a spectator's are not asked
        for and are ignored, as are reports while no session runs."""
        if client is self.operator and self.session is not None:
            self.session.report_frames(message)

    def stop_by_admin(self, note: str = "") -> bool:
        """The study's admin ends the running session (its trial ends interrupted:
        ``admin_stop``; ``note``, their words, is recorded and told to the participant);
        False when none runs."""
        if self.session is None:
            return False
        self.session.request_stop("admin_stop", note)
        return True

    def stop(self, client: Client, message: m.Stop) -> None:
        if client is not self.operator:
            client.refuse("not_allowed", "stop: only the operator stops the session")
        elif self.session is None:
            client.refuse("not_allowed", "stop: no session is running")
        else:
            self.session.request_stop("operator_stop", message.reason.strip())

    def pause(self, client: Client, message: m.Pause) -> None:
        if client is not self.operator:
            client.refuse("not_allowed", "pause: only the operator pauses the session")
        elif self.session is None:
            client.refuse("not_allowed", "pause: no session is running")
        else:
            self.session.request_pause(message.paused)

    # --- session output (on the loop) -------------------------------------------------------

    def broadcast(self, message: m.ServerMessage) -> None:
        text = encode(message)
        for client in self.clients:
            if client.role is not None:
                client.send_text(text)

    def broadcast_text(self, text: str) -> None:
        if '"kind":"paused"' in text:
            self._paused_event = text
        elif '"kind":"resumed"' in text or '"kind":"trial_ended"' in text:
            self._paused_event = None
        for client in self.clients:
            if client.role is not None:
                client.send_text(text)

    def broadcast_state(self, text: str) -> None:
        for client in self.clients:
            if client.role is not None:
                client.offer_state(text)

    async def session_ended(self, ended: m.SessionEnded) -> None:
        if self.session is not None:
            await asyncio.to_thread(self.session.join, 30.0)  # its store is closed
        if self.shards is not None:
            ended = await asyncio.to_thread(self._merge, ended)
        self.session = None
        self._paused_event = None
        if self.operator is None:
            self.resume_token = None
            if self._grace is not None:
                self._grace.cancel()
                self._grace = None
        self.broadcast(ended)

    def _merge(self, ended: m.SessionEnded) -> m.SessionEnded:
        """The session's shard into the store (blocking); a failure is the ended
        message's detail, and the shard stays for the next start."""
        assert self.shards is not None
        try:
            self.shards.merge(self.store)
        except StoreError as error:
            logger.warning("seat %s: %s not merged: %s", self.seat, ended.session_id, error)
            problem = f"recorded in {self.store}, not yet merged into the store: {error}"
            detail = "; ".join(filter(None, (ended.detail, problem)))
            return dataclasses.replace(ended, detail=detail)
        return ended

    @property
    def idle(self) -> bool:
        """No client, no session, no operator's place kept: the seat can go."""
        return (
            not self.clients
            and self.session is None
            and not self._starting
            and self.resume_token is None
        )

    def _started_message(self, session: RelayedSession) -> m.SessionStarted:
        settings: dict[str, Any] = dataclasses.asdict(session.config)
        return m.SessionStarted(
            session_id=session.session_id,
            mode=session.config.task.mode,
            operator_id=session.config.operator_id,
            settings=settings,
        )

    async def _default_scene(self) -> m.Scene:
        if self._idle_scene is None:
            self._idle_scene = await asyncio.to_thread(idle_scene, SessionConfig())
        return self._idle_scene

    # --- shutdown ---------------------------------------------------------------------------

    def quit(self) -> None:
        """The server is stopping: end the running trial as ``application_quit``."""
        self.quitting = True
        if self.session is not None:
            self.session.request_stop("application_quit")

    async def shutdown(self) -> None:
        """End the session (if any) while clients are still connected and tell them."""
        self.quit()
        if self.session is not None:
            await asyncio.to_thread(self.finish, 30.0)
            for _ in range(100):  # its SessionEnded is broadcast by a callback on this loop
                if self._settled():
                    break
                await asyncio.sleep(0.01)

    def _settled(self) -> bool:
        """No session, and every client has been sent what it was due."""
        return self.session is None and not any(c.pending for c in self.clients)

    def close_clients(self) -> None:
        for client in list(self.clients):
            client.close()

    def finish(self, timeout: float) -> bool:
        """Wait (blocking) until a stopping session has closed its trial and its store."""
        session = self.session
        return session is None or session.join(timeout)

    @property
    def loop(self) -> asyncio.AbstractEventLoop | None:
        return self._loop
