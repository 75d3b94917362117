"""Demonstrations plus corrections, aggregated as HG-DAgger does (issue 35, item 3).

A LeRobot export's episode whose ``intervention`` feature is true on some frame is a
corrected rollout: a person took over from the driver there. Only its corrected stretches
(each run of consecutive ``intervention`` frames) are training data, each its own episode so
that LeRobot's timestamps stay 1/fps apart; the driver's own frames of that rollout are not
imitated. Every other episode is a demonstration and is kept whole. ``weight`` K repeats each
corrected stretch K times: LeRobot 0.4.4 has no per-sample weights, so repeating the
stretch's episode is what weighs it (each copy is sampled as often as a demonstration frame).

An episode a policy drove with nobody taking over is left out: it is the policy's own
behaviour, not a demonstration. Who drove each episode is the export's provenance sidecar's
``driver`` (``meta/workcell_provenance.parquet``, :mod:`workcell.export.provenance`); an
export from before that column holds no drivers, and there such an episode cannot be told
from a demonstration: export the demonstrations and the corrected rollouts (``workcell
export --trials``), not rollouts the policy ran alone.
"""

from __future__ import annotations

import json
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from workcell.export.lerobot_layout import PROVENANCE_TABLE_PATH
from workcell.learn.errors import LearnError, MissingLearnExtraError

INTERVENTION = "intervention"
"""LeRobot's per-frame boolean feature of a corrected frame (``workcell export``)."""
MAX_WEIGHT = 100
_LEROBOT_OWN = ("timestamp", "frame_index", "episode_index", "index", "task_index")
POLICY_DRIVER = "policy:"
"""How a trial's ``driver`` names a policy (``policy:<id>``; src/workcell/session/config.py)."""


@dataclass(frozen=True)
class Stretch:
    """Frames ``start`` (inclusive) to ``stop`` (exclusive) of source episode ``episode``."""

    episode: int
    start: int
    stop: int
    corrected: bool

    @property
    def length(self) -> int:
        return self.stop - self.start


@dataclass(frozen=True)
class CorrectionPlan:
    stretches: tuple[Stretch, ...]
    """In the order they are written: every episode's, each corrected stretch K times."""
    left_out: tuple[int, ...] = ()
    """Episodes a policy drove that nobody corrected: not trained on."""

    @property
    def demonstration_frames(self) -> int:
        return sum(s.length for s in self.stretches if not s.corrected)

    @property
    def corrected_frames(self) -> int:
        """Corrected frames written, copies counted."""
        return sum(s.length for s in self.stretches if s.corrected)


def check_weight(weight: int) -> None:
    if type(weight) is not int or not 1 <= weight <= MAX_WEIGHT:
        raise LearnError(
            f"--correction-weight = {weight!r}: must be a whole number 1 to {MAX_WEIGHT} "
            "(how many times each corrected stretch is repeated)"
        )


def corrected_runs(intervention: NDArray[np.bool_]) -> list[tuple[int, int]]:
    """Each run of consecutive true values as (start, stop)."""
    flags = np.concatenate([[False], np.asarray(intervention, dtype=bool), [False]])
    edges = np.flatnonzero(np.diff(flags.astype(np.int8)))
    return [(int(a), int(b)) for a, b in zip(edges[::2], edges[1::2], strict=True)]


def plan(
    episodes: dict[int, NDArray[np.bool_]],
    weight: int,
    source: str,
    drivers: Mapping[int, str | None] | None = None,
) -> CorrectionPlan:
    """The stretches to train on, from each episode's ``intervention`` column and who
    drove it (``drivers``, by episode; missing or None: not recorded)."""
    check_weight(weight)
    drivers = drivers or {}
    stretches: list[Stretch] = []
    left_out: list[int] = []
    for episode, intervention in sorted(episodes.items()):
        runs = corrected_runs(intervention)
        if not runs:
            if (drivers.get(episode) or "").startswith(POLICY_DRIVER):
                left_out.append(episode)  # the policy alone: not a demonstration
            else:
                stretches.append(Stretch(episode, 0, len(intervention), corrected=False))
            continue
        for start, stop in runs:
            stretches.extend(Stretch(episode, start, stop, corrected=True) for _ in range(weight))
    result = CorrectionPlan(tuple(stretches), tuple(left_out))
    if result.corrected_frames == 0:
        raise LearnError(
            f"--dataset {source!r} holds no corrections (no frame with intervention = true): "
            "train without --correction-weight, or export the rollouts a person corrected"
        )
    return result


def read_frames(dataset: Path) -> tuple[dict[str, Any], Any]:
    """The dataset's info.json and its frames (a pandas DataFrame, in index order)."""
    try:
        import pandas as pd  # type: ignore[import-untyped, unused-ignore]  # noqa: PLC0415
    except ImportError:
        raise MissingLearnExtraError("pandas") from None
    info = json.loads((dataset / "meta" / "info.json").read_text())
    files = sorted((dataset / "data").glob("*/*.parquet"))
    frames = pd.concat([pd.read_parquet(f) for f in files]).sort_values("index")
    return info, frames


def drivers(dataset: Path) -> dict[int, str | None]:
    """Who drove each episode (by episode index), from the export's provenance sidecar;
    empty for an export without one or from before its ``driver`` column."""
    import pandas as pd  # type: ignore[import-untyped, unused-ignore]  # noqa: PLC0415

    path = dataset / PROVENANCE_TABLE_PATH
    if not path.exists():
        return {}
    table = pd.read_parquet(path)
    if "driver" not in table.columns:
        return {}
    return {
        int(episode): None if pd.isna(driver) else str(driver)
        for episode, driver in zip(table["episode_index"], table["driver"], strict=True)
    }


def aggregated_path(out: Path) -> Path:
    """Where ``workcell train --out OUT --correction-weight K`` writes the dataset it
    trains on: ``OUT-dataset``, beside OUT (LeRobot wants OUT to itself)."""
    return out.with_name(f"{out.name or 'workcell'}-dataset")


def aggregate(dataset: Path, out: Path, weight: int) -> CorrectionPlan:
    """Write the demonstrations plus ``weight`` copies of each corrected stretch of
    ``dataset`` (a state-only LeRobot export) as a new LeRobotDataset at ``out``."""
    check_weight(weight)
    if out.exists():
        raise LearnError(
            f"{str(out)!r} exists: --correction-weight writes the dataset it trains on there "
            "(beside --out); remove it or give another --out"
        )
    info, frames = read_frames(dataset)
    features: dict[str, Any] = info["features"]
    if INTERVENTION not in features:
        raise LearnError(
            f"--dataset {str(dataset)!r} has no {INTERVENTION!r} feature: it was exported "
            "before corrections were recorded; train without --correction-weight"
        )
    if any(f.get("dtype") in ("video", "image") for f in features.values()):
        raise LearnError(
            f"--dataset {str(dataset)!r} has camera images; --correction-weight works on a "
            "state-only export (workcell export --format lerobot without --cameras)"
        )
    by_episode = {
        int(e): group.sort_values("frame_index") for e, group in frames.groupby("episode_index")
    }
    result = plan(
        {e: group[INTERVENTION].to_numpy(dtype=bool) for e, group in by_episode.items()},
        weight,
        str(dataset),
        drivers(dataset),
    )
    _write(
        out,
        info=info,
        features=features,
        by_episode=by_episode,
        result=result,
        tasks=_tasks(dataset),
    )
    return result


def _tasks(dataset: Path) -> dict[int, str]:
    import pandas as pd  # type: ignore[import-untyped, unused-ignore]  # noqa: PLC0415

    table = pd.read_parquet(dataset / "meta" / "tasks.parquet")
    return {int(i): str(name) for name, i in zip(table.index, table["task_index"], strict=True)}


def _write(
    out: Path,
    *,
    info: dict[str, Any],
    features: dict[str, Any],
    by_episode: dict[int, Any],
    result: CorrectionPlan,
    tasks: dict[int, str],
) -> None:
    try:
        from lerobot.datasets.lerobot_dataset import LeRobotDataset  # noqa: PLC0415
    except ImportError:
        raise MissingLearnExtraError("lerobot") from None
    own = {  # LeRobot compares shapes as tuples (info.json holds lists)
        k: {**v, "shape": tuple(v["shape"])} for k, v in features.items() if k not in _LEROBOT_OWN
    }
    target = LeRobotDataset.create(
        repo_id=f"local/{out.name}",
        fps=int(info["fps"]),
        features=own,
        robot_type=info.get("robot_type"),
        root=out,
        use_videos=False,
    )
    scalars = [key for key, feature in own.items() if feature["shape"] == (1,)]
    for stretch in result.stretches:
        rows = by_episode[stretch.episode].iloc[stretch.start : stretch.stop]
        for _, row in rows.iterrows():
            frame: dict[str, Any] = {"task": tasks[int(row["task_index"])]}
            for key, feature in own.items():
                frame[key] = np.asarray(row[key], dtype=feature["dtype"]).reshape(feature["shape"])
            target.add_frame(frame)
        buffer = target.episode_buffer
        for key in scalars:  # shape (1,): LeRobot validates (1,) but stores a scalar column
            buffer[key] = [value.reshape(()) for value in buffer[key]]
        with warnings.catch_warnings():  # its statistics of the boolean intervention feature
            warnings.filterwarnings("ignore", "Converting input from bool", RuntimeWarning)
            target.save_episode()
    target.finalize()
