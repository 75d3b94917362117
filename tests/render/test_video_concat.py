"""Video files joined without re-encoding, keyframe spacing and the writer's encoding."""

from __future__ import annotations

from pathlib import Path

import av
import numpy as np
import pytest
from numpy.typing import NDArray

from workcell.errors import RenderError
from workcell.render.video import KEYFRAME_INTERVAL, VideoWriter, read_frames
from workcell.render.video_concat import VideoConcatenation, probe, writer_encoding

WIDTH, HEIGHT, FPS = 64, 48, 20


def _clip(path: Path, frames: int, seed: int, **options: int | None) -> Path:
    """A clip of moving noise (every frame differs)."""
    base = np.random.default_rng(seed).integers(0, 256, (HEIGHT, WIDTH, 3), dtype=np.uint8)
    with VideoWriter(path, WIDTH, HEIGHT, FPS, **options) as writer:  # type: ignore[arg-type]
        for i in range(frames):
            writer.write(np.roll(base, 3 * i, axis=1))
    return path


def _packets(path: Path) -> list[bytes]:
    with av.open(str(path)) as container:
        packets = [bytes(p) for p in container.demux(video=0) if p.size]
    return packets


def _times(path: Path) -> list[float]:
    with av.open(str(path)) as container:
        times = [frame.time or 0.0 for frame in container.decode(video=0)]
    return times


def _frames(path: Path) -> list[NDArray[np.uint8]]:
    return list(read_frames(path))


def test_keyframe_every_interval_by_default(tmp_path: Path) -> None:
    info = probe(_clip(tmp_path / "a.mp4", 30, 0))
    assert info.frames == 30
    assert info.longest_gop == KEYFRAME_INTERVAL == 2
    assert probe(_clip(tmp_path / "b.mp4", 30, 0, keyframe_interval=1)).longest_gop == 1
    assert probe(_clip(tmp_path / "c.mp4", 30, 0, keyframe_interval=None)).longest_gop > 2


@pytest.mark.parametrize("interval", [0, -2, 2.5, "2"])
def test_bad_keyframe_interval_is_refused(tmp_path: Path, interval: object) -> None:
    with pytest.raises(RenderError, match="keyframe_interval"):
        VideoWriter(tmp_path / "x.mp4", WIDTH, HEIGHT, FPS, keyframe_interval=interval)  # type: ignore[arg-type]


def test_segments_join_bit_for_bit_at_their_times(tmp_path: Path) -> None:
    segments = [_clip(tmp_path / f"s{i}.mp4", n, i) for i, n in enumerate((7, 4, 9))]
    joined = tmp_path / "joined.mp4"
    with VideoConcatenation(joined, FPS) as concatenation:
        for segment in segments:
            start = concatenation.frame_count
            assert concatenation.append(segment) == probe(segment).frames
            assert concatenation.frame_count == start + probe(segment).frames
    assert _packets(joined) == [p for s in segments for p in _packets(s)]
    assert _times(joined) == pytest.approx([i / FPS for i in range(20)], abs=1e-9)
    decoded = _frames(joined)
    expected = [frame for s in segments for frame in _frames(s)]
    assert all(np.array_equal(a, b) for a, b in zip(decoded, expected, strict=True))
    assert probe(joined).encoding == probe(segments[0]).encoding


def test_a_random_frame_decodes_after_a_seek(tmp_path: Path) -> None:
    segments = [_clip(tmp_path / f"s{i}.mp4", 11, i) for i in range(2)]
    joined = tmp_path / "joined.mp4"
    with VideoConcatenation(joined, FPS) as concatenation:
        for segment in segments:
            concatenation.append(segment)
    expected = _frames(segments[1])[4]  # frame 15 of the joined file
    with av.open(str(joined)) as container:
        stream = container.streams.video[0]
        assert stream.time_base is not None
        container.seek(int(15 / FPS / stream.time_base), stream=stream, backward=True)
        frame = next(f for f in container.decode(stream) if (f.time or 0) >= 15 / FPS - 1e-6)
        image = frame.to_ndarray(format="rgb24")
    assert np.array_equal(image, expected)


def test_another_encoding_or_count_is_refused_before_writing(tmp_path: Path) -> None:
    first = _clip(tmp_path / "first.mp4", 6, 0)
    other = _clip(tmp_path / "other.mp4", 6, 1, keyframe_interval=None)
    joined = tmp_path / "joined.mp4"
    with VideoConcatenation(joined, FPS) as concatenation:
        concatenation.append(first)
        with pytest.raises(RenderError, match="other encoder settings"):
            concatenation.append(other)
        with pytest.raises(RenderError, match="it has 6 frames, not 7"):
            concatenation.append(first, frames=7)
        assert concatenation.frame_count == 6
    assert probe(joined).frames == 6
    with (
        VideoConcatenation(tmp_path / "slow.mp4", 10) as slow,
        pytest.raises(RenderError, match="20 frames/s, not 10"),
    ):
        slow.append(first)


def test_writer_encoding_is_that_of_any_clip(tmp_path: Path) -> None:
    clip = _clip(tmp_path / "long.mp4", 45, 3)
    assert writer_encoding(WIDTH, HEIGHT, FPS) == probe(clip).encoding
    assert writer_encoding(WIDTH, HEIGHT, FPS, None) != probe(clip).encoding
    assert probe(clip).encoding.differences(writer_encoding(96, 64, FPS)) == ["64x48, not 96x64"]


def test_unreadable_file_is_one_render_error(tmp_path: Path) -> None:
    broken = tmp_path / "broken.mp4"
    broken.write_bytes(b"not a video")
    with pytest.raises(RenderError, match="cannot read video"):
        probe(broken)
    with pytest.raises(RenderError, match="cannot read video"):
        list(read_frames(broken))
