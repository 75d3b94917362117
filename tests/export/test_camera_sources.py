"""Exports take camera images from the trials' recorded videos (``workcell collect
--cameras``) when they match, and render them otherwise; they say which, and why."""

from __future__ import annotations

import hashlib
import json
import shutil
from pathlib import Path
from typing import Any

import av
import h5py  # type: ignore[import-untyped, unused-ignore]
import numpy as np
import pytest

from tests.export.conftest import RECORDED_CAMERAS, RECORDED_SIZE
from workcell.cli.main import main
from workcell.export.camera_sources import RecordedVideo, camera_sources, recorded_videos
from workcell.export.hdf5_export import HDF5_NAME, export_hdf5
from workcell.export.lerobot_export import export_lerobot
from workcell.export.lerobot_layout import INFO_PATH, PROVENANCE_JSON_PATH, VIDEO_PATH
from workcell.export.options import ExportOptions, ImageSize
from workcell.record.store import Store
from workcell.render.video import VideoWriter, read_frames
from workcell.render.video_concat import writer_encoding

RECORDED = RECORDED_CAMERAS
FPS = 20


def _videos(store: Path) -> list[dict[str, RecordedVideo]]:
    """Each trial's recorded videos, in trial order."""
    with Store.open(store, writer=False) as reader:
        return [recorded_videos(store, reader.events(t.trial_id)) for t in reader.trials()]


def _copy(store: Path, folder: Path) -> Path:
    """The store and its media folder, copied into ``folder``."""
    folder.mkdir()
    shutil.copy(store, folder / store.name)
    shutil.copytree(store.with_name(store.name + ".media"), folder / (store.name + ".media"))
    return folder / store.name


def _packets(path: Path) -> list[bytes]:
    with av.open(str(path)) as container:
        packets = [bytes(p) for p in container.demux(video=0) if p.size]
    return packets


def _sources(document: dict[str, Any]) -> dict[tuple[int, str], dict[str, Any]]:
    return {(s["episode_index"], s["camera"]): s for s in document["camera_sources"]}


def test_lerobot_copies_the_recorded_videos(camera_store: Path, tmp_path: Path) -> None:
    out = tmp_path / "dataset"
    summary = export_lerobot(camera_store, out, ExportOptions(cameras=RECORDED))
    assert (summary.recorded_videos, summary.rendered_videos) == (4, 0)
    info = json.loads((out / INFO_PATH).read_text())
    assert info["features"]["observation.images.head_cam"]["shape"] == [48, 64, 3]
    videos = _videos(camera_store)
    for camera in RECORDED:
        exported = out / VIDEO_PATH.format(
            video_key=f"observation.images.{camera}", chunk_index=0, file_index=0
        )
        recorded = [trial[camera].path for trial in videos]
        assert _packets(exported) == _packets(recorded[0]) + _packets(recorded[1])
    document = json.loads((out / PROVENANCE_JSON_PATH).read_text())
    sources = _sources(document)
    assert len(sources) == 4 and document["image_size"] == [64, 48]
    for (episode, camera), source in sources.items():
        video = videos[episode][camera]
        assert (source["source"], source["file"], source["sha256"]) == (
            "recorded",
            video.file,
            video.sha256,
        )


def test_unrecorded_camera_is_rendered_beside_recorded_ones(
    camera_store: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "dataset"
    argv = ["export", "--format", "lerobot", "--store", str(camera_store), "--out", str(out)]
    assert main([*argv, "--cameras", "head_cam,wrist_r_cam"]) == 0
    captured = capsys.readouterr()
    assert "2 camera streams (2 episode videos from the recordings, 2 rendered)" in captured.out
    assert (
        "episode 1/2: cameras head_cam: recorded video; wrist_r_cam: rendered "
        "(not recorded with the trial)" in captured.err
    )
    sources = _sources(json.loads((out / PROVENANCE_JSON_PATH).read_text()))
    assert sources[(1, "wrist_r_cam")]["reason"] == "not recorded with the trial"
    rendered = out / VIDEO_PATH.format(
        video_key="observation.images.wrist_r_cam", chunk_index=0, file_index=0
    )
    frames = list(read_frames(rendered))
    assert len(frames) == sum(v["head_cam"].frames for v in _videos(camera_store))
    assert frames[0].shape == (48, 64, 3)


def test_recorded_and_rendered_images_show_the_same_frames(
    camera_store: Path, tmp_path: Path
) -> None:
    """Frame i of a recorded video is frame i of the trial: it matches the image rendered
    from frame i's state far better than those of the frames around it."""
    export_hdf5(camera_store, tmp_path / "recorded", ExportOptions(cameras=("head_cam",)))
    options = ExportOptions(cameras=("head_cam",), rerender=True)
    export_hdf5(camera_store, tmp_path / "rendered", options)
    images = []
    for name in ("recorded", "rendered"):
        with h5py.File(tmp_path / name / HDF5_NAME, "r") as file:
            demo = file["data/demo_0"]
            images.append(demo["obs/head_cam_image"][:].astype(float))
            (source,) = json.loads(demo.attrs["camera_sources"])
            assert source["source"] == name
    recorded, rendered = images

    def distance(a: Any, b: Any) -> Any:
        return np.abs(a - b).mean(axis=(1, 2, 3))

    same = distance(recorded, rendered)
    # H.264 at 64x48 costs several levels per pixel (the floor's slab joints and markings most)
    assert same.max() < 10.0
    after = distance(recorded[:-1], rendered[1:])  # recorded i against rendered i + 1
    before = distance(recorded[1:], rendered[:-1])  # recorded i + 1 against rendered i
    moving = np.flatnonzero(distance(rendered[1:], rendered[:-1]) > 3.0)  # i to i + 1
    assert len(moving) >= 5
    assert (same[moving] < after[moving]).all() and (same[moving + 1] < before[moving]).all()


def test_hdf5_holds_the_recorded_frames(camera_store: Path, tmp_path: Path) -> None:
    summary = export_hdf5(camera_store, tmp_path / "out", ExportOptions(cameras=RECORDED))
    assert (summary.recorded_videos, summary.rendered_videos) == (4, 0)
    videos = _videos(camera_store)
    with h5py.File(tmp_path / "out" / HDF5_NAME, "r") as file:
        for i, trial in enumerate(videos):
            for camera in RECORDED:
                stored = file[f"data/demo_{i}/obs/{camera}_image"][:]
                decoded = np.stack(list(read_frames(trial[camera].path)))
                assert np.array_equal(stored, decoded)


def test_changed_missing_or_other_size_recordings_are_rendered(
    camera_store: Path, tmp_path: Path
) -> None:
    store = _copy(camera_store, tmp_path / "copy")
    first, second = _videos(store)
    with first["head_cam"].path.open("ab") as file:
        file.write(b"\0")
    second["head_cam"].path.unlink()
    out = tmp_path / "dataset"
    summary = export_lerobot(store, out, ExportOptions(cameras=RECORDED))
    assert (summary.recorded_videos, summary.rendered_videos) == (2, 2)
    sources = _sources(json.loads((out / PROVENANCE_JSON_PATH).read_text()))
    assert "is not the file recorded (its sha256 differs)" in sources[(0, "head_cam")]["reason"]
    assert sources[(1, "head_cam")]["reason"] == f"{second['head_cam'].file} is missing"
    assert sources[(0, "wrist_l_cam")]["source"] == "recorded"
    bigger = export_lerobot(
        store, tmp_path / "bigger", ExportOptions(cameras=("wrist_l_cam",), size=ImageSize(96, 64))
    )
    assert (bigger.recorded_videos, bigger.rendered_videos) == (0, 2)
    document = json.loads((tmp_path / "bigger" / PROVENANCE_JSON_PATH).read_text())
    reasons = {s["reason"] for s in document["camera_sources"]}
    assert reasons == {"recorded at 64x48, the export is 96x64"}


def test_a_recording_of_another_encoding_is_decoded_but_not_copied(tmp_path: Path) -> None:
    path = tmp_path / "old.mp4"
    rng = np.random.default_rng(0)
    with VideoWriter(path, 64, 48, FPS, keyframe_interval=None) as writer:  # before GOP 2
        for _ in range(30):
            writer.write(rng.integers(0, 256, (48, 64, 3), dtype=np.uint8))
    digest = hashlib.sha256(path.read_bytes()).hexdigest()
    video = RecordedVideo("head_cam", "old.mp4", path, 30, digest, RECORDED_SIZE)
    options = ExportOptions(cameras=("head_cam",), size=RECORDED_SIZE)
    decoded = camera_sources({"head_cam": video}, 30, FPS, options, None)["head_cam"]
    assert decoded.recorded
    copied = camera_sources({"head_cam": video}, 30, FPS, options, writer_encoding(64, 48, FPS))
    assert not copied["head_cam"].recorded
    assert "encoded differently: other encoder settings" in copied["head_cam"].reason
    short = camera_sources({"head_cam": video}, 31, FPS, options, None)["head_cam"]
    assert short.reason == "the media event counts 30 frames, the trial 31"


def test_rerender_needs_cameras(
    camera_store: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = ["export", "--format", "hdf5", "--store", str(camera_store), "--out", str(tmp_path)]
    assert main([*argv, "--rerender"]) == 2
    assert (
        capsys.readouterr()
        .err.strip()
        .endswith("--rerender applies to camera images: give --cameras too")
    )
