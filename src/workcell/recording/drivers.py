"""Who drives a recorded session, as frozen, picklable values.

A :class:`~workcell.recording.recorded_session.RecordedSessionConfig` names its driver:
the scripted expert (:class:`ExpertDriver`), a learned policy (:class:`PolicyDriver`),
a human at a browser (:class:`TeleopDriver`) or recorded trials replayed in new worlds
(:class:`GeneratedDriver`). The session builds the operator from it in
whichever process runs the simulation, together with the source of the raw device input
the recorder stores beside each frame (None for an operator that only gives commands).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Protocol

from workcell.expert.skill import ExpertConfig

if TYPE_CHECKING:
    from workcell.control.simulation import Simulation
    from workcell.generate.plan import GenerationPlan
    from workcell.learn.checkpoint import PolicyCheckpoint
    from workcell.recording.recorder import InputSource
    from workcell.session.config import SessionConfig
    from workcell.sim.world import World
    from workcell.task.operator import Operator
    from workcell.teleop.clutch import Pose


@dataclass(frozen=True)
class Driving:
    """A built driver: the operator, where its raw device input comes from, the driver's
    name as trials record it (``person``, ``expert``, ``policy:<id>``, ``generated``) and,
    for a session a person may take over, whether the person drives now."""

    operator: Operator
    operator_input: InputSource | None = None
    name: str = "person"
    intervention: Callable[[], bool] | None = None


@dataclass(frozen=True)
class ExpertDriver:
    """The session task's scripted expert at ``expert``'s skill (:meth:`Task.expert`)."""

    expert: ExpertConfig = field(default_factory=ExpertConfig)

    def build(self, config: SessionConfig, sim: Simulation) -> Driving:
        from workcell.tasks.registry import load_task  # noqa: PLC0415

        operator: Operator = load_task(config.task.kind).expert(self.expert)
        if self.expert.base_noise > 0:
            from workcell.expert.noise import NoisyBase  # noqa: PLC0415

            operator = NoisyBase(operator, self.expert.base_noise)
        return Driving(operator, name="expert")


@dataclass(frozen=True)
class PolicyDriver:
    """The learned policy of ``checkpoint`` (needs the learn extra)."""

    checkpoint: PolicyCheckpoint
    verbose: bool = False
    """Show what torch and LeRobot print while the policy loads."""

    def build(self, config: SessionConfig, sim: Simulation) -> Driving:
        from workcell.learn.policy_operator import PolicyOperator  # noqa: PLC0415

        operator = PolicyOperator(self.checkpoint, config, sim, verbose=self.verbose)
        return Driving(operator, name=f"policy:{self.checkpoint.operator_id}")


@dataclass(frozen=True)
class TeleopDriver:
    """A teleoperator whose inputs are submitted to the built
    :class:`~workcell.teleop.operator.TeleopOperator` (from any thread)."""

    def build(self, config: SessionConfig, sim: Simulation) -> Driving:
        from workcell.teleop.config import TeleopConfig  # noqa: PLC0415
        from workcell.teleop.operator import TeleopOperator  # noqa: PLC0415
        from workcell.teleop.soft_stop import SoftStop  # noqa: PLC0415

        ik = sim.controller.ik
        sim.controller.solve_held_arms = False  # a released clutch: no solve (issue 38)

        def tcp_target(world: World, side: str) -> Pose:
            """The TCP pose the IK configuration is at (base frame): the arm's current
            target, where a clutch engaging takes over."""
            qw, qx, qy, qz, x, y, z = (float(v) for v in ik.tcp_pose(side).wxyz_xyz)
            return (x, y, z, qw, qx, qy, qz)

        def reference_heading(world: World) -> tuple[float, float]:
            """The heading the base is asked to be at, and its rate: what a snap steers."""
            return float(sim.controller.base.pose[2]), float(sim.controller.base.twist[2])

        operator = TeleopOperator(
            TeleopConfig.for_session(config),
            tcp_source=tcp_target,
            soft_stop=SoftStop(sim.world.model, config.world.robot),
            heading_source=reference_heading,
        )
        return Driving(operator, operator.operator_input)


@dataclass(frozen=True)
class GeneratedDriver:
    """Source trials replayed into each trial's world (``workcell generate``,
    :class:`~workcell.generate.operator.GeneratedOperator`); never the task's expert."""

    plan: GenerationPlan

    def build(self, config: SessionConfig, sim: Simulation) -> Driving:
        from workcell.generate.operator import GeneratedOperator  # noqa: PLC0415

        return Driving(GeneratedOperator(self.plan), name="generated")


class Autonomous(Protocol):
    """A driver whose operator can go on from a state someone else left
    (:class:`~workcell.intervene.operator.Resumable`): the expert, a policy."""

    def build(self, config: SessionConfig, sim: Simulation) -> Driving: ...


@dataclass(frozen=True)
class InterveningDriver:
    """``autonomous`` drives while a person at a browser watches and may take over and
    hand back (:class:`~workcell.intervene.operator.InterveningOperator`); the recorded
    device input is the person's while they drive. With a ``corrector`` (the task's expert)
    no person is at a browser: the corrector takes over instead, when a
    :class:`~workcell.intervene.corrector.ScriptedCorrector` watching the session says so."""

    autonomous: Autonomous
    corrector: ExpertDriver | None = None

    def build(self, config: SessionConfig, sim: Simulation) -> Driving:
        from workcell.intervene.operator import InterveningOperator, Resumable  # noqa: PLC0415
        from workcell.teleop.operator import TeleopOperator  # noqa: PLC0415

        person: TeleopOperator | Resumable
        if self.corrector is None:
            teleop = TeleopDriver().build(config, sim).operator
            assert isinstance(teleop, TeleopOperator)
            person = teleop
        else:
            person = self.corrector.build(config, sim).operator  # type: ignore[assignment]
        sim.controller.solve_held_arms = True  # the driver's arms are solved every period
        driving = self.autonomous.build(config, sim)
        operator = InterveningOperator(
            driving.operator,  # type: ignore[arg-type]  # expert and policy can resume
            person,
            driving.name,
        )
        return Driving(operator, operator.operator_input, driving.name, operator.intervention)


Driver = ExpertDriver | PolicyDriver | TeleopDriver | GeneratedDriver | InterveningDriver
