"""How far the IK leaves a TCP from its target: one formula for the live IK and for
recorded frames (which compute it later, from captured positions), so both agree to the
last bit."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def residuals(positions: NDArray[np.float64], targets: NDArray[np.float64]) -> NDArray[np.float64]:
    """Distances between the rows of (n, 3) ``positions`` and ``targets``, metres."""
    error = positions - targets
    x, y, z = error[:, 0], error[:, 1], error[:, 2]
    return np.sqrt(x * x + y * y + z * z)
