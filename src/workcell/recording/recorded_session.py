"""One session run and recorded: its world, operator, runner and recorder, and when it stops.

Every way Workcell runs a session goes through :class:`RecordedSession`: ``workcell
collect`` and its scale-out workers (as fast as the machine goes) and ``workcell serve``'s
live session (paced on the wall clock). The loop is :meth:`SessionRunner.run
<workcell.task.runner.SessionRunner.run>`; this class decides, before each control period,
whether it stops and why:

- the schedule ends it (the mode's trials are done, a challenge campaign is complete) or
  the trial cap does (``max_trials``): the session is ``completed``;
- the recorder failed (a full disk, an I/O error, the writer process dead — noticed
  before the next control period, or at the latest at the next hand-over of frames): the
  running trial ends ``interrupted``/``storage_error``, at the trial time the store closed
  it with;
- a :class:`~workcell.task.pacing.StopRequest` (from any thread, e.g. the operator's stop
  or the server quitting) or the caller's own reason (SIGINT, a closed standard output):
  the running trial ends ``interrupted`` with that reason.

An interrupted last trial makes the session ``interrupted``. An exception out of a control
period leaves the running trial open in the store: the next writer closes it as
``crash_recovered`` with every committed frame intact.

A session is described by a :class:`RecordedSessionConfig`, frozen and picklable, so that a
process can be handed one and run its session there.
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Literal

from workcell.control.simulation import Simulation
from workcell.record.errors import StorageError
from workcell.record.media_paths import media_dir_for
from workcell.recording.drivers import Driver, ExpertDriver
from workcell.recording.media import CameraOptions, MediaRecorder
from workcell.recording.recorder import Recorder, RecordingStore
from workcell.session.config import SessionConfig
from workcell.task import events as ev
from workcell.task.hud import HudPhase
from workcell.task.pacing import Idle, Pacer, PacingStats, PauseRequest, StopRequest
from workcell.task.runner import SessionRunner, TrialResult
from workcell.tasks.registry import load_task

StopReason = Callable[[], ev.InterruptionReason | None]
"""Why the session must stop now (its running trial is interrupted so), or None."""
STOPPED_BY: dict[ev.InterruptionReason, ev.StopBy] = {
    "operator_stop": "operator",
    "admin_stop": "admin",
}
"""The stops someone asked for, recorded with their words as a ``stop_requested`` event."""
PAUSE_POLL_S = 0.1
"""How often a paused loop looks at the recorder's health while it waits."""


@dataclass(frozen=True)
class RealTime:
    """Pace control periods on the wall clock (see :class:`~workcell.task.pacing.Pacer`)."""

    max_catch_up_s: float = 0.25
    """How far behind the wall clock the loop may run steps back to back to catch up."""


@dataclass(frozen=True)
class RecordedSessionConfig:
    """Everything a recorded session needs, resolved: settings, driver, store, stop rules."""

    session: SessionConfig
    """The session's settings, seed and operator id."""
    driver: Driver = field(default_factory=ExpertDriver)
    """Who drives."""
    store: Path | None = None
    """The SQLite store recorded into (created if absent); None: nothing is recorded."""
    writer: Literal["process", "inline"] = "process"
    """Who writes the store: a writer process on another core, or this process."""
    key_file: Path | None = None
    """Sign the store's hash chain with the secret in this file."""
    cameras: CameraOptions | None = None
    """Cameras recorded as videos at the frame rate, beside the store."""
    max_trials: int | None = None
    """Stop after this many trials; None: the mode decides."""
    real_time: RealTime | None = None
    """Pace the loop on the wall clock; None: as fast as possible."""


class RecordedSession:
    """A session: built from its configuration (the world, operator and runner), recording
    while inside :meth:`recording`, run by :meth:`run`. :meth:`open` does both at once."""

    def __init__(
        self,
        config: RecordedSessionConfig,
        stop: StopRequest | None = None,
        pause: PauseRequest | None = None,
        idle: Idle | None = None,
    ) -> None:
        self.config = config
        self.idle = idle
        """How the paced loop waits when it has work to do meanwhile (a live session's
        child serving its pipe, :data:`~workcell.task.pacing.Idle`); None: it sleeps."""
        self.stop = stop if stop is not None else StopRequest()
        """Set from any thread to end the running trial (see :meth:`StopRequest.request`)."""
        self.pause = pause if pause is not None else PauseRequest()
        """Set from any thread to pause the running trial: before its next control period
        the loop stands still (no physics, no trial clock) until it is resumed or stopped,
        recorded as ``paused`` and ``resumed`` events."""
        self.sim = Simulation(config.session.world, load_task(config.session.task.kind).scene())
        self._driving = config.driver.build(config.session, self.sim)
        self.operator = self._driving.operator
        self.runner = SessionRunner(
            config.session, self.sim, self.operator, max_trials=config.max_trials
        )
        self.recorder: Recorder | None = None
        """Records the session while inside :meth:`recording` (None: not recorded)."""
        self.pacing = PacingStats()
        """The real-time loop's counters (all zero when not paced)."""
        self._reported = 0

    @contextlib.contextmanager
    def recording(self) -> Iterator[RecordedSession]:
        """Open the store (unless the session is not recorded) and record the session into
        it; the store is closed on leaving."""
        with _open_store(self.config) as store:
            if store is not None:
                driving = self._driving
                self.recorder = Recorder(
                    store,
                    self.runner,
                    driving.operator_input,
                    media=self._media(),
                    driver=driving.name,
                    intervention=driving.intervention,
                )
            yield self

    @classmethod
    @contextlib.contextmanager
    def open(
        cls, config: RecordedSessionConfig, stop: StopRequest | None = None
    ) -> Iterator[RecordedSession]:
        """Build the session, then record it (:meth:`recording`)."""
        with cls(config, stop).recording() as session:
            yield session

    # --- state ------------------------------------------------------------------------------

    @property
    def session_id(self) -> str:
        """The recorded session's id ("" when nothing is recorded)."""
        return "" if self.recorder is None else self.recorder.session_id

    @property
    def failure(self) -> StorageError | None:
        """Why recording stopped, when it failed."""
        return None if self.recorder is None else self.recorder.failure

    @property
    def frames_written(self) -> int:
        return 0 if self.recorder is None else self.recorder.frames_written

    # --- running ----------------------------------------------------------------------------

    def start(self) -> None:
        """Begin the first trial (:meth:`run` does it when not done yet)."""
        if not self.runner.started:
            self.runner.start()

    def run(
        self,
        should_stop: StopReason | None = None,
        after_step: Callable[[], None] | None = None,
        on_trial: Callable[[TrialResult], None] | None = None,
    ) -> ev.SessionEndReason:
        """Run the session to its end and close it in the store. ``should_stop`` is asked
        before each control period (after the recorder's failure and :attr:`stop`),
        ``after_step`` called after each, ``on_trial`` with each trial's result as it
        ends. Returns why the session ended: ``"completed"`` or the interruption reason."""
        assert self.recorder is not None or self.config.store is None, "not recording yet"
        real_time = self.config.real_time
        pacer = None
        if real_time is not None:
            pacer = Pacer(self.sim.control_dt, real_time.max_catch_up_s, idle=self.idle)
            self.pacing = pacer.stats
        ended: ev.SessionEndReason = "completed"

        def stop_reason() -> ev.InterruptionReason | None:
            nonlocal ended
            reason = self._stop_reason(should_stop)
            if reason is None and self.pause.paused and self.runner.phase is HudPhase.RUNNING:
                self._hold(pacer)
                reason = self._stop_reason(should_stop)
            if reason is None and pacer is not None and not pacer.wait(self.stop):
                reason = self._stop_reason(None)  # requested while the pacer waited
            if reason is not None:
                ended = reason
            if reason in STOPPED_BY:
                by, note = STOPPED_BY[reason], self.stop.note
                self.runner.note(lambda i, t: ev.StopRequested(i, t, by, note))
            if reason == "storage_error" and self.recorder is not None:
                # the trial ends when the store says it did (the runner's own interrupt
                # that follows finds it ended)
                self.runner.interrupt(reason, at=self.recorder.stored_end)
            return reason

        def stepped() -> None:
            if pacer is not None:
                pacer.done()
            if after_step is not None:
                after_step()
            self._report(on_trial)

        self.start()
        self.runner.run(stop_reason, stepped)
        self._report(on_trial)
        if self.recorder is not None:
            self.recorder.close(interrupted=ended != "completed")
            self._report(on_trial)  # the last trials' ends are written now
        return ended

    def _hold(self, pacer: Pacer | None) -> None:
        """Stand paused until resumed, stopped, or the recorder fails; the wall time it
        stood is recorded (``resumed``) and skipped by the pacer."""
        began = time.monotonic()
        self.runner.note(ev.Paused)
        while self.pause.paused and not self.stop.is_set():
            if self.recorder is not None:
                self.recorder.check()
            if self.failure is not None:
                break
            if self.idle is not None:
                self.idle(PAUSE_POLL_S)  # what resumes it arrives through the idle's work
            else:
                self.pause.wait_for_change(PAUSE_POLL_S)
        paused_s = time.monotonic() - began
        self.runner.note(lambda i, t: ev.Resumed(i, t, round(paused_s, 3)))
        if pacer is not None:
            pacer.skip(paused_s)

    def _stop_reason(self, should_stop: StopReason | None) -> ev.InterruptionReason | None:
        if self.recorder is not None:
            self.recorder.check()
        if self.failure is not None:
            return "storage_error"
        if self.stop.is_set():
            return self.stop.reason or "operator_stop"
        return None if should_stop is None else should_stop()

    def _report(self, on_trial: Callable[[TrialResult], None] | None) -> None:
        """Each trial's result once the store has its end (a writer process writes it a
        moment later), in order."""
        self._agree_with_store()
        results = self.runner.results
        recorder = self.recorder
        while self._reported < len(results):
            result = results[self._reported]
            if recorder is not None and not recorder.trial_settled(result.spec.trial_index):
                break
            if on_trial is not None:
                on_trial(result)
            self._reported += 1

    def _agree_with_store(self) -> None:
        """After recording failed, the runner's results say what the store says: the trials
        it closed ended ``interrupted``/``storage_error`` (also one whose success or
        timeout was being written as the failure came), and trials begun after the
        failure, never recorded, are not results."""
        recorder = self.recorder
        if recorder is None or recorder.failure is None:
            return
        lost = recorder.lost_trials
        box_score = self.config.session.task.box_score
        agreed: list[TrialResult] = []
        for position, result in enumerate(self.runner.results):
            stored = result
            index = result.spec.trial_index
            if index in lost and result.interruption_reason != "storage_error":
                stored = replace(
                    result,
                    outcome="interrupted",
                    interruption_reason="storage_error",
                    completion_time_s=None,
                    score=box_score * result.boxes_done,
                )
            if position < recorder.results_at_failure or index in lost:
                agreed.append(stored)
        self.runner.results[:] = agreed

    def _media(self) -> MediaRecorder | None:
        config = self.config
        if config.cameras is None or config.store is None:
            return None
        rate = config.session.recording.sampling_rate_hz
        return MediaRecorder(
            self.sim.world.model, config.cameras, media_dir_for(config.store), rate
        )


@contextlib.contextmanager
def _open_store(config: RecordedSessionConfig) -> Iterator[RecordingStore | None]:
    if config.store is None:
        yield None
        return
    from workcell.record.chain import ChainKey  # noqa: PLC0415
    from workcell.recording.in_process import InProcessStore  # noqa: PLC0415
    from workcell.recording.store_process import StoreProcess  # noqa: PLC0415

    opened: StoreProcess | InProcessStore
    if config.writer == "process":
        opened = StoreProcess.open(config.store, key_file=config.key_file)
    else:
        key = None if config.key_file is None else ChainKey.from_file(config.key_file)
        opened = InProcessStore.open(config.store, writer=True, key=key)
    with opened as store:
        yield store
