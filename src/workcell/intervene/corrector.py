"""A scripted corrector: the task's expert stands in for the person who watches a driver
and takes over (issue 35, ``bench/intervene.py``), headless.

After each control period :meth:`ScriptedCorrector.after_step` looks at the trial:

- **take over** when the trial's stage (its judge's furthest stage, ``runner.stage``) has
  not advanced for ``stall_s`` (:class:`~workcell.intervene.rules.CorrectorRules`, 8 s by
  default) while the driver drives (reason ``stalled 8 s at touched``), or when the box
  **drifts from its course**: the trial's stage is ``grasped`` or ``lifted`` (a box was
  picked up but never carried over its goal) and no box has been held for ``drop_s``
  (0.5 s; reason ``dropped the box at lifted``);
- drive with the expert, resumed from the world as the driver left it
  (:meth:`~workcell.tasks.elements.expert.ExpertOperator.resume`), until the trial's stage
  is past the one it took over at;
- **hand back** then (reason ``reached grasped``): the driver goes on from there.

Both switches go through :func:`workcell.intervene.switch.switch`, so the record is that
of a live correction: ``take_over``/``hand_back`` events naming the corrector and the
driver, ``frames.intervention`` 1 while the expert drives, ``trials.driver`` the driver's.
A trial that ends while the expert drives records no hand-back (as a live one would not).
"""

from __future__ import annotations

from workcell.intervene.operator import InterveningOperator, Resumable
from workcell.intervene.rules import DROP_STAGES, CorrectorRules
from workcell.intervene.switch import switch
from workcell.task.hud import HudPhase
from workcell.task.runner import SessionRunner


class ScriptedCorrector:
    """Watches ``runner``'s trials, driven by ``operator`` (whose person is the stand-in),
    and switches control by :class:`CorrectorRules`; call :meth:`after_step` after each
    control period."""

    def __init__(
        self, operator: InterveningOperator[Resumable], runner: SessionRunner, rules: CorrectorRules
    ) -> None:
        self.operator = operator
        self.runner = runner
        self.rules = rules
        self._trial: int | None = None
        self._stage = ""
        self._since = 0.0
        """Trial time since which the stage has not advanced (or the driver drove again)."""
        self._held_at = 0.0
        """Trial time a box was last held."""
        self._taken_at_stage = ""
        self.take_overs = 0

    def after_step(self) -> None:
        runner = self.runner
        current = runner.current
        if current is None or runner.phase is not HudPhase.RUNNING:
            return
        t = runner.trial_time
        stage = runner.stage
        if current.trial_index != self._trial:
            self._trial, self._stage, self._since, self._held_at = current.trial_index, stage, t, t
        if runner.sim.world.grasp.holding is not None:
            self._held_at = t
        advanced = stage != self._stage
        if advanced:
            self._stage, self._since = stage, t
        operator = self.operator
        if operator.person_drives:
            if advanced and self._past(stage, self._taken_at_stage):
                self._switch(False, f"reached {stage}")
                self._since = self._held_at = t
            return
        if t - self._since >= self.rules.stall_s:
            self._take_over(stage, f"stalled {self.rules.stall_s:g} s at {stage}")
        elif stage in DROP_STAGES and t - self._held_at >= self.rules.drop_s:
            self._take_over(stage, f"dropped the box at {stage}")

    def _past(self, stage: str, than: str) -> bool:
        stages = self.runner.task.stages
        return stages.index(stage) > stages.index(than)

    def _take_over(self, stage: str, reason: str) -> None:
        if self._switch(True, reason):
            self._taken_at_stage = stage
            self.take_overs += 1

    def _switch(self, person: bool, reason: str) -> bool:
        return switch(self.operator, self.runner, person, self.rules.operator_id, reason)
