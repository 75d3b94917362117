"""``workcell train --correction-weight K`` (issue 35, item 3): demonstrations plus the
corrected stretches, aggregated as HG-DAgger does, read back with the real LeRobot; the
driver's own frames of a corrected rollout are left out; a dataset without corrections is
refused in one line; and LeRobot's training runs on the aggregate."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from tests.export.corrected import record_corrected
from tests.learn.test_policy_correction import TINY_ACT
from tests.learn_extra import require_learn_extra
from workcell.export.lerobot_export import export_lerobot
from workcell.export.options import ExportOptions
from workcell.learn.corrections import aggregate, corrected_runs, drivers, plan
from workcell.learn.errors import LearnError
from workcell.record.store import Store

pytestmark = pytest.mark.filterwarnings(
    "ignore:The video decoding and encoding capabilities of torchvision:UserWarning"
)


@pytest.fixture(scope="module")
def corrected_export(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, list[np.ndarray]]:
    """A LeRobot export of two expert trials, the second taken over once; each trial's
    recorded intervention flags."""
    folder = tmp_path_factory.mktemp("corrections")
    store = folder / "store.sqlite"
    record_corrected(store, trials=2, taken={1})
    with Store.open(store, writer=False) as reader:
        flags = [
            np.nan_to_num(np.asarray(reader.frames(t.trial_id)["intervention"], float)) == 1.0
            for t in reader.trials()
        ]
    out = folder / "dataset"
    export_lerobot(store, out, ExportOptions(include_all=True))
    return out, flags


def test_runs_of_corrected_frames() -> None:
    flags = np.array([0, 1, 1, 0, 0, 1, 0, 1, 1, 1], dtype=bool)
    assert corrected_runs(flags) == [(1, 3), (5, 6), (7, 10)]
    assert corrected_runs(np.zeros(4, dtype=bool)) == []


@pytest.mark.filterwarnings("error::RuntimeWarning")  # none printed to the person training
@pytest.mark.parametrize("weight", [1, 3])
def test_the_training_dataset_holds_demonstrations_plus_the_corrected_stretches(
    corrected_export: tuple[Path, list[np.ndarray]], tmp_path: Path, weight: int
) -> None:
    require_learn_extra()
    from lerobot.datasets.lerobot_dataset import (  # type: ignore[import-untyped, import-not-found, unused-ignore]
        LeRobotDataset,
    )

    dataset, (demo, rollout) = corrected_export
    assert not demo.any() and rollout.any()
    built = tmp_path / "built"
    result = aggregate(dataset, built, weight)
    corrected = int(rollout.sum())
    assert result.demonstration_frames == len(demo)
    assert result.corrected_frames == weight * corrected
    read = LeRobotDataset("local/built", root=built)
    assert read.num_episodes == 1 + weight
    assert len(read) == len(demo) + weight * corrected
    lengths = [int(e["length"]) for e in read.meta.episodes]
    assert lengths == [len(demo), *[corrected] * weight]
    flags = [bool(read[i]["intervention"].item()) for i in range(len(read))]
    # the demonstration whole, then only the corrected frames: none of the driver's own
    assert flags == [False] * len(demo) + [True] * (weight * corrected)
    source = LeRobotDataset("local/source", root=dataset)
    first = int(np.flatnonzero(rollout)[0])
    start = len(demo) + first  # the rollout's first corrected frame in the source
    for copy in range(weight):
        at = len(demo) + copy * corrected
        for offset in (0, corrected - 1):
            assert np.allclose(read[at + offset]["action"], source[start + offset]["action"]), (
                copy,
                offset,
            )
            assert read[at + offset]["frame_index"].item() == offset


def test_a_policy_rollout_nobody_corrected_is_left_out() -> None:
    alone, corrected = np.zeros(4, dtype=bool), np.array([0, 1, 1, 0], dtype=bool)
    episodes = {0: alone, 1: corrected, 2: alone, 3: alone, 4: alone}
    who = {0: "person", 1: "policy:runs/act", 2: "policy:runs/act", 3: "expert", 4: None}
    result = plan(episodes, 2, "d", who)
    assert result.left_out == (2,)  # the policy alone; the person's, expert's, unknown kept
    assert [(s.episode, s.corrected) for s in result.stretches] == [
        (0, False),
        (1, True),
        (1, True),
        (3, False),
        (4, False),
    ]
    assert plan(episodes, 2, "d").left_out == ()  # without drivers nothing can be told apart


def test_the_export_names_who_drove_each_episode(
    corrected_export: tuple[Path, list[np.ndarray]],
) -> None:
    dataset, flags = corrected_export
    assert drivers(dataset) == dict.fromkeys(range(len(flags)), "expert")


def test_a_dataset_without_corrections_says_so(lerobot_dir: Path, tmp_path: Path) -> None:
    require_learn_extra()
    with pytest.raises(LearnError, match="holds no corrections") as raised:
        aggregate(lerobot_dir, tmp_path / "built", 2)
    assert "\n" not in str(raised.value)
    with pytest.raises(LearnError, match="--correction-weight = 0: must be"):
        plan({0: np.ones(3, dtype=bool)}, 0, "d")


def test_training_runs_on_demonstrations_plus_corrections(
    corrected_export: tuple[Path, list[np.ndarray]], tmp_path: Path
) -> None:
    require_learn_extra()
    dataset, (_, rollout) = corrected_export
    out = tmp_path / "act"
    done = subprocess.run(
        [sys.executable, "-m", "workcell", "train", "--dataset", str(dataset),
         "--out", str(out), "--steps", "2", "--batch-size", "4",
         "--correction-weight", "2", *TINY_ACT],
        capture_output=True, text=True, timeout=900, check=False,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-3000:] + done.stdout[-2000:]
    assert f"1 corrected stretch(es) x 2 = {2 * int(rollout.sum())} frames" in done.stdout
    assert (out / "checkpoints" / "last" / "pretrained_model").is_dir()
    assert (tmp_path / "act-dataset" / "meta" / "info.json").is_file()
    bad = subprocess.run(
        [sys.executable, "-m", "workcell", "train", "--dataset", str(dataset),
         "--out", str(tmp_path / "x"), "--correction-weight", "0"],
        capture_output=True, text=True, timeout=300, check=False,
    )  # fmt: skip
    assert bad.returncode != 0 and "--correction-weight = 0: must be" in bad.stderr
