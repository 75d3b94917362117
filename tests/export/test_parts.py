"""The export's parts on small inputs: options, inclusion, boxes, statistics, files."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pyarrow as pa  # type: ignore[import-untyped, unused-ignore]
import pytest

from workcell.errors import ConfigError
from workcell.export.boxes import box_feature_names, parse_boxes
from workcell.export.episode_data import next_commands
from workcell.export.lerobot_files import DataFiles
from workcell.export.lerobot_layout import CHUNKS_SIZE, FileCursor
from workcell.export.options import ExportOptions, ImageSize, parse_cameras
from workcell.export.selection import decide
from workcell.export.stats import aggregate, image_stats, vector_stats
from workcell.record.entries import AnnotationRecord, StoredMetrics, TrialRecord


def test_image_size_and_cameras() -> None:
    assert ImageSize.parse("64x48") == ImageSize(64, 48)
    assert str(ImageSize.parse(" 320X240 ")) == "320x240"
    for text in ("64", "64x47", "0x48", "axb"):
        with pytest.raises(ConfigError, match=f"--size {text!r}|--size {text}"):
            ImageSize.parse(text)
    assert parse_cameras("wrist_r_cam, head_cam,head_cam") == ("wrist_r_cam", "head_cam")
    with pytest.raises(ConfigError, match="name one or more of"):
        parse_cameras(",")
    with pytest.raises(ConfigError, match="must be distinct names"):
        ExportOptions(cameras=("head_cam", "head_cam"))


def _trial(outcome: str, included: bool, reason: str | None = None) -> TrialRecord:
    return TrialRecord(
        session_id="s",
        trial_id="t",
        trial_index=0,
        mode="collection",
        round=None,
        level=None,
        required_boxes=1,
        time_limit_s=120.0,
        outcome=outcome,
        interruption_reason="operator_stop" if outcome == "interrupted" else None,
        elapsed_s=1.0,
        completion_time_s=None,
        boxes_delivered=0,
        score=0,
        n_frames=10,
        metrics=StoredMetrics(),
        quality_flags=(),
        included=included,
        exclusion_reason=reason,
        trial_seed=1,
        started_wall=0.0,
        ended_wall=1.0,
    )


def _review(kind: str, at: float) -> AnnotationRecord:
    return AnnotationRecord(f"a{at}", "t", kind, f"{kind} at {at}", "ann", at)


def test_inclusion_follows_the_latest_reviewer_decision() -> None:
    assert decide(_trial("success", True), []).included
    excluded = decide(_trial("timeout", False, "low hz"), [])
    assert (excluded.included, excluded.reason) == (False, "low hz")
    reviews = [_review("exclude", 1.0), _review("note", 3.0), _review("include", 2.0)]
    ordered = sorted(reviews, key=lambda a: a.at_wall)
    decision = decide(_trial("success", False), ordered)
    assert decision.included and decision.review == reviews[2]
    last = decide(_trial("success", True), [*ordered, _review("exclude", 4.0)])
    assert (last.included, last.reason) == (False, "excluded by reviewer ann: exclude at 4.0")


def test_an_interrupted_trial_is_never_included() -> None:
    decision = decide(_trial("interrupted", True), [_review("include", 1.0)])
    assert not decision.included
    assert decision.reason == "incomplete: interrupted (operator_stop)"  # as the audit says


def test_boxes_and_deliveries() -> None:
    def frame(*states: str) -> str:
        return json.dumps([[i, s, i, 0, 1, 1, 0, 0, 0] for i, s in enumerate(states)])

    column = [
        frame("active", "parked"),
        frame("delivered", "active"),
        frame("delivered", "delivered"),
        frame("parked", "delivered"),
    ]
    track = parse_boxes(column, 2)
    assert track.deliveries().tolist() == [0.0, 1.0, 1.0, 0.0]
    features = track.features()
    assert features.shape == (4, 16)
    names = box_feature_names(2)
    assert features[1, names.index("box0_state")] == 2.0
    assert features[0, names.index("box1_x")] == 1.0
    with pytest.raises(Exception, match="lists 2 boxes where the session's pool has 3"):
        parse_boxes(column, 3)


def test_actions_are_the_next_recorded_commands() -> None:
    recorded = np.arange(8.0).reshape(4, 2)
    assert next_commands(recorded).tolist() == [[2, 3], [4, 5], [6, 7], [6, 7]]
    assert next_commands(recorded[:0]).shape == (0, 2)


def test_aggregated_stats_equal_stats_of_all_rows() -> None:
    rng = np.random.default_rng(0)
    parts = [rng.normal(i, 1 + i, size=(n, 3)) for i, n in enumerate((50, 7, 130))]
    merged = aggregate([vector_stats(p) for p in parts])
    direct = vector_stats(np.concatenate(parts))
    for name in ("min", "max", "mean", "std", "count"):
        assert np.allclose(merged[name], direct[name]), name
    scalar = vector_stats(np.array([True, False, False, True]))
    assert scalar["mean"].tolist() == [0.5] and scalar["count"].tolist() == [4.0]
    images = [np.full((8, 8, 3), 255, np.uint8), np.zeros((8, 8, 3), np.uint8)]
    pictures = image_stats(images)
    assert pictures["mean"].shape == (3, 1, 1)
    assert np.allclose(pictures["mean"], 0.5) and pictures["count"].tolist() == [2.0]


def test_data_files_roll_over_at_their_limit(tmp_path: Path) -> None:
    files = DataFiles(tmp_path, limit_mb=1e-4)  # about 100 bytes
    table = pa.table({"x": pa.array(np.arange(20), pa.int64())})
    assert files.write(table) == (0, 0)
    assert files.write(table) == (0, 1)
    files.close()
    assert sorted(p.name for p in (tmp_path / "data/chunk-000").iterdir()) == [
        "file-000.parquet",
        "file-001.parquet",
    ]
    cursor = FileCursor(file_index=CHUNKS_SIZE - 1)
    cursor.advance()
    assert (cursor.chunk_index, cursor.file_index) == (1, 0)
