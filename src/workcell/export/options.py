"""What an export or a re-render is asked for: cameras, image size, which trials."""

from __future__ import annotations

import re
from dataclasses import dataclass

from workcell.errors import ConfigError

ROBOT_CAMERAS: tuple[str, ...] = ("head_cam", "wrist_l_cam", "wrist_r_cam")
"""The robot's cameras, in model order (see :mod:`workcell.sim.robot`)."""

MAX_SIDE = 4096
_SIZE = re.compile(r"^(\d+)x(\d+)$")


@dataclass(frozen=True)
class ImageSize:
    """Width and height of rendered images, pixels. Even (H.264 in yuv420p needs it)."""

    width: int = 320
    height: int = 240

    def __post_init__(self) -> None:
        problems = []
        for name, value in (("width", self.width), ("height", self.height)):
            if type(value) is not int or not 2 <= value <= MAX_SIDE or value % 2:
                problems.append(
                    f"image {name} = {value!r}: must be an even whole number from 2 to {MAX_SIDE}"
                )
        if problems:
            raise ConfigError(problems)

    @classmethod
    def parse(cls, text: str, option: str = "--size") -> ImageSize:
        """``"320x240"`` → ImageSize(320, 240)."""
        match = _SIZE.match(text.strip().lower())
        if match is None:
            raise ConfigError([f"{option} {text!r}: must be WIDTHxHEIGHT, e.g. 320x240"])
        try:
            return cls(int(match[1]), int(match[2]))
        except ConfigError as error:
            raise ConfigError([f"{option} {text}: {p}" for p in error.problems]) from None

    def __str__(self) -> str:
        return f"{self.width}x{self.height}"


def parse_cameras(text: str, option: str = "--cameras") -> tuple[str, ...]:
    """``"head_cam,wrist_l_cam"`` → the camera names, checked and without repeats."""
    names = tuple(name.strip() for name in text.split(",") if name.strip())
    unknown = [name for name in names if name not in ROBOT_CAMERAS]
    if unknown or not names:
        raise ConfigError(
            [
                f"{option} {text!r}: name one or more of {', '.join(ROBOT_CAMERAS)}, "
                "separated by commas"
            ]
        )
    return tuple(dict.fromkeys(names))


DEFAULT_SIZE = ImageSize()
"""The image size of an export whose trials hold no recorded video of the cameras asked for
(or videos of several sizes)."""


@dataclass(frozen=True)
class TrialFilter:
    """Which closed trials with frames become episodes."""

    include_all: bool = False
    """Every closed trial (interrupted and excluded ones too), not only included ones."""
    audited: bool = False
    """Inclusion as the audit decides it: valid and without a quality flag."""
    successes_only: bool = False
    """Only successful trials (a dataset for imitation)."""
    tasks: tuple[str, ...] = ()
    """Only the trials of sessions that ran one of these tasks (``task.kind``; none: all)."""
    operators: tuple[str, ...] = ()
    """Only the trials of sessions of one of these operators (their ids; none: all)."""

    def __post_init__(self) -> None:
        if self.include_all and self.audited:
            raise ConfigError(
                ["--all and --audited: --all takes every trial, --audited what the audit keeps"]
            )


@dataclass(frozen=True)
class ExportOptions:
    """Which trials and which camera streams go into a dataset."""

    include_all: bool = False
    """False: included trials only (never interrupted ones); True: every closed trial."""
    audited: bool = False
    """Inclusion as the audit decides it (valid, no quality flag) instead of the store's."""
    successes_only: bool = False
    """Only successful trials."""
    cameras: tuple[str, ...] = ()
    """Robot cameras whose images go into the dataset (none: no images): from the trials'
    recorded videos where they can be used, else rendered from the recorded states (see
    :mod:`workcell.export.camera_sources`)."""
    size: ImageSize | None = None
    """None: the size of the selected trials' recorded videos of these cameras, when there
    are some and they share one size, else :data:`DEFAULT_SIZE`."""
    rerender: bool = False
    """Render every camera image from the recorded states, even where videos were recorded."""
    tasks: tuple[str, ...] = ()
    """Only sessions that ran one of these tasks (none: every task)."""
    operators: tuple[str, ...] = ()
    """Only sessions of one of these operators (none: every operator)."""

    @property
    def trials(self) -> TrialFilter:
        """Which trials become episodes."""
        return TrialFilter(
            self.include_all, self.audited, self.successes_only, self.tasks, self.operators
        )

    @property
    def image_size(self) -> ImageSize:
        """The size asked for (:data:`DEFAULT_SIZE` when none is given)."""
        return self.size or DEFAULT_SIZE

    def __post_init__(self) -> None:
        _ = self.trials  # checks them
        unknown = [c for c in self.cameras if c not in ROBOT_CAMERAS]
        if unknown or len(set(self.cameras)) != len(self.cameras):
            raise ConfigError(
                [
                    f"cameras {list(self.cameras)}: must be distinct names among "
                    f"{', '.join(ROBOT_CAMERAS)}"
                ]
            )
