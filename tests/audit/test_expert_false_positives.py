"""Deliberate expert motion is not an oscillation: a real challenge round, audited."""

from __future__ import annotations

import csv
from pathlib import Path

from workcell.cli.main import main


def test_expert_challenge_round_has_no_oscillation_flags(tmp_path: Path) -> None:
    """Levels 2 and 3 chain grasps, lifts and releases quickly; detector version 1 flagged
    both of them (the wrist reverses several times within 2 s), version 2 flags neither."""
    store = tmp_path / "challenge.sqlite"
    args = ["collect", "--mode", "challenge", "--trials", "3", "--seed", "0"]
    assert main([*args, "--store", str(store), "--json"]) == 0
    out = tmp_path / "audit"
    assert main(["audit", "--store", str(store), "--out", str(out)]) == 0
    with (out / "trials.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    assert [r["level"] for r in rows] == ["1", "2", "3"]
    assert all(r["outcome"] == "success" for r in rows)
    assert [r["flag_arm_oscillation"] for r in rows] == ["0", "0", "0"]
