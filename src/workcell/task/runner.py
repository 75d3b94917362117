"""The task state machine: runs the trials of a session, one control step at a time.

Each trial: reset (the world from a seed derived from the session seed and the trial
index), countdown, running, then success, failed (its task's judge says it can no longer
succeed), timeout or interrupted. The trial clock is the
sim clock counted in physics steps from the end of the countdown, so limits are exact.
Every transition is published as a typed event on the bus (the recorder and the HUD
subscribe). The runner is step-driven; :meth:`SessionRunner.run` is the one session loop,
which a :class:`~workcell.recording.recorded_session.RecordedSession` drives headless at
full speed or paced on the wall clock for a live operator.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from workcell.control.command import Command
from workcell.control.simulation import Simulation
from workcell.errors import SimulationError
from workcell.session.config import SessionConfig
from workcell.sim import events as world_events
from workcell.task import events as ev
from workcell.task.bus import EventBus
from workcell.task.hud import Hud, HudPhase
from workcell.task.operator import Operator
from workcell.task.schedule import Schedule, TrialSpec
from workcell.task.scoring import time_bonus, trial_score
from workcell.tasks import Evaluation, Task, TrialJudge
from workcell.tasks.registry import load_task


@dataclass(frozen=True)
class TrialResult:
    spec: TrialSpec
    trial_seed: int
    outcome: ev.Outcome
    interruption_reason: ev.InterruptionReason | None
    elapsed_s: float
    completion_time_s: float | None
    boxes_done: int
    """The boxes its task counted as done (the contract's ``boxes_delivered``)."""
    score: int
    stage: str
    """The furthest of the task's stages the trial reached (its judge's last word)."""
    progress: float = 0.0
    """The task's progress (0..1) as its judge said last."""


def trial_seed(session_seed: int, trial_index: int) -> int:
    """The world seed of one trial: reproducible from the session seed and the index."""
    state = np.random.SeedSequence([session_seed, trial_index]).generate_state(1, np.uint64)
    return int(state[0] >> np.uint64(1))


class SessionRunner:
    def __init__(
        self,
        config: SessionConfig,
        sim: Simulation,
        operator: Operator,
        bus: EventBus | None = None,
        max_trials: int | None = None,
    ) -> None:
        self.config = config
        self.sim = sim
        self.operator = operator
        self.task: Task = load_task(config.task.kind)
        """The task every trial of the session runs (``task.kind``): it judges success."""
        scene = sim.world.scene
        if scene is None or scene.task_name != self.task.name:
            built = "no task's scene" if scene is None else f"the scene of {scene.task_name}"
            raise SimulationError(
                f"the simulation was built with {built}, but the session runs "
                f"{self.task.name}: build it with the task's, Simulation(world, task.scene())"
            )
        self.bus = bus or EventBus()
        self.max_trials = max_trials
        self.schedule = Schedule(config.task)
        self.results: list[TrialResult] = []
        self.capped = False
        """True when ``max_trials`` ended the session before the schedule did."""
        self._countdown_steps = round(config.task.countdown_s / sim.control_dt)
        self._steps_per_frame = config.physics_steps_per_frame
        self.last_command = Command()
        """The command of the latest control period (what the recorder stores as action)."""
        self.last_step_wall_s = 0.0
        """Wall time the latest control period took to compute and simulate."""
        self._spec: TrialSpec | None = None
        self._seed = 0
        self._conditions: dict[str, object] = {}
        self._instruction = ""
        """What the current trial asks (:attr:`Hud.instruction`)."""
        self._start_step = 0
        self._judge: TrialJudge = self.task.new_trial(1)
        self._stage = self.task.stages[0]
        self._progress = 0.0
        self.phase = HudPhase.FINISHED
        self.on_judged: list[Callable[[Evaluation], None]] = []
        """Called with the judge's word at each frame instant it judges the trial, before
        the trial may end on it (the recorder keeps it with the frame of that instant)."""

    # --- driving ----------------------------------------------------------------------------

    def start(self, first: TrialSpec | None = None, world_seed: int | None = None) -> None:
        """Begin the first trial: the schedule's, or ``first``; its world is reset with
        ``world_seed`` when given (one episode of the environment, the expert's episode
        helper), else with the seed derived from the session seed and the trial index."""
        self._begin(first or self.schedule.first(), world_seed)

    def run(
        self,
        should_stop: Callable[[], ev.InterruptionReason | None] | None = None,
        after_step: Callable[[], None] | None = None,
    ) -> list[TrialResult]:
        """Run to the end (beginning the first trial unless :meth:`start` did): before each
        control period ``should_stop`` may return a reason, which interrupts the session
        (it may also wait, to pace the loop); ``after_step`` follows each period."""
        if not self.started:
            self.start()
        while self.phase is not HudPhase.FINISHED:
            reason = should_stop() if should_stop is not None else None
            if reason is not None:
                self.interrupt(reason)
                break
            self.step()
            if after_step is not None:
                after_step()
        return self.results

    def step(self) -> None:
        """One control period."""
        if self.phase is HudPhase.FINISHED:
            return
        running = self.phase is HudPhase.RUNNING
        started = time.perf_counter()
        command = self.operator.act(self.sim.world) if running else Command()
        self.last_command = command
        world_events_now = self.sim.step(command)
        self.last_step_wall_s = time.perf_counter() - started
        for event in world_events_now:
            self._publish_world_event(event)
        if self.phase is HudPhase.COUNTDOWN and self.sim.world.physics_steps >= self._start_step:
            self._go()
        elif running:
            self._check_end()

    def interrupt(self, reason: ev.InterruptionReason, at: float | None = None) -> None:
        """End the current trial as interrupted and finish the session; ``at``: the trial
        time it ended at when not now (after recording failed: the last the store holds).
        A trial still counting down never started: it ends with no result and no event, as
        the store never holds a row of it."""
        if self.phase in (HudPhase.FINISHED, HudPhase.COUNTDOWN) or self._spec is None:
            self.phase = HudPhase.FINISHED
            return
        t = self.trial_time if at is None else at
        self.bus.publish(ev.TrialInterrupted(self._spec.trial_index, t, reason))
        self._end("interrupted", reason, max(t, 0.0))

    def act_on(self, action: ev.OperatorAction, source: ev.ActionSource) -> None:
        """Record an operator's action; ``restart_trial`` ends a running trial as
        interrupted, ``operator_restart``, and begins a new trial of the same kind (the next
        trial index, its own seed). During a countdown nothing is under way to restart."""
        if self.phase is HudPhase.FINISHED or self._spec is None:
            return
        spec = self._spec
        t = self.trial_time
        self.bus.publish(ev.OperatorActed(spec.trial_index, t, action, source))
        if action != "restart_trial" or self.phase is not HudPhase.RUNNING:
            return
        self.bus.publish(ev.TrialInterrupted(spec.trial_index, t, "operator_restart"))
        self._finish("interrupted", "operator_restart", max(t, 0.0))
        self._begin(replace(spec, trial_index=spec.trial_index + 1))

    def note(self, event: Callable[[int, float], ev.TaskEvent]) -> None:
        """Publish ``event(trial_index, t_sim)``, stamped with the trial under way (or
        counting down), e.g. how the operator's browser draws; nothing once finished."""
        if self.phase is HudPhase.FINISHED or self._spec is None:
            return
        self.bus.publish(event(self._spec.trial_index, self.trial_time))

    # --- state ------------------------------------------------------------------------------

    @property
    def trial_time(self) -> float:
        """Seconds on the trial clock; negative during the countdown."""
        steps = self.sim.world.physics_steps - self._start_step
        return steps * self.config.world.timestep

    @property
    def started(self) -> bool:
        """Whether the first trial has begun."""
        return self._spec is not None

    @property
    def campaign_complete(self) -> bool:
        """A challenge session whose last trial completed the campaign (see
        :meth:`Schedule.completes`)."""
        last = self.results[-1] if self.results else None
        return last is not None and self.schedule.completes(last.spec, last.outcome)

    @property
    def stage(self) -> str:
        """The furthest of the task's stages the current (or last) trial reached, as its
        judge said at the latest frame instant."""
        return self._stage

    @property
    def progress(self) -> float:
        """The task's progress (0..1) in the current (or last) trial, as its judge said at
        the latest frame instant."""
        return self._progress

    @property
    def judge(self) -> TrialJudge:
        """The task's judge of the current (or last) trial."""
        return self._judge

    @property
    def current(self) -> TrialSpec | None:
        return self._spec if self.phase is not HudPhase.FINISHED else None

    @property
    def trial_start_step(self) -> int:
        """The physics step count at which the current trial's clock started (or starts)."""
        return self._start_step

    def hud(self) -> Hud:
        spec = self._spec
        t = self.trial_time
        limit = spec.time_limit_s if spec else 0.0
        boxes = self._judge.done
        return Hud(
            phase=self.phase,
            mode=self.config.task.mode,
            trial_index=spec.trial_index if spec else 0,
            round=spec.round if spec else None,
            rounds=self.config.task.rounds if self.config.task.mode == "challenge" else None,
            level=spec.level if spec else None,
            boxes_delivered=boxes,
            required_boxes=spec.required_boxes if spec else 0,
            countdown_s=max(0.0, -t) if self.phase is HudPhase.COUNTDOWN else 0.0,
            remaining_s=max(0.0, limit - max(t, 0.0)),
            score=self.config.task.box_score * boxes if self.phase is HudPhase.RUNNING else 0,
            task=self.task.name,
            stage=self._stage,
            time_bonus=time_bonus(limit, max(t, 0.0)) if self.phase is HudPhase.RUNNING else 0,
            instruction=self._instruction,
        )

    def _as_task_asks(self, spec: TrialSpec) -> TrialSpec:
        """``spec`` with the task's own count of objects and its least time limit
        (:attr:`Task.objects_per_trial`, :attr:`Task.least_time_limit_s`)."""
        task = self.task
        required = spec.required_boxes if task.objects_per_trial is None else task.objects_per_trial
        limit = max(spec.time_limit_s, task.least_time_limit_s)
        if (required, limit) == (spec.required_boxes, spec.time_limit_s):
            return spec
        return replace(spec, required_boxes=required, time_limit_s=limit)

    # --- transitions ------------------------------------------------------------------------

    def _begin(self, spec: TrialSpec, world_seed: int | None = None) -> None:
        spec = self._as_task_asks(spec)
        self._spec = spec
        self._seed = (
            trial_seed(self.config.seed, spec.trial_index) if world_seed is None else world_seed
        )
        self._judge = self.task.new_trial(spec.required_boxes)
        self._stage = self.task.stages[0]
        self._progress = 0.0
        self._conditions = self.sim.reset(self._seed).as_dict()
        self._instruction = self.task.trial_instruction(spec.required_boxes, self._conditions)
        self.operator.start_trial(self._seed)
        self._start_step = self._countdown_steps * self.sim.world.substeps
        if self._countdown_steps:
            self.phase = HudPhase.COUNTDOWN
            self.bus.publish(
                ev.CountdownStarted(spec.trial_index, self.trial_time, self.config.task.countdown_s)
            )
        else:
            self._go()

    def _go(self) -> None:
        spec = self._spec
        assert spec is not None
        self.phase = HudPhase.RUNNING
        self.bus.publish(
            ev.TrialStarted(
                trial_index=spec.trial_index,
                t_sim=0.0,
                mode=spec.mode,
                round=spec.round,
                level=spec.level,
                required_boxes=spec.required_boxes,
                time_limit_s=spec.time_limit_s,
                trial_seed=self._seed,
                conditions=self._conditions,
            )
        )

    def _check_end(self) -> None:
        """Success, failure or timeout, decided on the frame clock: a trial ends at the
        first frame instant at or after its deciding moment, so its last frame is its end.
        The task judges success and failure (:meth:`workcell.tasks.TrialJudge.evaluate`);
        a trial its judge says can no longer succeed ends ``failed`` at once."""
        spec = self._spec
        assert spec is not None
        if (self.sim.world.physics_steps - self._start_step) % self._steps_per_frame:
            return
        t = self.trial_time
        evaluation = self._judge.evaluate(self.sim.world)
        if evaluation.stage not in self.task.stages:
            raise SimulationError(
                f"the judge of task {self.task.name} says stage {evaluation.stage!r}, which is "
                f"not one of its stages {self.task.stages} (Task.stages)"
            )
        self._stage = evaluation.stage
        self._progress = min(1.0, max(0.0, float(evaluation.progress)))
        for listener in self.on_judged:
            listener(evaluation)
        if evaluation.success:
            self._end("success", None, t)
        elif evaluation.failure:
            self._end("failed", None, t)
        elif t >= spec.time_limit_s - 1e-9:
            self.bus.publish(ev.TrialTimedOut(spec.trial_index, t))
            self._end("timeout", None, t)

    def _end(self, outcome: ev.Outcome, reason: ev.InterruptionReason | None, t: float) -> None:
        spec = self._finish(outcome, reason, t)
        following = self.schedule.next(spec, outcome)
        capped = self.max_trials is not None and len(self.results) >= self.max_trials
        if following is not None and capped:
            self.capped = True
            following = None
        if following is None:
            self.phase = HudPhase.FINISHED
            return
        if following.level is not None and following.round is not None:
            repeat = (following.round, following.level) == (spec.round, spec.level)
            self.bus.publish(
                ev.LevelChanged(spec.trial_index, t, following.round, following.level, repeat)
            )
        self._begin(following)

    def _finish(
        self, outcome: ev.Outcome, reason: ev.InterruptionReason | None, t: float
    ) -> TrialSpec:
        """Score the trial under way, keep its result and announce its end."""
        spec = self._spec
        assert spec is not None
        box_score = self.config.task.box_score
        limit = spec.time_limit_s
        done = self._judge.done
        score = trial_score(box_score, done, limit, t) if outcome == "success" else box_score * done
        result = TrialResult(
            spec=spec,
            trial_seed=self._seed,
            outcome=outcome,
            interruption_reason=reason,
            elapsed_s=t,
            completion_time_s=t if outcome == "success" else None,
            boxes_done=done,
            score=score,
            stage=self._stage,
            progress=self._progress,
        )
        self.results.append(result)
        self.bus.publish(ev.TrialEnded(spec.trial_index, t, outcome, reason, t, done, score))
        return spec

    def _publish_world_event(self, event: world_events.WorldEvent) -> None:
        spec = self._spec
        assert spec is not None
        running = self.phase is HudPhase.RUNNING
        if isinstance(event, world_events.BoxCompleted) and not running:
            return
        if running:
            self._judge.observe(event)
        self.bus.publish(ev.stamped(event, spec.trial_index, self.trial_time, self._judge.done))
