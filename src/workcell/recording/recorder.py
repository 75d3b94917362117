"""The recorder: task events and frames of a running session into the store.

It subscribes to the session runner's events and samples a frame at the configured rate on
the sim clock (exactly: the world calls it at the due physics step), stamping wall time
too. A sample only copies numbers (:mod:`workcell.recording.frame_capture`), with the
task's judgement of that frame instant (the runner judges after the world's step and tells
the recorder, :attr:`SessionRunner.on_judged`); frames are handed to the store in batches
covering at most 0.25 s of sim time (a batch goes once its last frame is judged, or before
the next frame for a frame the runner does not judge), so a killed process loses at most
about that much. Each trial row records its task, named world and goal at its start, and
the judge's last stage and progress at its end. At each trial's end the store computes the
metrics of docs/architecture.md from the frames as stored and closes the trial. A storage failure
stops recording, is kept in :attr:`Recorder.failure`, and the caller interrupts the session
(``storage_error``) at the trial time the store closed the running trial with
(:attr:`Recorder.stored_end`), so that what the operator is told is what the store says. A
failure the store already knows of (its writer process died) is found before each control
period (:meth:`Recorder.check`), not only at the next hand-over of frames.

Recording through a :class:`~workcell.recording.store_process.StoreProcess` (as ``workcell
collect`` and ``workcell serve`` do) leaves formatting, checksums and SQLite to a writer
process on another core.
"""

from __future__ import annotations

import dataclasses
import math
import sqlite3
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Protocol

from workcell.errors import WorkcellError
from workcell.metrics import (
    METRIC_DEFINITIONS,
    METRICS_VERSION,
    MetricThresholds,
)
from workcell.record.entries import SessionInfo, TrialEnd, TrialStart
from workcell.record.errors import StorageError
from workcell.record.store import Store
from workcell.recording.frame_capture import (
    CapturedFrames,
    FrameCapture,
    FrameLayout,
    OperatorInput,
)
from workcell.recording.media import MediaRecorder
from workcell.session.config import SessionConfig
from workcell.task import events as ev
from workcell.task.runner import SessionRunner
from workcell.tasks import CUSTOM, Evaluation, world_of

MAX_UNCOMMITTED_S = 0.25
"""Sim time a commit may lag behind: what a killed process can lose at most."""

InputSource = Callable[[], OperatorInput | None]


class RecordingStore(Protocol):
    """What a recorder writes to: an :class:`~workcell.recording.in_process.InProcessStore`
    opened for writing, or a :class:`~workcell.recording.store_process.StoreProcess`."""

    path: Path

    def create_session(self, info: SessionInfo) -> str: ...

    def start_trial(self, session_id: str, start: TrialStart) -> str: ...

    def add_event(
        self,
        session_id: str,
        kind: str,
        payload: Mapping[str, object] | None = None,
        *,
        trial_id: str | None = None,
        t_sim: float | None = None,
        t_wall: float | None = None,
    ) -> object: ...

    def prepare_frames(self, layout: FrameLayout) -> None: ...

    def add_captured_frames(self, trial_id: str, frames: CapturedFrames) -> int: ...

    def commit(self) -> None: ...

    def failure_pending(self) -> bool: ...

    def end_trial(
        self, trial_id: str, end: TrialEnd, *, thresholds: MetricThresholds | None = None
    ) -> None: ...

    def end_session(self, session_id: str, status: str = "completed") -> None: ...

    def trial_end_written(self, trial_id: str) -> bool: ...

    def try_interrupt_session(self, session_id: str, reason: str = "storage_error") -> bool: ...


def metric_thresholds(config: SessionConfig) -> MetricThresholds:
    recording = config.recording
    return MetricThresholds(
        **{f.name: getattr(recording, f.name) for f in dataclasses.fields(MetricThresholds)}
    )


def session_info(config: SessionConfig) -> SessionInfo:
    """Everything a session row stores about its configuration."""
    return SessionInfo(
        mode=config.task.mode,
        operator_id=config.operator_id,
        seed=config.seed,
        parameters=dataclasses.asdict(config),
        thresholds=dataclasses.asdict(metric_thresholds(config)),
        metric_definitions=dict(METRIC_DEFINITIONS),
        metrics_version=METRICS_VERSION,
    )


class Recorder:
    """Records one session of ``runner`` into ``store`` (opened as the writer)."""

    def __init__(
        self,
        store: RecordingStore,
        runner: SessionRunner,
        operator_input: InputSource | None = None,
        media: MediaRecorder | None = None,
        *,
        driver: str = "person",
        intervention: Callable[[], bool] | None = None,
    ) -> None:
        """``driver``: who drives, as each trial records it; ``intervention``: whether a
        person who took over from it drives now (None: never)."""
        self.store = store
        self.driver = driver
        self._intervention = intervention
        self.runner = runner
        self.config = runner.config
        self.thresholds = metric_thresholds(self.config)
        self._input = operator_input
        self.media = media
        self.session_id = store.create_session(session_info(self.config))
        self.failure: StorageError | None = None
        self.lost_trials: frozenset[int] = frozenset()
        """After recording failed: the indices of the trials the store closed
        ``interrupted``/``storage_error`` (the one running, and any whose end had not been
        written yet)."""
        self.results_at_failure = 0
        """How many trial results the runner had when recording failed."""
        self.stored_end: float | None = None
        """After recording failed: the trial time the store closed the running trial at
        (its last frame or event), None when no trial was running or the store could not
        close it."""
        self.frames_written = 0
        self._steps_per_frame = self.config.physics_steps_per_frame
        rate = self.config.recording.sampling_rate_hz
        self._frames_per_commit = max(1, math.floor(MAX_UNCOMMITTED_S * rate + 1e-9))
        self._trial_id: str | None = None
        self._trial_index: int | None = None
        self._ending: dict[int, str] = {}
        """Trials whose end was handed to the store, by index, until it is written."""
        self._pending_events: list[ev.TaskEvent] = []
        self._capture = FrameCapture(
            runner.sim.world, runner.sim.controller, self._frames_per_commit, runner.task.stages
        )
        self._stage_index = {stage: i for i, stage in enumerate(runner.task.stages)}
        self._sampled_step = -1
        """The physics step of the latest frame captured."""
        store.prepare_frames(self._capture.layout)  # not while the first trial runs
        self.next_step = -1
        self._unsubscribe = runner.bus.subscribe(self._on_event)
        runner.on_judged.append(self._judged)

    # --- the world's sampler ----------------------------------------------------------------

    def sample(self) -> None:
        """Take the frame due now (called by the world at exact physics steps), with the
        task's judgement as the runner has it; a frame the runner judges at its instant
        (after the world's step: :meth:`_judged`) takes that judgement instead. A full
        buffer is handed to the store once its last frame is judged, or before the next
        frame at the latest."""
        runner = self.runner
        capture = self._capture
        source = self._input
        if capture.full:
            self._flush_or_fail()
        capture.capture(
            runner.last_command,
            None if source is None else source(),  # None: a command-only operator
            t_sim=runner.trial_time,
            step_wall_ms=runner.last_step_wall_s * 1000.0,
            stage=self._stage_index.get(runner.stage, -1),
            progress=runner.progress,
            intervention=float(self._intervention is not None and self._intervention()),
        )
        self._sampled_step = runner.sim.world.physics_steps
        if self.media is not None:
            self.media.frame(runner.sim.world.data)
        self.next_step += self._steps_per_frame

    def _judged(self, evaluation: Evaluation) -> None:
        """The runner judged the trial at a frame instant: the frame of that instant keeps
        its word."""
        if self._trial_id is None or self.failure is not None:
            return
        if self._sampled_step != self.runner.sim.world.physics_steps:
            return  # no frame of this instant (not sampled at it)
        self._capture.judged(self._stage_index.get(evaluation.stage, -1), self.runner.progress)
        if self._capture.full:
            self._flush_or_fail()

    def _flush_or_fail(self) -> None:
        try:
            self._flush()
        except StorageError as error:
            self._fail(error)

    def check(self) -> None:
        """Stop recording now if the store already knows it cannot write (its writer
        process died, a write sent earlier failed), rather than at the next hand-over of
        frames; asked before each control period, it costs no system call."""
        if self.failure is not None or not self.store.failure_pending():
            return
        try:
            self.store.commit()
        except StorageError as error:
            self._fail(error)

    # --- events -----------------------------------------------------------------------------

    def _on_event(self, event: ev.TaskEvent) -> None:
        if self.failure is not None:
            return
        try:
            if isinstance(event, ev.TrialStarted):
                self._start_trial(event)
            elif isinstance(event, ev.LevelChanged):
                self._add_event(event, session_level=True)  # between two trials' clocks
            elif isinstance(event, ev.StopRequested) and self._trial_id is None:
                # stopped during a countdown: its trial never starts, the stop is the session's
                self._add_event(event, session_level=True)
            elif self._trial_id is None:
                self._pending_events.append(event)  # countdown: the trial row comes next
            else:
                self._add_event(event)
            if isinstance(event, ev.TrialEnded):
                self._end_trial(event)
        except StorageError as error:
            self._fail(error)

    def _start_trial(self, event: ev.TrialStarted) -> None:
        task = self.runner.task
        named = world_of(task.worlds, self.config.world.randomization)
        goal = task.goal(event.conditions, self.config.world)
        start = TrialStart(
            mode=event.mode,
            required_boxes=event.required_boxes,
            time_limit_s=event.time_limit_s,
            round=event.round,
            level=event.level,
            trial_seed=event.trial_seed,
            task=self.config.task.kind,
            world=None if named == CUSTOM else named,
            goal=dict(zip(task.goal_names, goal, strict=True)),
            driver=self.driver,
        )
        self._trial_id = self.store.start_trial(self.session_id, start)
        self._trial_index = event.trial_index
        if self.media is not None:
            self.media.start(self._trial_id)
        for pending in self._pending_events:
            self._add_event(pending)
        self._pending_events.clear()
        self._add_event(event)
        self._capture.take()  # nothing left of an earlier trial
        world = self.runner.sim.world
        self.next_step = world.physics_steps
        world.sampler = self
        self.sample()  # the frame at t_sim = 0

    def _add_event(self, event: ev.TaskEvent, session_level: bool = False) -> None:
        self.store.add_event(
            self.session_id,
            ev.event_kind(event),
            ev.event_payload(event),
            trial_id=None if session_level else self._trial_id,
            t_sim=event.t_sim,
        )

    def _end_trial(self, event: ev.TrialEnded) -> None:
        trial_id = self._trial_id
        if trial_id is None:  # interrupted during the countdown: nothing was started
            self._pending_events.clear()
            return
        self.runner.sim.world.sampler = None
        self._flush()
        if self.media is not None:
            self.store.add_event(
                self.session_id, "media", self.media.end(), trial_id=trial_id, t_sim=event.t_sim
            )
        self.store.end_trial(
            trial_id,
            TrialEnd(
                outcome=event.outcome,
                interruption_reason=event.interruption_reason,
                elapsed_s=event.elapsed_s,
                completion_time_s=event.elapsed_s if event.outcome == "success" else None,
                boxes_delivered=event.boxes_delivered,
                score=event.score,
                stage=self.runner.stage,
                progress=self.runner.progress,
            ),
            thresholds=self.thresholds,  # metrics from the frames as stored
        )
        self.store.commit()
        if self._trial_index is not None:
            self._ending[self._trial_index] = trial_id
        self._trial_id = None
        self._trial_index = None

    def trial_settled(self, trial_index: int) -> bool:
        """Whether the store has the trial's end written (or never had the trial, or
        recording failed: then :attr:`lost_trials` says how the store closed it)."""
        trial_id = self._ending.get(trial_index)
        if trial_id is None or self.failure is not None:
            return True
        if not self.store.trial_end_written(trial_id):
            return False
        del self._ending[trial_index]
        return True

    def _flush(self) -> None:
        if self._trial_id is None or not len(self._capture):
            return
        frames = self._capture.take()
        self.frames_written += self.store.add_captured_frames(self._trial_id, frames)
        self.store.commit()

    def _fail(self, error: StorageError) -> None:
        """Stop recording and close the session as ``storage_error`` (its running trial
        ``interrupted``), as far as the store can still write."""
        self.failure = error
        self.results_at_failure = len(self.runner.results)
        self.runner.sim.world.sampler = None
        self._capture.take()
        running = None if self._trial_id is None else self._trial_index
        running_id = self._trial_id
        self._trial_id = None
        self._trial_index = None
        closed = self.store.try_interrupt_session(self.session_id, "storage_error")
        if closed and running_id is not None:
            self.stored_end = self._elapsed_in_store(running_id)
        # answered after every call before it: the ends written are known now
        unwritten = {i for i, t in self._ending.items() if not self.store.trial_end_written(t)}
        self.lost_trials = frozenset(unwritten | ({running} if running is not None else set()))

    def _elapsed_in_store(self, trial_id: str) -> float | None:
        """The elapsed time the store has for ``trial_id`` (read by a reader of its own:
        the writer may be gone)."""
        try:
            with Store.open(self.store.path, writer=False) as reader:
                trials = reader.trials(self.session_id)
        except (WorkcellError, sqlite3.Error, OSError):  # then the runner's own time
            return None
        return next((t.elapsed_s for t in trials if t.trial_id == trial_id), None)

    # --- the end ----------------------------------------------------------------------------

    def close(self, interrupted: bool) -> None:
        """Close the session (its trials have ended) and stop listening."""
        self._unsubscribe()
        if self._judged in self.runner.on_judged:
            self.runner.on_judged.remove(self._judged)
        if self.media is not None:
            self.media.close()
        if self.failure is not None:
            return
        try:
            self.store.end_session(self.session_id, "interrupted" if interrupted else "completed")
        except StorageError as error:
            self._fail(error)
