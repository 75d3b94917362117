"""One sign for every recorded orientation, continuous from frame to frame.

``q`` and ``-q`` are the same rotation, and turning a rotation matrix into a quaternion
picks one of them by a rule of its own (MuJoCo's ``mju_mat2Quat`` keeps ``w >= 0``). So a
TCP quaternion read that way can flip sign between two frames while the hand barely
turns: a jump of length 2 in a feature a policy learns from. Each recorded quaternion
after a trial's first therefore takes the sign that agrees with the frame before it (a
non-negative dot product); the first keeps the converter's sign. The record, the exports
and the Gymnasium environment all use :func:`continuous`, so they agree value for value.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def continuous(
    quaternions: NDArray[np.float64], previous: NDArray[np.float64] | None = None
) -> NDArray[np.float64]:
    """``quaternions`` (frames, ..., 4; w, x, y, z), each frame's signs chosen against the
    frame before it, the first against ``previous`` (shape ``(..., 4)``; None: kept).

    Applying it to a sequence it returned changes nothing.
    """
    q = np.asarray(quaternions, dtype=np.float64)
    if len(q) == 0:
        return q.copy()
    agree = np.ones(q.shape[:-1])
    if previous is not None:
        agree[0] = np.where(np.sum(q[0] * previous, axis=-1) < 0.0, -1.0, 1.0)
    agree[1:] = np.where(np.sum(q[1:] * q[:-1], axis=-1) < 0.0, -1.0, 1.0)
    signs = np.cumprod(agree, axis=0)
    result: NDArray[np.float64] = q * signs[..., None]
    return result
