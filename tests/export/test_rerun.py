"""The Rerun export: one ``.rrd`` per trial, read back with rerun 0.26's own reader
(``rerun.dataframe``), the version LeRobot 0.4 pins."""

from __future__ import annotations

import json
import os
import sqlite3
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa  # type: ignore[import-untyped, unused-ignore]
import pytest
import rerun as rr
from numpy.typing import NDArray

from tests.export.stores import Stores
from workcell.cli.main import EXIT_USAGE, main
from workcell.export.options import ExportOptions
from workcell.export.provenance import PROVENANCE_FIELDS
from workcell.export.rerun_export import PROVENANCE_NAME, export_rerun, recording_name
from workcell.export.rerun_layout import (
    APPLICATION_ID,
    BASE_ENTITY,
    BOXES_ENTITY,
    EVENT_TIMELINE,
    EVENTS_ENTITY,
    FRAME_TIMELINE,
    PROVENANCE_ENTITY,
    TCP_COLORS,
    hand_entity,
    joint_entity,
    packed_rgba,
    tcp_entity,
    trajectory_entity,
)
from workcell.record.columns import HAND_COLUMNS
from workcell.record.entries import TrialRecord
from workcell.record.store import Store
from workcell.sim.joints import JOINT_ORDER


@dataclass(frozen=True)
class Recording:
    """One ``.rrd`` file as rerun's dataframe API reads it.

    A dataframe view has one row per value of its index timeline (rows sharing a value
    are merged), so per-frame entities are read on ``frame`` and the events on ``event``.
    """

    recording: Any
    """A ``rerun.dataframe.Recording``."""

    @property
    def application_id(self) -> str:
        return str(self.recording.application_id())

    @property
    def recording_id(self) -> str:
        return str(self.recording.recording_id())

    def table(self, entity: str, *, index: str = FRAME_TIMELINE) -> Any:
        """An entity's rows in index order (``entity`` with or without the leading '/')."""
        view = self.recording.view(index=index, contents=_path(entity))
        return view.select().read_all()

    def static(self, entity: str) -> Any:
        """An entity's static row."""
        view = self.recording.view(index=FRAME_TIMELINE, contents=_path(entity))
        return view.select_static().read_all()

    def values(self, entity: str, component: str) -> NDArray[Any]:
        """A per-frame component, one value (or vector) per row."""
        column = self.table(entity).column(f"{_path(entity)}:{component}").combine_chunks()
        values = column.flatten()
        if pa.types.is_fixed_size_list(values.type):
            return np.asarray(values.flatten().to_numpy()).reshape(len(column), -1)
        return np.asarray(values.to_numpy(zero_copy_only=False))

    def index(self, entity: str, timeline: str) -> NDArray[np.int64]:
        column = self.table(entity).column(timeline).combine_chunks()
        return np.asarray(column.cast(pa.int64()).to_numpy())

    def static_fields(self, entity: str) -> dict[str, list[Any]]:
        """Every static component of ``entity`` in the file's schema, by component name,
        with its values (the reader returns no row for an empty list: [] then)."""
        path = _path(entity)
        row = self.static(entity).to_pydict()
        return {
            column.component: list(row.get(column.name, [[]])[0])
            for column in self.recording.schema().component_columns()
            if column.entity_path == path and column.is_static
        }

    def static_value(self, entity: str, component: str) -> list[Any]:
        """A static component's values, as a list (``component`` as logged: for the root's
        AnyValues the field name, else ``Archetype:field``)."""
        column = self.static(entity).column(f"{_path(entity)}:{component}")
        return list(column.to_pylist()[0])


def _path(entity: str) -> str:
    return "/" + entity.strip("/")


def read_recording(path: Path) -> Recording:
    return Recording(rr.dataframe.load_recording(str(path)))


@pytest.fixture(scope="module")
def rerun_all_dir(recorded: Stores, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The mixed store exported with --all: 2 successes (one excluded), a timeout and an
    interrupted trial."""
    out = tmp_path_factory.mktemp("rerun_all") / "recordings"
    export_rerun(recorded.mixed, out, ExportOptions(include_all=True))
    return out


@pytest.fixture(scope="module")
def trials(recorded: Stores) -> list[TrialRecord]:
    with Store.open(recorded.mixed, writer=False) as store:
        return store.trials()


@pytest.fixture(scope="module")
def recordings(rerun_all_dir: Path, trials: list[TrialRecord]) -> dict[str, Recording]:
    """Every exported recording, by trial id."""
    return {
        t.trial_id: read_recording(rerun_all_dir / recording_name(i, t.trial_id))
        for i, t in enumerate(trials)
    }


def test_one_recording_per_exported_trial(
    rerun_all_dir: Path, trials: list[TrialRecord], recordings: dict[str, Recording]
) -> None:
    names = sorted(p.name for p in rerun_all_dir.iterdir())
    expected = [recording_name(i, t.trial_id) for i, t in enumerate(trials)]
    assert names == sorted([*expected, PROVENANCE_NAME])
    for trial_id, recording in recordings.items():
        assert (recording.application_id, recording.recording_id) == (APPLICATION_ID, trial_id)
    document = json.loads((rerun_all_dir / PROVENANCE_NAME).read_text())
    assert [e["trial_id"] for e in document["episodes"]] == [t.trial_id for t in trials]
    assert document["selection"]["include_all"] is True


def test_the_rerun_0_26_cli_verifies_every_recording(rerun_all_dir: Path) -> None:
    """``rerun rrd verify`` (the viewer's own loader, version 0.26 as pinned) reads every
    file: a component of an archetype it does not know, such as rerun 0.41's
    TransformAxes3D, fails it with "Unknown archetype"."""
    assert rr.__version__.startswith("0.26.")
    cli = Path(sys.executable).with_name("rerun")
    files = sorted(str(p) for p in rerun_all_dir.glob("*.rrd"))
    command = [str(cli), "rrd", "verify", *files]
    result = subprocess.run(command, check=False, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert f"{len(files)} files verified without error" in result.stderr + result.stdout


def test_every_frame_and_joint_value_is_the_stored_one(
    recorded: Stores, trials: list[TrialRecord], recordings: dict[str, Recording]
) -> None:
    with Store.open(recorded.mixed, writer=False) as store:
        stored = {t.trial_id: store.frames(t.trial_id) for t in trials}
    for trial in trials:
        recording, frames = recordings[trial.trial_id], stored[trial.trial_id]
        n = trial.n_frames
        assert n is not None and n == len(frames["frame_index"]) > 0
        t_sim_ns = np.rint(frames["t_sim"] * 1e9).astype(np.int64)
        per_frame = [joint_entity(j) for j in JOINT_ORDER] + [hand_entity(c) for c in HAND_COLUMNS]
        per_frame += [BASE_ENTITY, BOXES_ENTITY, tcp_entity("tcp_l"), tcp_entity("tcp_r")]
        for entity in per_frame:
            assert np.array_equal(recording.index(entity, "frame"), np.arange(n)), entity
            assert np.array_equal(recording.index(entity, "t_sim"), t_sim_ns), entity
        for joint in JOINT_ORDER:
            values = recording.values(joint_entity(joint), "Scalars:scalars")
            assert np.array_equal(values, frames[f"q_{joint}"]), joint
        for column in HAND_COLUMNS:
            values = recording.values(hand_entity(column), "Scalars:scalars")
            assert np.array_equal(values, frames[column]), column
        base = recording.values(BASE_ENTITY, "Transform3D:translation")
        np.testing.assert_allclose(base[:, 0], frames["base_x"], atol=1e-5)
        np.testing.assert_allclose(base[:, 1], frames["base_y"], atol=1e-5)
        tcp = recording.values(tcp_entity("tcp_l"), "Points3D:positions")
        np.testing.assert_allclose(tcp[:, 2], frames["tcp_l_z"], atol=1e-5)
        (strip,) = recording.static_value(trajectory_entity("tcp_r"), "LineStrips3D:strips")
        np.testing.assert_allclose(np.array(strip)[:, 0], frames["tcp_r_x"], atol=1e-5)


def test_colours_are_one_per_point_and_box(
    trials: list[TrialRecord], recordings: dict[str, Recording]
) -> None:
    for trial in trials:
        recording = recordings[trial.trial_id]
        for tcp in ("tcp_l", "tcp_r"):
            colors = recording.values(tcp_entity(tcp), "Points3D:colors")
            assert colors.tolist() == [int(packed_rgba(TCP_COLORS[tcp]))] * (trial.n_frames or 0)
        boxes = recording.table(BOXES_ENTITY)
        centers = boxes.column("/world/boxes:Boxes3D:centers").to_pylist()
        colors = boxes.column("/world/boxes:Boxes3D:colors").to_pylist()
        assert [len(row) for row in colors] == [len(row) for row in centers]
        axis = recording.static_value(BASE_ENTITY, "Transform3D:axis_length")
        assert axis == [pytest.approx(0.4)]


def test_packed_rgba_is_rerun_s_colour() -> None:
    rgba = (66, 135, 245, 255)
    assert int(packed_rgba(rgba)) == rr.components.ColorBatch([rgba]).as_arrow_array()[0].as_py()


def test_boxes_have_the_trials_size(
    recorded: Stores, trials: list[TrialRecord], recordings: dict[str, Recording]
) -> None:
    with Store.open(recorded.mixed, writer=False) as store:
        events = {t.trial_id: store.events(t.trial_id) for t in trials}
    for trial in trials:
        recording = recordings[trial.trial_id]
        (started,) = [e for e in events[trial.trial_id] if e.kind == "trial_started"]
        size = np.array(started.payload["conditions"]["box_size"])
        centers = recording.table(BOXES_ENTITY).column("/world/boxes:Boxes3D:centers")
        centers = centers.to_pylist()
        half_sizes = np.array(recording.static_value(BOXES_ENTITY, "Boxes3D:half_sizes"))
        assert {len(row) for row in centers} == {len(half_sizes)}  # the pool at every frame
        np.testing.assert_allclose(half_sizes, np.tile(size / 2, (len(half_sizes), 1)), atol=1e-6)


def test_provenance_at_the_root(
    trials: list[TrialRecord], recordings: dict[str, Recording]
) -> None:
    outcomes = set()
    for trial in trials:
        recording = recordings[trial.trial_id]
        fields = recording.static_fields("/")
        assert set(fields) == set(PROVENANCE_FIELDS)
        assert fields["trial_id"] == [trial.trial_id]
        assert fields["session_id"] == [trial.session_id]
        assert fields["outcome"] == [trial.outcome]
        assert fields["interruption_reason"] == [trial.interruption_reason]
        assert fields["quality_flags"] == list(trial.quality_flags)
        assert fields["score"] == [trial.score]
        assert fields["n_frames"] == [trial.n_frames]
        (included,) = fields["included"]
        if trial.outcome == "interrupted":
            assert fields["interruption_reason"] == ["application_quit"] and not included
        outcomes.add((trial.outcome, included, fields["exclusion_reason"][0]))
        (text,) = recording.static_value(PROVENANCE_ENTITY, "TextDocument:text")
        document = json.loads(text.split("```json\n", 1)[1].split("\n```", 1)[0])
        assert [e["trial_id"] for e in document["episodes"]] == [trial.trial_id]
        assert list(document["sessions"]) == [trial.session_id]
    assert (
        "success",
        False,
        "excluded by reviewer tests: operator bumped the conveyor",
    ) in outcomes
    assert ("success", True, None) in outcomes


def test_events_are_text_logs_at_their_sim_time(
    recorded: Stores, trials: list[TrialRecord], recordings: dict[str, Recording]
) -> None:
    with Store.open(recorded.mixed, writer=False) as store:
        for trial in trials:
            events = store.events(trial.trial_id)
            recording = recordings[trial.trial_id]
            logged = recording.table(EVENTS_ENTITY, index=EVENT_TIMELINE)
            assert logged.column(EVENT_TIMELINE).to_pylist() == list(range(len(events)))
            times = logged.column("t_sim").cast(pa.int64()).to_pylist()
            assert times == [round((e.t_sim or 0.0) * 1e9) for e in events]
            texts = [row[0] for row in logged.column("/events:TextLog:text").to_pylist()]
            assert [t.split(":")[0] for t in texts] == [e.kind for e in events]
            frames = logged.column("frame").to_numpy()
            assert frames.min() >= 0 and frames.max() < (trial.n_frames or 0)
            levels = {row[0] for row in logged.column("/events:TextLog:level").to_pylist()}
            assert ("WARN" in levels) == (trial.outcome != "success")


def test_cli_exports_included_trials(
    recorded: Stores, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "out"
    argv = ["export", "--format", "rerun", "--store", str(recorded.mixed), "--out", str(out)]
    assert main(argv) == 0
    line = capsys.readouterr().out
    assert line.startswith("exported 2 episodes, ") and f"as rerun to {out}" in line
    assert len(list(out.glob("*.rrd"))) == 2


@pytest.fixture
def _keep_mujoco_gl(monkeypatch: pytest.MonkeyPatch) -> None:
    """Keep MUJOCO_GL as the other tests expect it, whatever this test does to it."""
    monkeypatch.setenv("MUJOCO_GL", os.environ.get("MUJOCO_GL", "egl"))


def _copy(source: Path, target: Path) -> Path:
    with sqlite3.connect(source) as src, sqlite3.connect(target) as dst:
        src.backup(dst)
    return target


@pytest.mark.usefixtures("_keep_mujoco_gl")
@pytest.mark.parametrize("case", ["empty", "unverified", "not_empty", "nothing_included", "camera"])
def test_bad_input_is_one_line_and_exit_2(
    case: str, recorded: Stores, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    store, out, extra = recorded.short, tmp_path / "o", []
    if case == "empty":
        store = tmp_path / "empty.sqlite"
        Store.open(store, writer=True).close()
    elif case == "unverified":
        store = _copy(recorded.short, tmp_path / "changed.sqlite")
        with sqlite3.connect(store) as conn:
            conn.execute("UPDATE frames SET base_x = base_x + 1 WHERE frame_index = 2")
    elif case == "not_empty":
        out = tmp_path
        (tmp_path / "keep.txt").write_text("mine")
    elif case == "nothing_included":
        store = _copy(recorded.short, tmp_path / "excluded.sqlite")
        with Store.open(store, writer=True) as writer:
            for trial in writer.trials():
                writer.annotate(trial.trial_id, "exclude", "not wanted", "tests")
    else:
        extra = ["--cameras", "head_cam"]
    argv = ["export", "--format", "rerun", "--store", str(store), "--out", str(out), *extra]
    capsys.readouterr()
    assert main(argv) == EXIT_USAGE
    captured = capsys.readouterr()
    lines = captured.err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("workcell: error: "), captured.err
    expected = {
        "empty": "holds no trials",
        "unverified": "fails verification (",
        "not_empty": "is not an empty folder; give a new or empty folder",
        "nothing_included": "pass --all to export trials that are not included",
        "camera": "--cameras: applies to the lerobot and hdf5 formats",
    }[case]
    assert expected in lines[0]
    if case == "not_empty":
        assert [p.name for p in out.iterdir()] == ["keep.txt"]
    else:
        assert not out.exists()
