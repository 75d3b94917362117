"""Every setup parameter of a session (the paper's Fig. 3), frozen and validated.

Defaults are the paper's. Each setting is declared once with
:func:`~workcell.settings.setting`; its validation, template line, setup-page hint and
README row come from that declaration. A session stores its whole :class:`SessionConfig`
as metadata, so every trial can be traced to the exact parameters it ran under.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal, get_args

from workcell import checks
from workcell.errors import ConfigError
from workcell.metrics.definitions import MetricThresholds
from workcell.settings import declared_problems, divides, same_as, section, setting, steps_per
from workcell.sim.config import WorldConfig

Mode = Literal["practice", "collection", "challenge"]
MODES: tuple[str, ...] = get_args(Mode)
PoseFilterKind = Literal["one_euro", "off"]
TASK_KIND_PATTERN = r"[a-z][a-z0-9_]{0,63}|[A-Za-z_][\w.]{0,199}:[A-Za-z_]\w{0,99}"
"""A built-in task's name, or ``module:Class`` (:mod:`workcell.tasks.registry`)."""
DRIVER_PATTERN = r"person|expert|policy:\S.{0,999}"
"""Who drives a live session: ``person``, ``expert`` or ``policy:PATH``."""


def _raise_if(problems: list[str]) -> None:
    if problems:
        raise ConfigError(problems)


@dataclass(frozen=True)
class TaskConfig:
    """What the operator is asked to do: the task, the mode and its levels, limits and
    scoring."""

    kind: str = setting(
        "box_transfer",
        "the task (workcell tasks lists them), or module:Class for a task of your own",
        pattern=TASK_KIND_PATTERN,
        pattern_doc="a task's name (lower case, digits, '_') or module:Class",
    )
    mode: Mode = setting(
        "practice",
        "practice: one trial, one box; collection: repeated one-box trials; "
        "challenge: rounds of levels",
    )
    time_limit_s: float = setting(
        120.0,
        "time limit of a practice or collection trial",
        unit="s",
        low=0.0,
        low_open=True,
        high=3600.0,
    )
    trials: int = setting(
        0,
        "collection: stop after this many trials (0: until stopped)",
        unit="trials",
        low=0,
        high=100_000,
    )
    first_trial: int = setting(
        0,
        "collection: the trial index the session starts at (a study step resumed after a "
        "stop: the trials before it were done in an earlier session); 0: from the first",
        unit="trials",
        low=0,
        high=100_000,
    )
    rounds: int = setting(5, "challenge: rounds in the campaign", unit="rounds", low=1, high=100)
    box_score: int = setting(100, "points per completed object", unit="points", low=0, high=100_000)
    level_boxes: tuple[int, ...] = setting(
        (1, 2, 3),
        "challenge: boxes required at each level of a round",
        unit="boxes",
        low=1,
        high=20,
        min_items=1,
    )
    level_time_limits_s: tuple[float, ...] = setting(
        (120.0, 100.0, 90.0),
        "challenge: time limit of each level",
        unit="s",
        low=0.0,
        low_open=True,
        high=3600.0,
        min_items=1,
        constraint="one limit per level of task.level_boxes",
    )
    countdown_s: float = setting(
        3.0, "countdown before each trial's clock starts", unit="s", low=0.0, high=30.0
    )

    def __post_init__(self) -> None:
        problems = declared_problems(self, "task")
        if self.level_boxes and len(self.level_time_limits_s) != len(self.level_boxes):
            problems.append(
                checks.problem(
                    "task.level_time_limits_s",
                    tuple(self.level_time_limits_s),
                    f"must have one limit per level: task.level_boxes has "
                    f"{len(self.level_boxes)} levels",
                )
            )
        if self.first_trial and self.mode != "collection":
            problems.append(
                checks.problem(
                    "task.first_trial",
                    self.first_trial,
                    f"must be 0 in {self.mode} mode: only a collection session starts at a "
                    "later trial",
                )
            )
        elif self.first_trial and self.trials and self.first_trial >= self.trials:
            problems.append(
                checks.problem(
                    "task.first_trial",
                    self.first_trial,
                    f"must be less than task.trials ({self.trials}): the session would "
                    "have no trial to run",
                )
            )
        _raise_if(problems)

    @property
    def levels(self) -> int:
        return len(self.level_boxes)


@dataclass(frozen=True)
class RecordingConfig:
    """How frames are sampled and which motion counts as activity in the metrics."""

    sampling_rate_hz: float = setting(
        20.0,
        "frames per second of simulated time",
        unit="Hz",
        low=0.0,
        low_open=True,
        constraint="must divide the physics rate 1/world.timestep evenly",
    )
    grip_threshold: float = same_as(MetricThresholds, "grip_threshold")
    base_linear_threshold: float = same_as(MetricThresholds, "base_linear_threshold")
    base_yaw_threshold: float = same_as(MetricThresholds, "base_yaw_threshold")
    joint_rate_threshold: float = same_as(MetricThresholds, "joint_rate_threshold")

    def __post_init__(self) -> None:
        _raise_if(declared_problems(self, "recording"))


@dataclass(frozen=True)
class InputConfig:
    """Jitter filtering of the operator's tracked poses (controllers, hands, headset): a
    One-Euro filter (Casiez et al., CHI 2012) per pose, whose cutoff frequency rises with
    the pose's speed, so a hand held still is smoothed and a fast motion keeps up. The raw
    poses are recorded as they arrived; the filtered ones drive the arms and the head."""

    filter: PoseFilterKind = setting(
        "one_euro", "one_euro (filter tracked poses) or off (use them as they arrive)"
    )
    min_cutoff_hz: float = setting(
        1.5,
        "cutoff frequency of a pose held still: lower smooths more and lags more",
        unit="Hz",
        low=0.0,
        low_open=True,
        high=100.0,
    )
    beta_position: float = setting(
        20.0,
        "how fast the cutoff rises with the position's speed (Hz per m/s)",
        unit="s/m",
        low=0.0,
        high=1000.0,
    )
    beta_rotation: float = setting(
        5.0,
        "how fast the cutoff rises with the rotation's angular speed (Hz per rad/s)",
        unit="s/rad",
        low=0.0,
        high=1000.0,
    )
    d_cutoff_hz: float = setting(
        1.0,
        "cutoff frequency of the speed estimate",
        unit="Hz",
        low=0.0,
        low_open=True,
        high=100.0,
    )

    def __post_init__(self) -> None:
        _raise_if(declared_problems(self, "input"))


@dataclass(frozen=True)
class SessionConfig:
    """One operator sitting: task, recording, world, seed, operator, study condition and
    step."""

    task: TaskConfig = section(TaskConfig, "the task mode, levels, limits and scoring")
    recording: RecordingConfig = section(RecordingConfig, "sampling and activity thresholds")
    world: WorldConfig = section(WorldConfig, "the factory workcell and the robot")
    input: InputConfig = section(InputConfig, "jitter filtering of the operator's tracked poses")
    seed: int = setting(
        0,
        "session seed: every trial's start is derived from it",
        unit="1",
        low=0,
        high=2**63 - 1,
    )
    operator_id: str = setting(
        "anonymous",
        "who operates",
        pattern=r"[\w.-]{1,64}",
        pattern_doc="1 to 64 letters, digits, '.', '_' or '-'",
    )
    condition: str = setting(
        "",
        "the study condition the session belongs to (empty: none); "
        "workcell audit --by condition compares conditions",
        pattern=r"[\w.-]{0,64}",
        pattern_doc="up to 64 letters, digits, '.', '_' or '-'",
    )
    driver: str = setting(
        "person",
        "who drives a live session: person (the operator at the browser or headset), expert "
        "(the task's scripted expert) or policy:PATH (a trained policy's checkpoint); with "
        "expert or a policy the person watches and may take over and hand back "
        "(docs/intervention.md); workcell collect's --operator decides there",
        pattern=DRIVER_PATTERN,
        pattern_doc="person, expert or policy:PATH (PATH a trained policy's folder)",
    )
    consent: str = setting(
        "",
        "SHA-256 of the consent text the operator accepted for this session (empty: none "
        "asked); workcell serve --study sets it",
        pattern=r"([0-9a-f]{64})?",
        pattern_doc="empty or 64 lower-case hex digits",
    )
    study_step: int = setting(
        0,
        "which of the participant's planned sessions this is, from 1 in the order they run "
        "them (0: not a planned session of a study); workcell serve --study and workcell "
        "study set it",
        unit="1",
        low=0,
        high=10_000,
    )

    def __post_init__(self) -> None:
        problems = declared_problems(self, "")
        problems += divides(
            "recording.sampling_rate_hz",
            self.recording.sampling_rate_hz,
            self.world.physics_hz,
            "the physics rate 1/world.timestep",
        )
        _raise_if(problems)

    @property
    def physics_steps_per_frame(self) -> int:
        """Physics steps per recorded frame (validated to be whole on construction)."""
        steps = steps_per(self.world.physics_hz, self.recording.sampling_rate_hz)
        assert steps is not None, "validated in __post_init__"
        return steps
