"""``workcell evaluate --policy PATH`` with a real LeRobot policy trained for a few steps."""

from __future__ import annotations

import re
import sqlite3
import subprocess
import sys
from pathlib import Path

import pytest

from tests.learn.test_policy_loop import TINY_ACT
from tests.learn_extra import require_learn_extra
from workcell.learn.checkpoint import PolicyCheckpoint
from workcell.record.verify import verify_store
from workcell.task.runner import trial_seed

SEED = 5
LIMIT_S = 1.5
"""A rollout's time limit: a policy trained 2 steps delivers nothing, so it times out."""


def _workcell(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "workcell", *args],
        capture_output=True,
        text=True,
        timeout=900,
        check=False,
    )


@pytest.fixture(scope="module")
def tiny_policy(lerobot_dir: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    require_learn_extra()
    out = tmp_path_factory.mktemp("train") / "tiny-act"
    done = _workcell(
        "train", "--dataset", str(lerobot_dir), "--out", str(out), "--steps", "2", *TINY_ACT
    )
    assert done.returncode == 0, done.stderr[-3000:]
    return out


def test_a_policy_climbs_the_ladder_like_the_expert(tiny_policy: Path, tmp_path: Path) -> None:
    store = tmp_path / "eval.sqlite"
    done = _workcell(
        "evaluate", "--policy", str(tiny_policy), "--world", "D2", "--rollouts", "1",
        "--seed", str(SEED), "--set", f"task.time_limit_s={LIMIT_S}", "--store", str(store),
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-3000:]
    operator = PolicyCheckpoint.locate(tiny_policy).operator_id
    lines = done.stdout.splitlines()
    assert lines[0] == f"{operator} on box_transfer, seed {SEED}: 1 rollout per world"
    row = re.split(r"\s{2,}", lines[2])  # no LeRobot chatter above the table
    assert row[:4] == ["D2", "0/1", "0.0 % [0.0, 79.3]", "-"]  # Wilson; no success, no time
    assert lines[3] == f"recorded 1 session into {store}"
    assert verify_store(store) == []
    with sqlite3.connect(store) as db:
        rows = list(
            db.execute(
                "SELECT operator_id, world, trial_seed, outcome, stage, n_frames "
                "FROM trials JOIN sessions USING (session_id)"
            )
        )
    assert len(rows) == 1
    who, world, seed, outcome, stage, frames = rows[0]
    assert (who, world, seed, outcome) == (operator, "D2", trial_seed(SEED, 0), "timeout")
    assert frames == LIMIT_S * 20 + 1 and row[4] == f"1 {stage}"
