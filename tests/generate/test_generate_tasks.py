"""``workcell generate --task shelve|palletize``: the other tasks generated through the same
path as box transfer's. Expert trials recorded with ``workcell collect`` are replayed in new
worlds (real MuJoCo, real SQLite) in a guarded interpreter that fails if the expert is
built. Shelve: each attempt replays a source that put its box on the attempt's asked board
where there is one, and otherwise moves the carry up or down by the boards' height
difference. Palletize and sort: each source is cut where the hands take and let go of each
of its four boxes, every carry moved with the slot or table it went to; sort replays a
source whose boxes' kinds came in the attempt's order. Successes are re-checked by each
task's settled check."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from tests.generate.test_generate import EXPERT_BUILT, generation_events, guarded
from workcell.cli.main import main
from workcell.record import Store
from workcell.record.verify import verify_store
from workcell.tasks.registry import load_task
from workcell.tasks.shelve.shelf import BOARD_TOPS

RECHECK_HELD = {"seconds": 1.0, "settle_s": 0.25, "held": True, "reason": None}


def collect(store: Path, trials: int, task: str = "shelve") -> None:
    argv = ["collect", "--task", task, "--mode", "collection", "--trials", str(trials)]
    assert main([*argv, "--seed", "1", "--store", str(store), "--writer", "inline"]) == 0


def generate(  # noqa: PLR0917 - the command's flags
    sources: Path, out: Path, attempts: int, seed: int, world: str, task: str = "shelve"
) -> str:
    run = guarded(
        out.with_name(EXPERT_BUILT),
        "generate", "--task", task, "--source", str(sources), "--attempts", str(attempts),
        "--seed", str(seed), "--store", str(out), "--world", world,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    assert not out.with_name(EXPERT_BUILT).exists()
    return run.stdout


def heights(store: Path) -> dict[str, float]:
    """Each trial's asked board height."""
    with Store.open(store, writer=False) as reader:
        return {t.trial_id: float((t.goal or {})["shelf_height"]) for t in reader.trials()}


def goal_lifts(payload: dict[str, Any]) -> set[float]:
    return {float(s["lift_m"]) for s in payload["segments"] if s["reference"] == "goal"}


@pytest.fixture(scope="module")
def three_boards(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Three expert trials (seed 1): one on each board."""
    store = tmp_path_factory.mktemp("shelve") / "sources.sqlite"
    collect(store, 3)
    assert sorted(heights(store).values()) == sorted(BOARD_TOPS)
    return store


def test_attempts_replay_a_source_of_the_asked_board(three_boards: Path, tmp_path: Path) -> None:
    out = tmp_path / "generated.sqlite"
    stdout = generate(three_boards, out, 3, 7, "D1")
    assert "3/3 accepted" in stdout, stdout
    source_heights, asked = heights(three_boards), heights(out)
    events = generation_events(out)
    assert set(events) == set(asked)
    for trial_id, payload in events.items():
        assert payload["accepted"] and payload["recheck"] == RECHECK_HELD
        assert source_heights[payload["source_trial_id"]] == asked[trial_id]
        assert goal_lifts(payload) == {0.0}
        stages = [s["end_stage"] for s in payload["segments"]]
        assert stages[-1] == "settled"
        assert {s["reference"] for s in payload["segments"]} == {"box", "goal"}
    assert verify_store(out) == []


def test_a_source_of_another_board_is_moved_by_the_height_difference(tmp_path: Path) -> None:
    sources = tmp_path / "one.sqlite"
    collect(sources, 1)
    (source_height,) = heights(sources).values()
    out = tmp_path / "generated.sqlite"
    generate(sources, out, 4, 3, "D0")
    asked = heights(out)
    assert len(set(asked.values())) > 1, "the attempts should ask more than one board"
    for trial_id, payload in generation_events(out).items():
        (lift,) = goal_lifts(payload)
        assert lift == pytest.approx(asked[trial_id] - source_height, abs=1e-6)
        assert {s["lift_m"] for s in payload["segments"] if s["reference"] == "box"} == {0.0}
        assert payload["accepted"], payload["reason"]


def test_palletize_is_cut_per_box_and_every_carry_moves_with_its_slot(tmp_path: Path) -> None:
    sources, out = tmp_path / "sources.sqlite", tmp_path / "generated.sqlite"
    collect(sources, 2, "palletize")
    stdout = generate(sources, out, 2, 7, "D0", "palletize")
    assert "2/2 accepted" in stdout, stdout
    for payload in generation_events(out).values():
        assert payload["accepted"] and payload["recheck"] == RECHECK_HELD
        segments = payload["segments"]
        taken = [s["box"] for s in segments if s["reference"] == "box"]
        assert sorted(set(taken)) == [0, 1, 2, 3]
        carried = {(s["box"], s["site"]) for s in segments if s["reference"] == "goal"}
        assert sorted(site for _, site in carried) == [0, 1, 2, 3]
        assert len(carried) == 4  # one slot per box
        yaws = {s["transform"]["yaw"] for s in segments if s["reference"] == "goal"}
        assert len(yaws) == 1  # the slots move with one pallet
        assert segments[-1]["end_stage"] == "settled"
    assert verify_store(out) == []


def test_sort_replays_a_source_whose_boxes_go_to_the_same_tables(tmp_path: Path) -> None:
    sources, out = tmp_path / "sources.sqlite", tmp_path / "generated.sqlite"
    collect(sources, 6, "sort")
    task = load_task("sort")

    def keys(store: Path) -> dict[str, tuple[float, ...]]:
        with Store.open(store, writer=False) as reader:
            return {
                t.trial_id: task.source_key([(t.goal or {})[n] for n in task.goal_names])
                for t in reader.trials()
            }

    source_keys = keys(sources)
    generate(sources, out, 4, 7, "D0", "sort")
    attempt_keys, matched = keys(out), 0
    for trial_id, payload in generation_events(out).items():
        if attempt_keys[trial_id] not in source_keys.values():
            continue  # no source sorted its kinds in this order: any source is replayed
        matched += 1
        assert source_keys[payload["source_trial_id"]] == attempt_keys[trial_id]
        assert payload["accepted"] and payload["recheck"] == RECHECK_HELD, payload["reason"]
        carried = {(s["box"], s["site"]) for s in payload["segments"] if s["reference"] == "goal"}
        tables = attempt_keys[trial_id]
        assert carried == {(box, int(tables[box])) for box in range(4)}
    assert matched >= 1
