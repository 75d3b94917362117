"""How far a trial got: stages read from real expert frames cut short at each step of the
task, and the definitions on hand-made holds."""

from __future__ import annotations

import csv
import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from numpy.typing import NDArray

from tests.audit import builders as b
from tests.audit.conftest import ExpertStores, expert_trials
from workcell.audit.run import AuditResult, run_audit
from workcell.audit.store_source import StoreSource
from workcell.audit.task_stages import (
    LIFT_M,
    TASK_STAGES,
    StageFrames,
    Zone,
    at_least,
    holds_from_sql,
    session_zone,
    stage_counts,
    stage_frames,
    stage_reached,
    started_conditions,
    trial_zone,
)
from workcell.audit.write import write_outputs
from workcell.record import Store

ZONE = Zone(center=(1.6, 1.9), size=(0.7, 0.7))
BELT = (0.0, 1.0, 0.8)


def _boxes(box: int, x: float, y: float, z: float) -> str:
    return json.dumps([[box, "active", x, y, z, 1.0, 0.0, 0.0, 0.0]])


def _rows(*frames: tuple[int, int, int, tuple[float, float, float]]) -> list[tuple[object, ...]]:
    """(contact_l, contact_r, attached, box position) per frame, box 0."""
    return [
        (i, contact_l, contact_r, attached, _boxes(0, *position))
        for i, (contact_l, contact_r, attached, position) in enumerate(frames)
    ]


def test_each_stage_from_hand_made_frames() -> None:
    x, y, z = BELT
    assert stage_reached(stage_frames([]), ZONE, 0) == "none"
    assert stage_reached(stage_frames(_rows((-1, -1, -1, BELT))), ZONE, 0) == "none"
    assert stage_reached(stage_frames(_rows((0, -1, -1, BELT))), ZONE, 0) == "touched"
    assert stage_reached(stage_frames(_rows((0, 0, 0, BELT))), ZONE, 0) == "grasped"
    lifted = _rows((0, 0, 0, BELT), (0, 0, 0, (x, y, z + LIFT_M)))
    assert stage_reached(stage_frames(lifted), ZONE, 0) == "lifted"
    almost = _rows((0, 0, 0, BELT), (0, 0, 0, (x, y, z + LIFT_M - 0.01)))
    assert stage_reached(stage_frames(almost), ZONE, 0) == "grasped"
    over = _rows((0, 0, 0, BELT), (0, 0, 0, (1.6 + 0.34, 1.9 - 0.34, z + 0.2)))
    assert stage_reached(stage_frames(over), ZONE, 0) == "over_zone"
    beside = _rows((0, 0, 0, BELT), (0, 0, 0, (1.6 + 0.36, 1.9, z)))
    assert stage_reached(stage_frames(beside), ZONE, 0) == "grasped"
    # a box over the zone that nobody holds (pushed, or falling) is not carried there
    pushed = _rows((0, -1, -1, (1.6, 1.9, 0.63)))
    assert stage_reached(stage_frames(pushed), ZONE, 0) == "touched"
    assert stage_reached(stage_frames([]), ZONE, 1) == "delivered"


def test_a_new_hold_measures_its_lift_from_where_it_began() -> None:
    x, y, z = BELT
    # held, let go at +4 cm, caught again at +4 cm and raised 4 cm more: never 5 cm in a hold
    regrasped = _rows(
        (0, 0, 0, BELT),
        (0, 0, 0, (x, y, z + 0.04)),
        (0, 0, -1, (x, y, z + 0.04)),
        (0, 0, 0, (x, y, z + 0.04)),
        (0, 0, 0, (x, y, z + 0.08)),
    )
    assert stage_reached(stage_frames(regrasped), ZONE, 0) == "grasped"
    # a different box in the next frame starts a hold of its own
    other = [
        (0, 0, 0, 0, _boxes(0, x, y, z)),
        (1, 1, 1, 1, _boxes(1, x, y, z + 0.06)),
        (2, 1, 1, 1, _boxes(1, x, y, z + 0.07)),
    ]
    assert stage_reached(stage_frames(other), ZONE, 0) == "grasped"


def test_unreadable_grasp_signals_cannot_raise_the_stage() -> None:
    rows: list[tuple[object, ...]] = [
        (0, None, "", float("nan"), None),
        (1, "x", -1, 0, "not json"),
        (2, -1, -1, 0, json.dumps([[3, "active", 0.0, 0.0, 0.0]])),  # holds a box not listed
        (3, -1, -1, 0, json.dumps([[0, "active", float("nan"), 0.0, 0.0]])),
    ]
    frames = stage_frames(rows)
    assert frames.holds == ()
    # the attached signal itself says a box was held, even without a readable pose
    assert stage_reached(frames, ZONE, 0) == "grasped"
    assert stage_reached(stage_frames(rows[:1]), ZONE, None) == "none"


def test_holds_read_inside_sqlite_fall_back_to_the_whole_list() -> None:
    """SQLite extracts the entry at the held box's position; an entry of another box there
    (a list out of order) sends that frame to the whole-list reader."""
    x, y, z = BELT
    out_of_order = json.dumps([[1, "active", 9.0, 9.0, 9.0], [0, "active", x, y, z + 0.06]])
    read: list[int] = []

    def boxes_of(frame_index: int) -> str | None:
        read.append(frame_index)
        return out_of_order

    rows = [(4, 0, json.dumps([0, x, y, z])), (5, 0, json.dumps([1, 9.0, 9.0, 9.0]))]
    frames = holds_from_sql((1, 1), rows, boxes_of)
    assert read == [5]
    assert [(h.frame_index, h.z) for h in frames.holds] == [(4, z), (5, z + 0.06)]
    assert stage_reached(frames, ZONE, 0) == "lifted"
    assert holds_from_sql((1, 0), [], boxes_of) == StageFrames(True, False, ())
    assert stage_reached(holds_from_sql((0, 0), [], boxes_of), ZONE, None) == "none"


def test_the_zone_comes_from_the_session_and_moves_with_the_trial() -> None:
    assert session_zone({}) == ZONE
    configured = {"world": {"target": {"center": [1.0, 2.0], "zone": [0.4, 0.5]}}}
    assert session_zone(configured) == Zone((1.0, 2.0), (0.4, 0.5))
    assert session_zone({"world": {"target": {"center": "far"}}}) == ZONE
    moved = trial_zone(ZONE, {"target_center": [1.7, 1.8]})
    assert moved == Zone((1.7, 1.8), (0.7, 0.7))
    assert trial_zone(ZONE, None) == ZONE
    payload = json.dumps({"conditions": {"target_center": [1.7, 1.8]}})
    assert started_conditions(payload) == {"target_center": [1.7, 1.8]}
    assert started_conditions("[1, 2]") == {} and started_conditions("{") == {}


def test_counts_name_every_stage_and_reached_includes_the_later_ones() -> None:
    counts = stage_counts(["delivered", "none", "lifted", "delivered"])
    assert list(counts) == list(TASK_STAGES)
    assert counts["delivered"] == 2 and counts["touched"] == 0
    reached = at_least(counts)
    assert reached == {
        "none": 4,
        "touched": 3,
        "grasped": 3,
        "lifted": 3,
        "over_zone": 2,
        "delivered": 2,
    }


def _audited(path: Path) -> AuditResult:
    source = StoreSource(path)
    try:
        return run_audit(source)
    finally:
        source.close()


def _first(mask: NDArray[np.bool_]) -> int:
    hits = np.flatnonzero(mask)
    assert len(hits), "the expert trial never reaches this step"
    return int(hits[0])


def _held_positions(frames: dict[str, NDArray[Any]]) -> NDArray[np.float64]:
    """The held box's x, y, z in every frame (NaN where none is held)."""
    out = np.full((len(frames["attached"]), 3), np.nan)
    for i, (attached, boxes) in enumerate(zip(frames["attached"], frames["boxes"], strict=True)):
        for entry in json.loads(boxes):
            if attached >= 0 and entry[0] == attached:
                out[i] = entry[2:5]
    return out


def test_an_expert_trial_cut_short_at_each_step_reads_as_that_stage(
    expert_stores: ExpertStores, tmp_path: Path
) -> None:
    session, wins, _ = expert_trials(expert_stores)
    frames = wins[0]
    touch = _first((frames["contact_l"] >= 0) | (frames["contact_r"] >= 0))
    grasp = _first(frames["attached"] >= 0)
    held = _held_positions(frames)
    lift = _first(held[:, 2] - held[grasp, 2] >= LIFT_M)
    over = _first(
        (np.abs(held[:, 0] - ZONE.center[0]) <= 0.35)
        & (np.abs(held[:, 1] - ZONE.center[1]) <= 0.35)
    )
    assert 0 < touch <= grasp < lift < over
    cuts = {
        "none": (min(touch, grasp), "interrupted"),
        "grasped": (grasp + 1, "interrupted"),
        "lifted": (lift + 1, "timeout"),
        "over_zone": (len(frames["t_sim"]), "timeout"),
        "delivered": (len(frames["t_sim"]), "success"),
    }
    if touch < grasp:
        cuts["touched"] = (touch + 1, "interrupted")
    path = tmp_path / "cut.sqlite"
    ids: dict[str, str] = {}
    with Store.open(path, writer=True) as store:
        session_id = store.create_session(b.session_info(session))
        for stage, (n, outcome) in cuts.items():
            reason = "application_quit" if outcome == "interrupted" else None
            trial = b.truncated(frames, n)
            ids[stage] = b.write_trial(
                store, session_id, trial, outcome, interruption_reason=reason
            )
        store.end_session(session_id)
    result = _audited(path)
    assert {t.trial_id: t.task_stage for t in result.trials} == {
        trial_id: stage for stage, trial_id in ids.items()
    }
    written = write_outputs(result, tmp_path / "audit")
    with written["trials.csv"].open(newline="") as file:
        column = {row["trial_id"]: row["stage_reached"] for row in csv.DictReader(file)}
    assert column == {trial_id: stage for stage, trial_id in ids.items()}
    summary = json.loads(written["summary.json"].read_text())["task_stages"]
    assert summary["definition_version"] == "1"
    assert summary["ended_at"] == {s: int(s in cuts) for s in TASK_STAGES}
    assert summary["reached"]["grasped"] == len(cuts) - 1 - ("touched" in cuts)
    report = written["report.html"].read_text()
    assert "How far trials got" in report


@pytest.mark.parametrize("shifted", [False, True])
def test_a_recorded_session_reads_its_trials_zone(
    expert_stores: ExpertStores, shifted: bool
) -> None:
    """The audit puts each trial's zone where its trial_started event says the target was,
    so an expert that carried the box to a moved target was over the zone."""
    source = StoreSource(expert_stores.skilled)
    try:
        ids = [row.trial_id for row in source.trials()]
        conditions = source.trial_conditions(ids)
        frames = source.stage_frames(ids)
        sessions = source.sessions()
    finally:
        source.close()
    assert len(conditions) == len(frames) > 0
    for trial_id, recorded in conditions.items():
        zone = trial_zone(sessions[0].zone, recorded)
        assert zone.center == tuple(recorded["target_center"])  # type: ignore[arg-type]
        if shifted:  # the same frames judged against a zone 2 m away: never over it
            zone = Zone((zone.center[0] + 2.0, zone.center[1]), zone.size)
            assert stage_reached(frames[trial_id], zone, 0) == "lifted"
        else:
            assert stage_reached(frames[trial_id], zone, 0) == "over_zone"


def test_a_boxes_cell_that_is_not_json_is_read_without_sqlite(
    expert_stores: ExpertStores, tmp_path: Path
) -> None:
    """One tampered ``boxes`` cell makes SQLite refuse its JSON query; the trial is read
    row by row instead and still gets its stage."""
    session, wins, _ = expert_trials(expert_stores)
    frames = {k: np.array(v, copy=True) for k, v in wins[0].items()}
    grasp = _first(frames["attached"] >= 0)
    frames["boxes"][grasp + 2] = "{not json"
    path = tmp_path / "tampered.sqlite"
    with Store.open(path, writer=True) as store:
        session_id = store.create_session(b.session_info(session))
        trial_id = b.write_trial(store, session_id, frames, "timeout")
        store.end_session(session_id)
    (trial,) = _audited(path).trials
    assert trial.trial_id == trial_id and trial.task_stage == "over_zone"
