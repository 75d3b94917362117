"""save_png: lossless PNG files in folders that may not exist yet."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from workcell.errors import RenderError
from workcell.render import save_png


def test_saves_a_lossless_rgb_png_creating_folders(tmp_path: Path) -> None:
    rng = np.random.default_rng(0)
    image = rng.integers(0, 256, size=(30, 50, 3), dtype=np.uint8)
    path = save_png(image, tmp_path / "a" / "b" / "picture.png")
    assert path == tmp_path / "a" / "b" / "picture.png"
    with Image.open(path) as png:
        assert png.format == "PNG"
        assert png.size == (50, 30)
        assert png.mode == "RGB"
        np.testing.assert_array_equal(np.asarray(png), image)


@pytest.mark.parametrize(
    "image",
    [np.zeros((4, 4), dtype=np.uint8), np.zeros((4, 4, 4), dtype=np.uint8), np.zeros((4, 4, 3))],
)
def test_rejects_anything_but_rgb_uint8(tmp_path: Path, image: np.ndarray) -> None:
    with pytest.raises(RenderError, match="uint8 RGB"):
        save_png(image, tmp_path / "bad.png")
    assert not (tmp_path / "bad.png").exists()
