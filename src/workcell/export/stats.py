"""Feature statistics as LeRobot keeps them: min, max, mean, std, count and quantiles.

Each episode's statistics are computed from its rows; the dataset's are aggregated from
the episodes' the way LeRobot aggregates them (count-weighted mean, pooled variance,
count-weighted quantiles), so an export never holds the whole dataset in memory. Image
statistics are per channel over pixels scaled to [0, 1], shaped (3, 1, 1).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

QUANTILES: dict[str, float] = {"q01": 0.01, "q10": 0.10, "q50": 0.50, "q90": 0.90, "q99": 0.99}
Stats = dict[str, NDArray[np.float64]]
"""``min``, ``max``, ``mean``, ``std``, ``count`` and the quantiles, as arrays."""
IMAGE_PIXEL_STRIDE = 4
"""Image statistics use every 4th pixel in each direction (a 16th of the pixels)."""


def vector_stats(values: NDArray[Any]) -> Stats:
    """Statistics over rows of ``values`` ((rows,) or (rows, dims)), per dimension."""
    array = np.asarray(values, dtype=np.float64)
    if array.ndim == 1:
        array = array[:, None]
    stats: Stats = {
        "min": array.min(axis=0),
        "max": array.max(axis=0),
        "mean": array.mean(axis=0),
        "std": array.std(axis=0),
        "count": np.array([len(array)], dtype=np.float64),
    }
    for name, q in QUANTILES.items():
        stats[name] = np.quantile(array, q, axis=0)
    return stats


def image_stats(images: Sequence[NDArray[np.uint8]]) -> Stats:
    """Per-channel statistics of (height, width, 3) uint8 images, shaped (3, 1, 1)."""
    step = IMAGE_PIXEL_STRIDE
    pixels = np.concatenate(
        [image[::step, ::step].reshape(-1, 3) for image in images], axis=0
    ).astype(np.float64)
    stats = vector_stats(pixels / 255.0)
    stats["count"] = np.array([len(images)], dtype=np.float64)
    return {
        name: value if name == "count" else value.reshape(3, 1, 1) for name, value in stats.items()
    }


def aggregate(parts: Sequence[Stats]) -> Stats:
    """The statistics of the union of the rows behind ``parts``."""
    counts = np.array([float(p["count"][0]) for p in parts])
    weights = counts / counts.sum()

    def weighted(name: str) -> NDArray[np.float64]:
        return np.asarray(sum(w * p[name] for w, p in zip(weights, parts, strict=True)))

    mean = weighted("mean")
    variance = sum(
        w * (p["std"] ** 2 + (p["mean"] - mean) ** 2) for w, p in zip(weights, parts, strict=True)
    )
    result: Stats = {
        "min": np.min(np.stack([p["min"] for p in parts]), axis=0),
        "max": np.max(np.stack([p["max"] for p in parts]), axis=0),
        "mean": mean,
        "std": np.sqrt(np.asarray(variance)),
        "count": np.array([counts.sum()]),
    }
    for name in QUANTILES:
        result[name] = weighted(name)
    return result


def to_json(stats: Stats) -> dict[str, Any]:
    """Nested lists (``count`` as an integer list), ready for ``stats.json``."""
    out: dict[str, Any] = {name: value.tolist() for name, value in stats.items()}
    out["count"] = [int(c) for c in stats["count"]]
    return out
