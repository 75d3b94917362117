"""Still pictures: save a rendered RGB image as PNG."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from PIL import Image

from workcell.errors import RenderError


def save_png(image: NDArray[np.uint8], path: str | Path) -> Path:
    """Write ``image`` ((H, W, 3) uint8 RGB) to ``path`` as PNG, creating parent folders.

    Returns the path written.
    """
    if image.dtype != np.uint8 or image.ndim != 3 or image.shape[2] != 3:
        raise RenderError(
            f"image of shape {image.shape} and dtype {image.dtype}: "
            "save_png needs an (height, width, 3) uint8 RGB array"
        )
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    Image.fromarray(image).save(out, format="PNG", optimize=True)
    return out
