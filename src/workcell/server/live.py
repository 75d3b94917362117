"""One session running in real time on its own thread, recorded into the store.

The thread runs a :class:`~workcell.recording.recorded_session.RecordedSession` (paced on
the wall clock, driven by a teleoperator) and owns everything that is not thread-safe: the
store's writer connection, the simulation, the runner and the recorder. Other threads talk
to it only through :meth:`LiveSession.request_stop` and the operator's latest-input slot,
and hear from it through a :class:`SessionListener` (called on the simulation thread).
"""

from __future__ import annotations

import collections
import contextlib
import dataclasses
import logging
import threading
from collections.abc import Callable
from pathlib import Path
from typing import Protocol

from workcell.errors import WorkcellError
from workcell.intervene.driver import live_driver
from workcell.intervene.operator import InterveningOperator
from workcell.intervene.switch import switch
from workcell.protocol.codec import encode
from workcell.protocol.messages import FrameStats, Scene, SessionEnded
from workcell.recording.recorded_session import RealTime, RecordedSession, RecordedSessionConfig
from workcell.server.scene import describe
from workcell.server.state_message import StateBuilder, event_message
from workcell.session.config import SessionConfig
from workcell.sim.world import World
from workcell.task import events as ev
from workcell.task.hud import HudPhase
from workcell.task.pacing import Idle, PacingStats, PauseRequest, StopRequest
from workcell.task.runner import SessionRunner
from workcell.teleop.operator import TeleopOperator
from workcell.teleop.rate import at_teleop_rate

logger = logging.getLogger(__name__)

SNAPS: dict[ev.OperatorAction, int] = {"snap_left": 1, "snap_right": -1}
"""The actions that turn the base by a snap (the direction of each)."""


class SessionListener(Protocol):
    """Receives a live session's output, on the simulation thread."""

    def state(self, text: str) -> None:
        """The newest State (encoded); an older one not yet sent may be dropped."""

    def message(self, text: str) -> None:
        """An encoded message every client must get, in order (task events)."""

    def ended(self, message: SessionEnded) -> None:
        """The session is over and its store closed."""


class LiveSession:
    """Start with :meth:`start`, which returns once the session is recording (or raises)."""

    def __init__(
        self,
        config: SessionConfig,
        store_path: Path,
        listener: SessionListener,
        state_hz: float = 60.0,
        max_catch_up_s: float = 0.25,
        *,
        key_file: Path | None = None,
        idle: Idle | None = None,
    ) -> None:
        """``idle``: how the simulation thread waits between control periods when it has
        work to do meanwhile (the child reading the server's requests,
        :data:`~workcell.task.pacing.Idle`)."""
        self.config = at_teleop_rate(config)
        """The session as it runs: at the control rate a person drives at."""
        self.recorded = RecordedSessionConfig(
            session=self.config,
            driver=live_driver(self.config),
            store=store_path,
            key_file=key_file,
            real_time=RealTime(max_catch_up_s),
        )
        """The recorded session this live session runs (picklable)."""
        self.listener = listener
        self.state_period = 1.0 / state_hz
        self.session_id = ""
        self.scene: Scene | None = None
        self._session: RecordedSession | None = None
        self._stop = StopRequest()
        self._pause = PauseRequest()
        self._requests: collections.deque[Callable[[SessionRunner], None]] = collections.deque()
        self._ready = threading.Event()
        self._startup_error: BaseException | None = None
        self._idle = idle
        self._thread = threading.Thread(target=self._main, name="workcell-sim", daemon=True)

    def start(self) -> None:
        """Open the store, build the world and begin the first trial (blocking)."""
        self._thread.start()
        self._ready.wait()
        if self._startup_error is not None:
            self._thread.join()
            raise self._startup_error

    def request_action(self, action: ev.OperatorAction, source: ev.ActionSource) -> None:
        """Have the runner act on an operator's action at its next control period (from
        any thread)."""

        def apply(runner: SessionRunner) -> None:
            runner.act_on(action, source)
            if action in SNAPS and runner.phase is HudPhase.RUNNING:
                self.operator.ask_snap(SNAPS[action])

        self._requests.append(apply)

    def request_driving(self, person: bool, reason: str = "") -> None:
        """The person takes control from the session's driver (``person``) or hands it
        back, at the next control period (from any thread); nothing happens in a session
        the person drives anyway, or when it is so already."""

        def apply(runner: SessionRunner) -> None:
            session = self._session
            if session is not None and isinstance(session.operator, InterveningOperator):
                switch(session.operator, runner, person, self.config.operator_id, reason)

        self._requests.append(apply)

    def report_frames(self, stats: FrameStats) -> None:
        """Record how the operator's browser draws, at the next control period (from any
        thread)."""

        figures = {f.name: getattr(stats, f.name) for f in dataclasses.fields(ev.FrameFigures)}

        def event(trial_index: int, t_sim: float) -> ev.TaskEvent:
            return ev.ClientFrames(trial_index=trial_index, t_sim=t_sim, **figures)

        self._requests.append(lambda runner: runner.note(event))

    def request_stop(self, reason: ev.InterruptionReason, note: str = "") -> None:
        """End the running trial as interrupted with ``reason`` (from any thread);
        ``note``: the words of whoever stopped it (recorded, and told to the clients)."""
        self._stop.request(reason, note)
        self._pause.wake()

    def request_pause(self, paused: bool) -> None:
        """Pause or resume the running trial (from any thread): see
        ``RecordedSession.pause`` (:mod:`workcell.recording.recorded_session`)."""
        self._pause.set(paused)

    def join(self, timeout: float | None = None) -> bool:
        self._thread.join(timeout)
        return not self._thread.is_alive()

    @property
    def running(self) -> bool:
        return self._thread.is_alive()

    @property
    def operator(self) -> TeleopOperator:
        """The operator the client's inputs go to (once :meth:`start` has returned)."""
        assert self._session is not None
        operator = self._session.operator
        if isinstance(operator, InterveningOperator):
            operator = operator.person
        assert isinstance(operator, TeleopOperator)
        return operator

    @property
    def pacing(self) -> PacingStats:
        return PacingStats() if self._session is None else self._session.pacing

    # --- the simulation thread --------------------------------------------------------------

    def _main(self) -> None:
        with contextlib.ExitStack() as stack:
            try:
                session = RecordedSession(self.recorded, self._stop, self._pause, self._idle)
                stack.enter_context(session.recording())
            except BaseException as error:  # reported to the caller of start()
                self._startup_error = error
                self._ready.set()
                return
            self._run(session)

    def _run(self, session: RecordedSession) -> None:
        self._session = session
        self.session_id = session.session_id
        world = session.sim.world
        session.runner.bus.subscribe(lambda event: self._forward(event, world))
        session.start()
        self.scene = describe(world.model, world.data)
        self._ready.set()
        reason: ev.SessionEndReason = "error"
        detail = "the simulation thread failed"
        try:
            send_state = self._state_sender(session)

            def after_step() -> None:
                self._apply_requests(session)
                send_state()

            reason = session.run(after_step=after_step)
            detail = ""
            if reason == "storage_error":  # the clients are told what failed, too
                detail = str(session.failure or "")
                logger.warning("session %s stopped: %s", session.session_id, detail)
        except WorkcellError as error:  # e.g. non-finite physics
            detail = str(error)
            # the trial stays open in the store: the next writer closes it as
            # interrupted (crash_recovered) with every committed frame intact
        except Exception as error:  # a bug must not take the server down with it
            logger.exception("the simulation thread failed")
            detail = str(error)
        finally:
            results = session.runner.results
            self.listener.ended(
                SessionEnded(
                    session_id=self.session_id,
                    reason=reason,
                    trials=len(results),
                    successes=sum(r.outcome == "success" for r in results),
                    total_score=sum(r.score for r in results),
                    detail=detail,
                    stop_note=self._stop.note if reason == self._stop.reason else "",
                )
            )

    def _forward(self, event: ev.TaskEvent, world: World) -> None:
        """A task event to every client; at a trial's start also the scene, when the
        trial's conditions changed it (box size, target...)."""
        if isinstance(event, ev.ClientFrames):
            return  # the client's own figures, for the record only
        if isinstance(event, ev.Resumed):  # a hand moved while paused does not jump its arm
            self.operator.after_pause()
        if self.scene is not None and isinstance(event, ev.CountdownStarted | ev.TrialStarted):
            scene = describe(world.model, world.data)
            if _shapes(scene) != _shapes(self.scene):
                self.scene = scene
                self.listener.message(encode(scene))
        self.listener.message(encode(event_message(event)))

    def apply_requests(self) -> None:
        """Apply what the clients asked since the last control period now: from the
        simulation thread between two periods (the child's idle, which reads the requests
        there), so an action or a frame report that arrived with a stop is applied before
        the stop ends the trial. While paused they wait for the resume, as ever."""
        session = self._session
        if session is not None and not self._pause.paused:
            self._apply_requests(session)

    def _apply_requests(self, session: RecordedSession) -> None:
        """What the operator's client asked of the runner since the last control period
        (actions, frame reports), in order."""
        while self._requests:  # deque.popleft is atomic: the socket thread appends
            self._requests.popleft()(session.runner)

    def _state_sender(self, session: RecordedSession) -> Callable[[], None]:
        """After each control period: the State to the listener when the period acted on
        a new input (the operator sees its input applied at once), else at ``state_hz``
        on the sim clock; never faster than the control rate."""
        operator = self.operator
        intervening = session.operator
        states = StateBuilder(
            session.runner,
            operator,
            intervening if isinstance(intervening, InterveningOperator) else None,
        )
        dt = session.sim.control_dt
        next_state: float | None = None  # None: the first period's State is due
        shown_input = operator.applied_seq

        def send() -> None:
            nonlocal next_state, shown_input
            now = session.pacing.steps * dt
            if next_state is None:
                next_state = now + self.state_period  # the grid starts here
            elif now >= next_state - dt / 2:
                next_state = max(next_state + self.state_period, now)
            elif operator.applied_seq != shown_input:  # and the next one a period on
                next_state = max(next_state, now + self.state_period)
            else:
                return
            shown_input = operator.applied_seq
            self.listener.state(encode(states.build()))

        return send


def _shapes(scene: Scene) -> tuple[object, ...]:
    """What a client builds from a scene (not where the moving bodies start)."""
    return tuple((b.name, b.geoms, None if b.dynamic else b.pose) for b in scene.bodies)
