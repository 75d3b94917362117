"""``workcell generate`` end to end: expert source trials recorded with ``workcell
collect``, attempts generated in D1 into a real store (real MuJoCo, real SQLite), their
provenance, verdicts and operator id read back, the store verified, audited and exported
by operator; and the generator never builds the task's expert."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path
from typing import Any

import h5py  # type: ignore[import-untyped, unused-ignore]
import numpy as np
import pytest

from workcell.cli.main import main
from workcell.generate.plan import generated_operator_id
from workcell.record import Store
from workcell.record.verify import verify_store

LIFT_BOX = "examples.lift_box:LiftBox"
"""A task of one's own that declares nothing generation needs (examples/lift_box)."""
EXPERT_BUILT = "expert-built"
"""The file the guarded interpreter writes when anything builds or runs the expert."""
GUARD = textwrap.dedent(
    """
    import sys
    from pathlib import Path
    from workcell.tasks.elements.expert import ExpertOperator

    marker = Path(sys.argv[1])

    def refuse(*args, **kwargs):
        marker.write_text("the expert was called")
        raise RuntimeError("the expert was called")

    ExpertOperator.__init__ = refuse
    ExpertOperator.act = refuse
    from workcell.cli.main import main
    raise SystemExit(main(sys.argv[2:]))
    """
)


def guarded(marker: Path, *argv: str) -> subprocess.CompletedProcess[str]:
    """``workcell argv`` in a fresh interpreter in which building the expert (or calling its
    act) writes ``marker`` and fails."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    return subprocess.run(
        [sys.executable, "-c", GUARD, str(marker), *argv],
        capture_output=True,
        text=True,
        env=env,
        timeout=600,
        check=False,
    )


@pytest.fixture(scope="module")
def sources(tmp_path_factory: pytest.TempPathFactory) -> Path:
    store = tmp_path_factory.mktemp("sources") / "sources.sqlite"
    argv = ["collect", "--mode", "collection", "--trials", "2", "--seed", "1"]
    assert main([*argv, "--store", str(store), "--writer", "inline"]) == 0
    return store


@pytest.fixture(scope="module")
def generated(sources: Path, tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, str]:
    """Three attempts in D1, generated in a guarded interpreter; (store, its stdout)."""
    folder = tmp_path_factory.mktemp("generated")
    out, marker = folder / "generated.sqlite", folder / EXPERT_BUILT
    run = guarded(
        marker,
        "generate", "--source", str(sources), "--attempts", "3", "--seed", "7",
        "--store", str(out), "--world", "D1",
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    assert not marker.exists()
    return out, run.stdout


def source_ids(store: Path) -> list[str]:
    with Store.open(store, writer=False) as reader:
        return sorted(t.trial_id for t in reader.trials() if t.outcome == "success")


def generation_events(store: Path) -> dict[str, dict[str, Any]]:
    """Each session's ``generation`` event payload, by trial id."""
    with Store.open(store, writer=False) as reader:
        events = [e for e in reader.events() if e.kind == "generation"]
    return {str(e.payload["trial_id"]): e.payload for e in events}


def test_the_guard_catches_the_expert(sources: Path, tmp_path: Path) -> None:
    """The guard the generation runs under does fail a command that drives the expert."""
    marker = tmp_path / EXPERT_BUILT
    run = guarded(marker, "collect", "--trials", "1", "--store", str(tmp_path / "x.sqlite"))
    assert run.returncode != 0
    assert marker.exists()


def test_attempts_are_recorded_with_operator_provenance_and_verdicts(
    sources: Path, generated: tuple[Path, str]
) -> None:
    out, stdout = generated
    ids = source_ids(sources)
    operator = generated_operator_id(ids)
    assert operator.startswith("generated-")
    with Store.open(out, writer=False) as reader:
        sessions = reader.sessions()
        trials = {t.trial_id: t for t in reader.trials()}
    assert [s.operator_id for s in sessions] == [operator] * 3
    assert {t.world for t in trials.values()} == {"D1"}
    events = generation_events(out)
    assert set(events) == set(trials)
    for trial_id, payload in events.items():
        assert payload["source_trial_ids"] == ids
        assert payload["source_trial_id"] in ids
        assert payload["outcome"] == trials[trial_id].outcome
        assert payload["stage"] == trials[trial_id].stage
        segments = payload["segments"]
        assert isinstance(segments, list) and segments
        assert [s["index"] for s in segments] == list(range(len(segments)))
        first = segments[0]
        assert first["reference"] == "box" and first["start_frame"] == 0
        assert first["end_frame"] > first["anchor_frame"] > 0
        assert set(first["transform"]) == {"x", "y", "yaw"}
    accepted = [p for p in events.values() if p["accepted"]]
    assert accepted, stdout
    for payload in accepted:
        assert payload["outcome"] == "success" and payload["reason"] is None
        assert payload["recheck"] == {
            "seconds": 1.0,
            "settle_s": 0.25,
            "held": True,
            "reason": None,
        }
        stages = [s["end_stage"] for s in payload["segments"]]
        assert stages[-1] == "delivered"
        assert {s["reference"] for s in payload["segments"]} == {"box", "goal"}
    assert "3/3 done" in stdout and "Wilson 95 %" in stdout


def test_an_attempt_drives_off_while_its_box_rides_the_belt(
    generated: tuple[Path, str],
) -> None:
    """The first segment's frames before its anchor (the source driving to the belt's end
    while its box arrived) are replayed while the attempt's box is on its way: the base is
    moving within the first second, not standing at its start until the box has rested,
    and the join that follows is short."""
    out, _ = generated
    events = generation_events(out)
    with Store.open(out, writer=False) as reader:
        for trial_id, payload in events.items():
            frames = reader.frames(trial_id)
            t, speed = frames["t_sim"], np.hypot(frames["base_vx"], frames["base_vy"])
            assert float(np.max(speed[t <= 1.0])) > 0.05, trial_id
            first, second = payload["segments"][:2]
            assert first["approached_s"] == pytest.approx(first["began_s"], abs=0.06)
            assert first["approached_s"] > 5.0
            assert second["approached_s"] == 0.0
            # join and play of the box-relative approach: seconds, not the drive from
            # the start
            assert second["began_s"] - first["began_s"] < 6.0


def test_the_output_verifies_audits_and_exports_by_operator(
    sources: Path, generated: tuple[Path, str], tmp_path: Path
) -> None:
    out, _ = generated
    assert verify_store(out) == []
    assert main(["verify", "--store", str(out)]) == 0
    assert main(["audit", "--store", str(out), "--out", str(tmp_path / "audit")]) == 0
    summary = json.loads((tmp_path / "audit" / "summary.json").read_text())
    assert summary["counts"]["raw"] == 3
    operator = generated_operator_id(source_ids(sources))
    data = tmp_path / "data"
    argv = ["export", "--format", "hdf5", "--store", str(out), "--out", str(data)]
    assert main([*argv, "--operator", operator]) == 0
    with h5py.File(data / "workcell.hdf5") as exported:
        episodes = len(exported["data"])
    accepted = sum(1 for p in generation_events(out).values() if p["accepted"])
    assert episodes == accepted
    assert main([*argv[:-1], str(tmp_path / "none"), "--operator", "expert"]) != 0


def test_a_rejected_attempt_says_why_and_how_far_it_got(sources: Path, tmp_path: Path) -> None:
    """With too little time to finish, attempts time out: rejected, with their stage."""
    out = tmp_path / "short.sqlite"
    argv = ["generate", "--source", str(sources), "--attempts", "1", "--world", "D1"]
    assert main([*argv, "--store", str(out), "--set", "task.time_limit_s=14"]) == 0
    (payload,) = generation_events(out).values()
    with Store.open(out, writer=False) as reader:
        (trial,) = reader.trials()
    assert trial.outcome == "timeout"
    assert payload["accepted"] is False and payload["recheck"] is None
    assert payload["reason"] == f"timeout at stage {trial.stage}"
    assert trial.stage in ("none", "touched", "grasped", "lifted")


def test_bad_input_gets_one_clear_error(
    sources: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    empty = tmp_path / "empty.sqlite"
    with Store.open(empty, writer=True):
        pass
    base = ["generate", "--attempts", "1", "--store", str(tmp_path / "out.sqlite")]
    cases = [
        (["--source", str(empty)], "holds no trials"),
        (["--source", str(tmp_path / "missing.sqlite")], "no such store"),
        (
            ["--source", str(sources), "--source-operator", "nobody"],
            "no trials of task box_transfer by operator nobody",
        ),
        (["--source", str(sources), "--task", LIFT_BOX], "lift_box: the task declares no"),
        (["--source", str(sources), "--task", "palletize"], "no trials of task palletize"),
        (["--source", str(sources), "--world", "D3"], "invalid choice: 'D3'"),
        (["--source", str(sources), "--attempts", "0"], "--attempts = 0: must be 1 to"),
    ]
    for extra, message in cases:
        assert main([*base, *extra]) == 2
        err = capsys.readouterr().err
        assert message in err and len(err.strip().splitlines()) == 1, err
    assert not (tmp_path / "out.sqlite").exists()


def test_workers_take_attempts_from_one_queue_into_one_verified_store(
    sources: Path, tmp_path: Path
) -> None:
    out = tmp_path / "workers.sqlite"
    argv = ["generate", "--source", str(sources), "--attempts", "3", "--seed", "7"]
    assert main([*argv, "--world", "D1", "--store", str(out), "--workers", "2"]) == 0
    assert verify_store(out) == []
    events = generation_events(out)
    assert sorted(int(str(p["attempt"])) for p in events.values()) == [0, 1, 2]
    with Store.open(out, writer=False) as reader:
        assert len(reader.sessions()) == 3
    assert not (tmp_path / "workers.sqlite.shards").exists()


@pytest.mark.slow
def test_ray_tasks_run_attempts_into_one_verified_store(sources: Path, tmp_path: Path) -> None:
    out = tmp_path / "ray.sqlite"
    argv = ["generate", "--source", str(sources), "--attempts", "6", "--seed", "7"]
    assert main([*argv, "--world", "D1", "--store", str(out), "--ray", "local"]) == 0
    assert verify_store(out) == []
    events = generation_events(out)
    assert sorted(int(str(p["attempt"])) for p in events.values()) == list(range(6))
    assert not (tmp_path / "ray.sqlite.shards").exists()
