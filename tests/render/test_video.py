"""VideoWriter: H.264 MP4 files that PyAV reads back with the frames written."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import av
import numpy as np
import pytest
from numpy.typing import NDArray

from workcell.errors import RenderError
from workcell.render import VideoWriter

WIDTH, HEIGHT = 160, 120


def _frame(i: int) -> NDArray[np.uint8]:
    """Red left half, blue right half, and a bright bar that moves with ``i``."""
    frame = np.zeros((HEIGHT, WIDTH, 3), dtype=np.uint8)
    frame[:, : WIDTH // 2, 0] = 220
    frame[:, WIDTH // 2 :, 2] = 220
    frame[:, (8 * i) % WIDTH : (8 * i) % WIDTH + 8] = 255
    return frame


def _read(path: Path) -> tuple[list[NDArray[np.uint8]], av.VideoStream]:
    with av.open(str(path)) as container:
        stream = container.streams.video[0]
        frames = [
            np.asarray(f.to_ndarray(format="rgb24"), dtype=np.uint8)
            for f in container.decode(stream)
        ]
    return frames, stream


def test_writes_an_mp4_with_every_frame(tmp_path: Path) -> None:
    path = tmp_path / "nested" / "clip.mp4"
    with VideoWriter(path, WIDTH, HEIGHT, fps=20) as video:
        for i in range(12):
            video.write(_frame(i))
        assert video.frame_count == 12
    frames, stream = _read(path)
    assert len(frames) == 12
    assert (stream.width, stream.height) == (WIDTH, HEIGHT)
    assert stream.codec_context.name == "h264"
    assert stream.codec_context.pix_fmt == "yuv420p"
    assert stream.average_rate == Fraction(20)


def test_colours_survive_encoding(tmp_path: Path) -> None:
    path = tmp_path / "colours.mp4"
    with VideoWriter(path, WIDTH, HEIGHT, fps=10) as video:
        for _ in range(3):
            video.write(_frame(0))
    decoded = _read(path)[0][0].astype(float)
    left, right = decoded[60, 40], decoded[60, 120]
    assert left[0] > 150 > left[2], "left half should stay red (RGB, not BGR)"
    assert right[2] > 150 > right[0], "right half should stay blue"
    assert np.abs(decoded - _frame(0)).mean() < 12.0


@pytest.mark.parametrize(("width", "height"), [(161, 120), (160, 119)])
def test_odd_size_is_rejected_with_a_hint(tmp_path: Path, width: int, height: int) -> None:
    with pytest.raises(RenderError, match="even size"):
        VideoWriter(tmp_path / "odd.mp4", width, height)


def test_frame_of_the_wrong_shape_is_rejected(tmp_path: Path) -> None:
    with VideoWriter(tmp_path / "clip.mp4", WIDTH, HEIGHT) as video:
        with pytest.raises(RenderError, match=r"\(120, 160, 3\)"):
            video.write(np.zeros((HEIGHT, WIDTH + 2, 3), dtype=np.uint8))
        with pytest.raises(RenderError, match="uint8"):
            video.write(np.zeros((HEIGHT, WIDTH, 3), dtype=np.float32))


def test_close_finalises_once(tmp_path: Path) -> None:
    video = VideoWriter(tmp_path / "clip.mp4", WIDTH, HEIGHT, fps=Fraction(30000, 1001))
    video.write(_frame(0))
    video.close()
    video.close()
    with pytest.raises(RenderError, match="closed"):
        video.write(_frame(1))
    assert len(_read(tmp_path / "clip.mp4")[0]) == 1


def test_invalid_fps_is_rejected(tmp_path: Path) -> None:
    with pytest.raises(RenderError, match="fps"):
        VideoWriter(tmp_path / "clip.mp4", WIDTH, HEIGHT, fps=0)


def test_long_clip_of_noise_keeps_every_frame(tmp_path: Path) -> None:
    """More frames than the encoder's look-ahead, with content that changes every frame:
    packets then leave the encoder while frames are still being written."""
    path = tmp_path / "noise.mp4"
    rng = np.random.default_rng(0)
    with VideoWriter(path, WIDTH, HEIGHT, fps=30) as video:
        for _ in range(90):
            video.write(rng.integers(0, 256, (HEIGHT, WIDTH, 3), dtype=np.uint8))
    frames, stream = _read(path)
    assert len(frames) == 90
    assert stream.average_rate == Fraction(30)
