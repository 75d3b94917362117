"""The LeRobot v3.0 export of real recorded trials, read back with pyarrow."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow.parquet as pq  # type: ignore[import-untyped, unused-ignore]
import pytest

from tests.export.stores import Stores
from workcell.export.boxes import box_feature_names
from workcell.export.features import ACTION_NAMES, STATE_NAMES, column_matrix
from workcell.export.lerobot_layout import DATA_PATH, EPISODES_PATH, VIDEO_PATH
from workcell.record.store import Store

FPS = 20
TIMESTAMP_TOLERANCE = 1e-4
STAT_NAMES = {"min", "max", "mean", "std", "count", "q01", "q10", "q50", "q90", "q99"}


def info(root: Path) -> dict[str, Any]:
    loaded: dict[str, Any] = json.loads((root / "meta/info.json").read_text())
    return loaded


def data(root: Path) -> dict[str, Any]:
    table = pq.read_table(root / DATA_PATH.format(chunk_index=0, file_index=0))
    columns: dict[str, Any] = table.to_pydict()
    return columns


def episodes(root: Path) -> list[dict[str, Any]]:
    rows: list[dict[str, Any]] = pq.read_table(
        root / EPISODES_PATH.format(chunk_index=0, file_index=0)
    ).to_pylist()
    return rows


def provenance(root: Path) -> list[dict[str, Any]]:
    rows: list[dict[str, Any]] = pq.read_table(
        root / "meta/workcell_provenance.parquet"
    ).to_pylist()
    return rows


def test_info_describes_a_v30_dataset(lerobot_dir: Path) -> None:
    meta = info(lerobot_dir)
    assert meta["codebase_version"] == "v3.0"
    assert meta["fps"] == FPS
    assert meta["data_path"] == "data/chunk-{chunk_index:03d}/file-{file_index:03d}.parquet"
    assert meta["video_path"] is None  # no cameras asked for
    features = meta["features"]
    assert features["observation.state"]["names"] == list(STATE_NAMES)
    assert features["observation.state"]["shape"] == [39]
    assert features["action"]["names"] == list(ACTION_NAMES)
    assert features["action"]["shape"] == [23]
    # every box, then the task's goal (the delivery zone's centre), then both as the robot
    # sees them
    names = features["observation.environment_state"]["names"]
    assert names[:34] == [*box_feature_names(4), "goal_x", "goal_y"]
    assert names[34:43] == [
        "box0_in_base_x", "box0_in_base_y", "box0_in_base_yaw",
        "box0_from_tcp_l_x", "box0_from_tcp_l_y", "box0_from_tcp_l_z",
        "box0_from_tcp_r_x", "box0_from_tcp_r_y", "box0_from_tcp_r_z",
    ]  # fmt: skip
    assert names[-2:] == ["goal_in_base_x", "goal_in_base_y"] and len(names) == 34 + 36 + 2
    for key in ("next.reward", "timestamp"):
        assert features[key] == {"dtype": "float32", "shape": [1], "names": None}
    for key in ("next.done", "next.success"):
        assert features[key]["dtype"] == "bool"
    for key in ("frame_index", "episode_index", "index", "task_index"):
        assert features[key]["dtype"] == "int64"
    for name, feature in features.items():
        assert "/" not in name
        assert all("/" not in n for n in feature["names"] or [])
    assert meta["total_episodes"] == 2  # the reviewer excluded one, the interrupted is out
    assert meta["splits"] == {"train": "0:2"}


def test_data_rows_match_the_features_and_the_totals(lerobot_dir: Path) -> None:
    meta = info(lerobot_dir)
    table = pq.read_table(lerobot_dir / DATA_PATH.format(chunk_index=0, file_index=0))
    assert table.num_rows == meta["total_frames"]
    assert table.column_names == [k for k, f in meta["features"].items() if f["dtype"] != "video"]
    for key in ("observation.state", "action", "observation.environment_state"):
        assert table.schema.field(key).type.list_size == meta["features"][key]["shape"][0]
    columns = data(lerobot_dir)
    assert columns["index"] == list(range(meta["total_frames"]))
    tasks = pq.read_table(lerobot_dir / "meta/tasks.parquet").to_pydict()
    assert set(columns["task_index"]) <= set(tasks["task_index"])
    assert tasks["task"] == ["Carry the box from the conveyor to the delivery table."]


def test_each_episode_is_contiguous_with_timestamps_one_frame_apart(lerobot_dir: Path) -> None:
    columns = data(lerobot_dir)
    episode_index = np.array(columns["episode_index"])
    for row in episodes(lerobot_dir):
        start, stop = row["dataset_from_index"], row["dataset_to_index"]
        assert stop - start == row["length"]
        assert np.all(episode_index[start:stop] == row["episode_index"])
        assert columns["frame_index"][start:stop] == list(range(row["length"]))
        stamps = np.array(columns["timestamp"][start:stop], dtype=np.float64)
        assert stamps[0] == 0.0
        assert np.allclose(np.diff(stamps), 1 / FPS, atol=TIMESTAMP_TOLERANCE)
        assert row["tasks"] == ["Carry the box from the conveyor to the delivery table."]
        assert row["data/chunk_index"] == 0 and row["data/file_index"] == 0
        for key in ("observation.state", "action", "next.reward", "index"):
            assert {f"stats/{key}/{s}" for s in STAT_NAMES} <= set(row)


def test_rows_hold_the_recorded_frames_and_the_next_command(
    lerobot_dir: Path, recorded: Stores
) -> None:
    columns = data(lerobot_dir)
    trial_id = provenance(lerobot_dir)[0]["trial_id"]
    with Store.open(recorded.mixed, writer=False) as store:
        frames = store.frames(trial_id)
    n = len(frames["t_sim"])
    state = np.array(columns["observation.state"][:n])
    action = np.array(columns["action"][:n])
    assert np.array_equal(state, column_matrix(frames, STATE_NAMES).astype(np.float32))
    commands = column_matrix(frames, ACTION_NAMES).astype(np.float32)
    assert np.array_equal(action[:-1], commands[1:])  # the command given after frame t
    assert np.array_equal(action[-1], commands[-1])


def test_rewards_and_ends(lerobot_all_dir: Path) -> None:
    columns = data(lerobot_all_dir)
    reward = np.array(columns["next.reward"])
    done = np.array(columns["next.done"])
    success = np.array(columns["next.success"])
    for row, origin in zip(episodes(lerobot_all_dir), provenance(lerobot_all_dir), strict=True):
        rows = slice(row["dataset_from_index"], row["dataset_to_index"])
        assert done[rows].tolist() == [False] * (row["length"] - 1) + [True]
        won = origin["outcome"] == "success"
        assert success[rows].tolist() == [False] * (row["length"] - 1) + [won]
        assert reward[rows].sum() == float(won)
        assert reward[rows][-1] == float(won)  # a success ends at its delivery frame


def test_stats_cover_every_feature(lerobot_dir: Path) -> None:
    meta = info(lerobot_dir)
    stats = json.loads((lerobot_dir / "meta/stats.json").read_text())
    assert set(stats) == set(meta["features"])
    state = stats["observation.state"]
    assert set(state) == STAT_NAMES
    assert state["count"] == [meta["total_frames"]]
    assert len(state["mean"]) == 39
    assert np.all(np.array(state["min"]) <= np.array(state["mean"]))
    columns = data(lerobot_dir)
    values = np.array(columns["observation.state"], dtype=np.float64)
    assert np.allclose(state["mean"], values.mean(axis=0), atol=1e-6)
    assert np.allclose(state["std"], values.std(axis=0), atol=1e-6)


def test_provenance_sidecar_keeps_the_four_layers(
    lerobot_dir: Path, lerobot_all_dir: Path, recorded: Stores
) -> None:
    with Store.open(recorded.mixed, writer=False) as store:
        trials = {t.trial_id: t for t in store.trials()}
    default = provenance(lerobot_dir)
    assert [p["episode_index"] for p in default] == [0, 1]
    assert {p["outcome"] for p in default} == {"success", "timeout"}
    everything = provenance(lerobot_all_dir)
    assert len(everything) == len(trials)
    for row in everything:
        trial = trials[row["trial_id"]]
        assert row["session_id"] == trial.session_id
        assert row["outcome"] == trial.outcome
        assert row["score"] == trial.score
        assert row["n_frames"] == trial.n_frames
        assert row["quality_flags"] == list(trial.quality_flags)
    by_outcome = {row["outcome"]: row for row in everything if row["outcome"] != "success"}
    interrupted = by_outcome["interrupted"]
    assert interrupted["interruption_reason"] == "application_quit"
    assert interrupted["included"] is False
    reviewed = [row for row in everything if row["review_kind"] == "exclude"]
    assert len(reviewed) == 1
    assert reviewed[0]["included"] is False and reviewed[0]["recorded_included"] is True
    assert (
        reviewed[0]["exclusion_reason"]
        == "excluded by reviewer tests: operator bumped the conveyor"
    )
    assert interrupted["exclusion_reason"] == "incomplete: interrupted (application_quit)"
    document = json.loads((lerobot_all_dir / "meta/workcell_provenance.json").read_text())
    assert document["selection"]["include_all"] is True
    assert len(document["sessions"]) == 3
    assert [e["trial_id"] for e in document["episodes"]] == [r["trial_id"] for r in everything]


def test_videos_have_one_frame_per_row(lerobot_video_dir: Path) -> None:
    av = pytest.importorskip("av")
    meta = info(lerobot_video_dir)
    feature = meta["features"]["observation.images.head_cam"]
    assert feature["dtype"] == "video"
    assert feature["shape"] == [48, 64, 3]
    assert feature["info"]["video.fps"] == FPS
    rows = episodes(lerobot_video_dir)
    for camera in ("head_cam", "wrist_l_cam"):
        key = f"observation.images.{camera}"
        path = lerobot_video_dir / VIDEO_PATH.format(video_key=key, chunk_index=0, file_index=0)
        with av.open(str(path)) as container:
            decoded = list(container.decode(video=0))
        assert len(decoded) == meta["total_frames"]
        assert (decoded[0].width, decoded[0].height) == (64, 48)
        times = np.array([float(frame.time) for frame in decoded])
        assert np.allclose(times, np.arange(len(times)) / FPS, atol=TIMESTAMP_TOLERANCE)
        for row in rows:
            start, stop = row[f"videos/{key}/from_timestamp"], row[f"videos/{key}/to_timestamp"]
            assert start == pytest.approx(row["dataset_from_index"] / FPS)
            assert stop - start == pytest.approx(row["length"] / FPS)
    stats = json.loads((lerobot_video_dir / "meta/stats.json").read_text())
    image = stats["observation.images.head_cam"]
    assert np.array(image["mean"]).shape == (3, 1, 1)
    assert 0.0 <= np.array(image["min"]).min() <= np.array(image["max"]).max() <= 1.0
