"""One session running in real time on its own thread, recorded into the store.

The thread owns everything that is not thread-safe: the store's writer connection, the
simulation, the runner and the recorder. Other threads talk to it only through
:meth:`LiveSession.request_stop` and the operator's latest-input slot, and hear from it
through a :class:`SessionListener` (called on the simulation thread).
"""

from __future__ import annotations

import logging
import threading
from pathlib import Path
from typing import Protocol

from workcell.control.ik import BimanualIK
from workcell.control.simulation import Simulation
from workcell.errors import WorkcellError
from workcell.protocol.codec import encode
from workcell.protocol.messages import Scene, SessionEnded
from workcell.recording.recorder import Recorder
from workcell.recording.store_process import StoreProcess
from workcell.server.pacing import Pacer, PacingStats
from workcell.server.scene import describe
from workcell.server.snapshot import StateBuilder, event_message
from workcell.session.config import SessionConfig
from workcell.sim.world import World
from workcell.task import events as ev
from workcell.task.runner import SessionRunner
from workcell.teleop.clutch import Pose
from workcell.teleop.config import TeleopConfig
from workcell.teleop.operator import TeleopOperator

logger = logging.getLogger(__name__)


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
    ) -> None:
        self.config = config
        self.store_path = store_path
        self.key_file = key_file
        self.listener = listener
        self.state_period = 1.0 / state_hz
        self.max_catch_up_s = max_catch_up_s
        self.operator = TeleopOperator(TeleopConfig.for_session(config), tcp_source=self._tcp)
        self._ik: BimanualIK | None = None
        self.session_id = ""
        self.scene: Scene | None = None
        self.pacing: PacingStats = PacingStats()
        self._stop = threading.Event()
        self._stop_reason: ev.InterruptionReason = "operator_stop"
        self._ready = threading.Event()
        self._startup_error: BaseException | None = None
        self._thread = threading.Thread(target=self._main, name="workcell-sim", daemon=True)

    def start(self) -> None:
        """Open the store, build the world and begin the first trial (blocking)."""
        self._thread.start()
        self._ready.wait()
        if self._startup_error is not None:
            self._thread.join()
            raise self._startup_error

    def request_stop(self, reason: ev.InterruptionReason) -> None:
        """End the running trial as interrupted with ``reason`` (from any thread)."""
        if not self._stop.is_set():
            self._stop_reason = reason
            self._stop.set()

    def join(self, timeout: float | None = None) -> bool:
        self._thread.join(timeout)
        return not self._thread.is_alive()

    @property
    def running(self) -> bool:
        return self._thread.is_alive()

    # --- the simulation thread --------------------------------------------------------------

    def _main(self) -> None:
        try:
            store = StoreProcess.open(self.store_path, key_file=self.key_file)
        except BaseException as error:  # reported to the caller of start()
            self._startup_error = error
            self._ready.set()
            return
        try:
            self._run(store)
        finally:
            store.close()

    def _run(self, store: StoreProcess) -> None:
        try:
            sim = Simulation(self.config.world)
            self._ik = sim.controller.ik
            runner = SessionRunner(self.config, sim, self.operator)
            recorder = Recorder(store, runner, self.operator.operator_input)
        except BaseException as error:
            self._startup_error = error
            self._ready.set()
            return
        self.session_id = recorder.session_id
        runner.bus.subscribe(lambda event: self._forward(event, sim.world))
        runner.start()
        self.scene = describe(sim.world.model, sim.world.data)
        self._ready.set()
        reason = "error: the simulation thread failed"
        try:
            reason = self._loop(runner, recorder)
            if not reason.startswith("error"):
                interrupted = bool(runner.results) and runner.results[-1].outcome == "interrupted"
                recorder.close(interrupted)
            # else the trial stays open in the store: the next writer closes it as
            # interrupted (crash_recovered) with every committed frame intact
        except Exception as error:  # a bug must not take the server down with it
            logger.exception("the simulation thread failed")
            reason = f"error: {error}"
        finally:
            results = runner.results
            self.listener.ended(
                SessionEnded(
                    session_id=self.session_id,
                    reason=reason,
                    trials=len(results),
                    successes=sum(r.outcome == "success" for r in results),
                    total_score=sum(r.score for r in results),
                )
            )

    def _forward(self, event: ev.TaskEvent, world: World) -> None:
        """A task event to every client; at a trial's start also the scene, when the
        trial's conditions changed it (box size, target...)."""
        if self.scene is not None and isinstance(event, ev.CountdownStarted | ev.TrialStarted):
            scene = describe(world.model, world.data)
            if _shapes(scene) != _shapes(self.scene):
                self.scene = scene
                self.listener.message(encode(scene))
        self.listener.message(encode(event_message(event)))

    def _loop(self, runner: SessionRunner, recorder: Recorder) -> str:
        """Step in real time until the session finishes; returns why it ended."""
        pacer = Pacer(runner.sim.control_dt, self.max_catch_up_s)
        self.pacing = pacer.stats
        states = StateBuilder(runner, self.operator)
        dt = runner.sim.control_dt
        next_state = 0.0  # on the sim clock: states at state_hz on average, never faster
        while runner.current is not None:
            if recorder.failure is not None:
                logger.warning("session %s stopped: %s", recorder.session_id, recorder.failure)
                runner.interrupt("storage_error")
                return "storage_error"
            if not pacer.wait(self._stop):
                runner.interrupt(self._stop_reason)
                return self._stop_reason
            try:
                runner.step()
            except WorkcellError as error:  # e.g. non-finite physics
                return f"error: {error}"
            pacer.done()
            now = pacer.stats.steps * dt  # than the control rate
            if now >= next_state - dt / 2:
                next_state = max(next_state + self.state_period, now)
                self.listener.state(encode(states.build()))
        return "completed"

    def _tcp(self, world: World, side: str) -> Pose:
        """The TCP pose the IK configuration is at (base frame): the arm's current target."""
        assert self._ik is not None
        qw, qx, qy, qz, x, y, z = (float(v) for v in self._ik.tcp_pose(side).wxyz_xyz)
        return (x, y, z, qw, qx, qy, qz)


def _shapes(scene: Scene) -> tuple[object, ...]:
    """What a client builds from a scene (not where the moving bodies start)."""
    return tuple((b.name, b.geoms, None if b.dynamic else b.pose) for b in scene.bodies)
