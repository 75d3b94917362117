"""What a task is: everything one kind of trial asks of the robot, declared in one class.

A task (docs/tasks.md) names itself, says in words what a trial asks
(:meth:`Task.instruction`) and as numbers a policy observes (:meth:`Task.goal`), lists its
stages in order, offers three worlds from narrow to broad
(:data:`~workcell.tasks.worlds.WORLDS`), judges a trial as it runs
(:meth:`Task.new_trial` and :meth:`TrialJudge.evaluate`) and brings its expert. The
session runner, the environment and the expert's episode helper all ask the task whether a
trial succeeded: the success rule is written once, in the task.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar, Literal, Protocol

from workcell.tasks.worlds import WorldName, WorldRanges

if TYPE_CHECKING:
    from workcell.expert.skill import ExpertConfig
    from workcell.sim.config import WorldConfig
    from workcell.sim.events import WorldEvent
    from workcell.sim.world import TaskScene, World
    from workcell.task.operator import Operator


@dataclass(frozen=True)
class Evaluation:
    """How a trial stands: ``success`` (the task is done and the scene has settled),
    ``failure`` (it can no longer be done), ``progress`` (0 to 1: the share of the task's
    objects done) and ``stage``, the furthest of the task's :attr:`Task.stages` reached."""

    success: bool
    failure: bool
    progress: float
    stage: str


Reference = Literal["box", "goal"]
BY_GRASP: Literal["by_grasp"] = "by_grasp"
"""A task's :attr:`Task.segment_references` when its segments end where the hands take or
let go of an object rather than at its stages."""
SegmentReferences = Mapping[str, Reference] | Literal["by_grasp"]


@dataclass(frozen=True)
class GoalSite:
    """One place a trial's objects go, for data generation: ``x``, ``y`` in the world, the
    turn of its frame (``yaw``, rad) and the ``height`` (m) of what an object is set down on
    (0: a goal on the floor plan only)."""

    x: float
    y: float
    yaw: float = 0.0
    height: float = 0.0


"""What a stage's motion acts on, for data generation (:mod:`workcell.generate.segments`):
``box`` the object the trial grasps, ``goal`` where the trial's objects go (the numbers of
:meth:`Task.goal`)."""


class SettledCheck(Protocol):
    """Whether the objects a trial completed stay completed once it succeeded: data
    generation keeps the simulation running a second past a success and asks this each
    control period (:mod:`workcell.generate.recheck`)."""

    @property
    def objects(self) -> int:
        """How many completed objects it watches (0: a success with none to check)."""
        ...

    def why_undone(self, world: World, settling: bool) -> str | None:
        """None while each watched object is still completed (or the scene took it away);
        else what undid one (``box 0 held again``). While ``settling`` (the success's first
        moments) an object in place and let go of may still be coming to rest."""
        ...


@dataclass(frozen=True)
class ObjectLook:
    """How one of a trial's objects looks: its sides (m) and its colour (RGBA, 0-1)."""

    size: tuple[float, float, float]
    rgba: tuple[float, float, float, float]


class TrialJudge(Protocol):
    """One trial's progress, kept from the world's events and read from the world at each
    frame instant (so what it says can be checked against the recorded frames)."""

    @property
    def done(self) -> int:
        """Objects the trial has completed so far (scored with ``task.box_score`` each)."""
        ...

    def observe(self, event: WorldEvent) -> None:
        """Take in one of the world's events of the trial's running time."""

    def evaluate(self, world: World) -> Evaluation:
        """The trial as it stands, read at a frame instant."""
        ...


class Task(ABC):
    """One task of the workcell; subclasses declare the class attributes and the methods.

    A task outside this package is named ``module:Class`` (``task.kind``, ``--task``) and
    loaded like a built-in one (:func:`workcell.tasks.registry.load_task`)."""

    name: ClassVar[str]
    """The name ``task.kind`` and ``--task`` use (lower case, ``_`` between words)."""
    summary: ClassVar[str]
    """One line for ``workcell tasks``."""
    stages: ClassVar[tuple[str, ...]]
    """The named stages of a trial, in order; the last one is the task done."""
    worlds: ClassVar[Mapping[WorldName, WorldRanges]]
    """The task's worlds ``D0`` (narrow), ``D1`` (moderate) and ``D2`` (broad): how far each
    trial's conditions may stray (:mod:`workcell.tasks.worlds`)."""
    objects_per_trial: ClassVar[int | None] = None
    """How many objects every trial of the task asks, whatever the session's schedule says
    (palletize: the four boxes of its pattern); None: the schedule's count (one in practice
    and collection, ``task.level_boxes`` in a challenge)."""
    least_time_limit_s: ClassVar[float] = 0.0
    """The least time a trial of the task is given: a shorter limit from the session
    (``task.time_limit_s``, ``task.level_time_limits_s``) is raised to it (palletize: 180 s
    for four carries)."""
    goal_names: ClassVar[tuple[str, ...]]
    """The names of :meth:`goal`'s numbers, in order (they follow the objects in every
    observation's ``environment_state`` and every dataset's feature names)."""
    segment_references: ClassVar[SegmentReferences | None] = None
    """For data generation (``workcell generate``): what the motion of a segment ending at
    each of :attr:`stages` acts on; or :data:`BY_GRASP` for a task that carries several
    objects a trial (a segment ends wherever the hands take or let go of one, and acts on
    the object it takes or on the goal site it sets it down at). None: the task's trials
    cannot be generated yet."""

    @abstractmethod
    def goal(self, conditions: Mapping[str, Any], world: WorldConfig) -> tuple[float, ...]:
        """What a trial asks, as numbers a policy observes: read from the trial's
        conditions as recorded (``trial_started``'s ``conditions``; the configured
        ``world`` where they say nothing), so the environment and the exports agree."""

    @abstractmethod
    def instruction(self, required: int) -> str:
        """What a trial that must complete ``required`` objects asks, in one sentence
        (the language instruction of every exported episode)."""

    def trial_instruction(self, required: int, conditions: Mapping[str, Any]) -> str:
        """What one trial asked, in one sentence, given its recorded ``conditions`` (a task
        whose trials ask different things, such as which shelf, says it here; by default
        :meth:`instruction`). Every exported episode carries it."""
        return self.instruction(required)

    def object_looks(
        self, conditions: Mapping[str, Any], pool: int, trial_box: ObjectLook
    ) -> tuple[ObjectLook, ...]:
        """How each of the trial's ``pool`` objects looked, read from its recorded
        ``conditions`` (what a replay or a Rerun recording draws); by default each is the
        trial's one box, ``trial_box`` (its ``box_size`` and ``box_rgba``). A task whose
        objects differ within a trial (sort's two kinds) says so here."""
        return (trial_box,) * pool

    @abstractmethod
    def scene(self) -> TaskScene:
        """What the task adds to the shared factory and watches there each control period
        (a new one for each world: :class:`workcell.sim.world.TaskScene`)."""

    @abstractmethod
    def new_trial(self, required: int) -> TrialJudge:
        """A judge for a trial that must complete ``required`` objects."""

    @abstractmethod
    def expert(self, config: ExpertConfig) -> Operator:
        """The task's scripted expert at ``config``'s skill."""

    def goal_sites(self, goal: Sequence[float]) -> tuple[GoalSite, ...]:
        """Where a trial's objects go, from :meth:`goal`'s numbers (data generation moves a
        segment acting on a goal from the source trial's site to the attempt's); by
        default one site: the goal's first two numbers, unturned, at height 0."""
        return (GoalSite(float(goal[0]), float(goal[1])),)

    def source_key(self, goal: Sequence[float]) -> tuple[float, ...]:
        """What a source trial must share with an attempt, read from :meth:`goal`'s numbers,
        for data generation to replay it there where the source set has such a trial (by
        default nothing: any source; shelve: the asked board's height; sort: which table
        each box goes to)."""
        return ()

    def settled_check(self, world: World) -> SettledCheck | None:
        """A check that the objects ``world``'s trial completed stay completed, taken the
        moment it succeeded (None: the task has none, and generation cannot re-check it)."""
        return None
