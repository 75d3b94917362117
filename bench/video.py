"""Video keyframe interval: random-access decode time and file size (issue 14).

A LeRobot data loader decodes one frame per camera per sample, at a random timestamp: it
opens the file, seeks to the keyframe at or before the timestamp and decodes every frame
from there to it (``decode_video_frames_torchvision`` with ``backend="pyav"``; each
decoded frame is converted to RGB). So the keyframe interval bounds the work per sample.

The frames are a real expert trial's ``head_cam`` images, rendered from its recorded states
at the export's default size (320x240) and the recording's default (128x128). Each is
encoded by :class:`workcell.render.VideoWriter` once per keyframe interval; the baseline is
libx264's own default (250 frames, plus scene cuts: what the writer used before). Printed,
per size and interval: keyframes, file size, encoding time per frame and the median time
to decode one random frame (the same random frames for every interval) with PyAV as
LeRobot's pyav backend does and, when the learn extra is installed, with LeRobot's own
``decode_video_frames_torchvision``; each also as a ratio to the baseline of that size.

Run: ``.venv/bin/python bench/video.py [--samples N] [--seed S]``.
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import io
import os
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

# MuJoCo picks its OpenGL backend when first imported (by the workcell modules below).
os.environ.setdefault("MUJOCO_GL", "egl")

import av
import numpy as np
from numpy.typing import NDArray

from workcell.cli.main import main as workcell
from workcell.export.options import ImageSize
from workcell.export.replay_world import ReplayWorld
from workcell.export.restore import RecordedStates
from workcell.export.source import session_config
from workcell.record.store import Store
from workcell.render.video import VideoWriter

CAMERA = "head_cam"
SIZES = (ImageSize(320, 240), ImageSize(128, 128))
INTERVALS: tuple[int | None, ...] = (None, 20, 10, 5, 3, 2, 1)
"""None: libx264's default (250). 20 frames is one second at the recording rate."""
FPS = 20


@dataclass(frozen=True)
class Row:
    """One keyframe interval's figures at one size."""

    interval: int | None
    keyframes: int
    size_bytes: int
    encode_s: float
    """Per frame."""
    decode_s: float
    """One random frame, median, PyAV as LeRobot's pyav backend does it (file reopened)."""
    open_s: float
    """One random frame, median, PyAV with the file kept open (a cached decoder)."""
    lerobot_s: float
    """One random frame, median, LeRobot's own decoder (NaN without the learn extra)."""


def record_trial(folder: Path, seed: int) -> Path:
    """One expert trial recorded into a new store (no cameras)."""
    store = folder / "trial.sqlite"
    argv = ["collect", "--mode", "collection", "--trials", "1", "--seed", str(seed)]
    with contextlib.redirect_stdout(io.StringIO()):  # one JSON line per trial
        code = workcell([*argv, "--store", str(store), "--json"])
    if code != 0:
        sys.exit(f"collect failed with exit status {code}")
    return store


def render_frames(store_path: Path, size: ImageSize) -> list[NDArray[np.uint8]]:
    """The trial's camera images at ``size``, rendered from its recorded states."""
    with Store.open(store_path, writer=False) as store:
        (session,) = store.sessions()
        (trial,) = store.trials()
        states = RecordedStates.from_frames(store.frames(trial.trial_id))
    world = ReplayWorld(session_config(session), size)
    try:
        return [images[CAMERA] for images in world.images(states, [CAMERA])]
    finally:
        world.close()


def encode(path: Path, frames: list[NDArray[np.uint8]], interval: int | None) -> float:
    """Seconds to encode ``frames`` into ``path``."""
    height, width = frames[0].shape[:2]
    start = time.perf_counter()
    with VideoWriter(path, width, height, FPS, keyframe_interval=interval) as writer:
        for frame in frames:
            writer.write(frame)
    return time.perf_counter() - start


def keyframes(path: Path) -> int:
    with av.open(str(path)) as container:
        count = sum(packet.is_keyframe for packet in container.demux(video=0) if packet.size)
    return count


def seek_and_decode(container: av.container.InputContainer, index: int) -> int:
    """Seek to the keyframe at or before frame ``index`` and decode (to RGB, as LeRobot
    does) every frame up to it; the index of the frame reached."""
    target = index / FPS
    stream = container.streams.video[0]
    assert stream.time_base is not None
    container.seek(int(target / stream.time_base), stream=stream, backward=True)
    reached = -1
    for frame in container.decode(stream):
        frame.to_ndarray(format="rgb24")
        reached = round((frame.time or 0.0) * FPS)
        if reached >= index:
            break
    return reached


def decode_at(path: Path, index: int) -> tuple[float, int]:
    """Seconds to get frame ``index`` as LeRobot's pyav path does (the file opened for
    each frame), and the index read."""
    start = time.perf_counter()
    with av.open(str(path)) as container:
        reached = seek_and_decode(container, index)
    return time.perf_counter() - start, reached


class OpenDecoder:
    """One file kept open across frames, as a decoder cache keeps it (LeRobot's torchcodec
    backend does; it needs FFmpeg's shared libraries, which this machine lacks)."""

    def __init__(self, path: Path) -> None:
        self.container = av.open(str(path))

    def __call__(self, index: int) -> tuple[float, int]:
        start = time.perf_counter()
        reached = seek_and_decode(self.container, index)
        return time.perf_counter() - start, reached

    def close(self) -> None:
        self.container.close()


def lerobot_decoder() -> Callable[[Path, int], float] | None:
    """LeRobot's own decoder (pyav backend), timed per frame, when the learn extra is
    installed; None otherwise."""
    try:
        from lerobot.datasets.video_utils import (  # type: ignore[import-untyped, import-not-found, unused-ignore]  # noqa: PLC0415
            decode_video_frames_torchvision,
        )
    except ImportError:
        return None

    def decode(path: Path, index: int) -> float:
        start = time.perf_counter()
        decode_video_frames_torchvision(path, [index / FPS], 1e-4, backend="pyav")
        return time.perf_counter() - start

    return decode


def measure(
    folder: Path, frames: list[NDArray[np.uint8]], samples: list[int], rng: np.random.Generator
) -> list[Row]:
    """Every interval's figures. The random frames are read interval by interval in a
    random order for each frame, so a drift in the machine's speed affects all alike."""
    lerobot = lerobot_decoder()
    paths = {interval: folder / f"g{interval}.mp4" for interval in INTERVALS}
    encoding = {interval: encode(paths[interval], frames, interval) for interval in INTERVALS}
    opened = {interval: OpenDecoder(paths[interval]) for interval in INTERVALS}
    times: dict[str, dict[int | None, list[float]]] = {
        way: {interval: [] for interval in INTERVALS} for way in ("reopen", "open", "lerobot")
    }
    for index in samples:
        for position in rng.permutation(len(INTERVALS)):
            interval = INTERVALS[position]
            for way, decode in (
                ("reopen", functools.partial(decode_at, paths[interval])),
                ("open", opened[interval]),
            ):
                seconds, read = decode(index)
                if read != index:
                    sys.exit(f"keyframe interval {interval}: asked frame {index}, read {read}")
                times[way][interval].append(seconds)
            if lerobot is not None:
                times["lerobot"][interval].append(lerobot(paths[interval], index))
    for decoder in opened.values():
        decoder.close()
    return [
        Row(
            interval=interval,
            keyframes=keyframes(paths[interval]),
            size_bytes=paths[interval].stat().st_size,
            encode_s=encoding[interval] / len(frames),
            decode_s=statistics.median(times["reopen"][interval]),
            open_s=statistics.median(times["open"][interval]),
            lerobot_s=statistics.median(times["lerobot"][interval] or [np.nan]),
        )
        for interval in INTERVALS
    ]


def report(size: ImageSize, n: int, samples: int, rows: list[Row]) -> None:
    base = rows[0]
    print(
        f"\n{CAMERA} {size}, {n} frames, {samples} random frames (median ms); ratios "
        "against libx264's default interval"
    )
    print(
        "interval  keyframes  size kB (ratio)  encode/frame (ratio)  random frame: "
        "reopened (ratio)   kept open (ratio)   LeRobot pyav (ratio)"
    )

    def cell(value: float, baseline: float, scale: float = 1e3, width: int = 8) -> str:
        return f"{value * scale:>{width}.2f} ({value / baseline:4.2f})"

    for row in rows:
        name = "default" if row.interval is None else str(row.interval)
        kilobytes = f"{row.size_bytes / 1e3:>8.0f} ({row.size_bytes / base.size_bytes:5.2f})"
        encode = cell(row.encode_s, base.encode_s, width=11)
        reopened = cell(row.decode_s, base.decode_s, width=23)
        kept_open = cell(row.open_s, base.open_s, width=12)
        lerobot = cell(row.lerobot_s, base.lerobot_s, width=15)
        print(
            f"{name:>8} {row.keyframes:>10} {kilobytes} {encode} {reopened} {kept_open} {lerobot}"
        )
    if np.isnan(base.lerobot_s):
        print("(LeRobot: not installed; make setup-learn adds it)")


def run() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    parser.add_argument("--samples", type=int, default=200, help="random frames per video")
    parser.add_argument("--seed", type=int, default=0, help="trial seed and frame choice")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as name:
        folder = Path(name)
        store = record_trial(folder, args.seed)
        rng = np.random.default_rng(args.seed)
        for size in SIZES:
            frames = render_frames(store, size)
            samples = [int(i) for i in rng.integers(0, len(frames), args.samples)]
            report(size, len(frames), len(samples), measure(folder, frames, samples, rng))


if __name__ == "__main__":
    run()
