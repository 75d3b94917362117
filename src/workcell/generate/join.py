"""How long the generator's join from where the robot is to a moved segment's first pose
takes (:class:`~workcell.generate.operator.GeneratedOperator`): as long as its longest move
at :data:`JOIN_SPEED`, at least :data:`MIN_JOIN_S`."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from workcell.generate.motion import MotionSample
from workcell.generate.planar import wrap

JOIN_SPEED = (0.3, 0.5, 0.25)
"""How fast a join moves the base (m/s, rad/s) and the hands (m/s) at most."""
MIN_JOIN_S = 0.5
"""The shortest join."""


def join_duration(
    base: NDArray[np.float64], hands: NDArray[np.float64], target: MotionSample
) -> float:
    distance = float(np.linalg.norm(target.base[:2] - base[:2]))
    turn = abs(wrap(float(target.base[2] - base[2])))
    # an arm the target does not have following (a person's released clutch) holds where
    # it is: its recorded target (often none) is no distance to cover
    reach = max(
        (
            float(np.linalg.norm(target.hands[i, :3] - hands[i, :3]))
            for i in range(2)
            if target.follow[i] and np.isfinite(target.hands[i]).all()
        ),
        default=0.0,
    )
    # the smooth blend's top speed is 1.5 times its mean
    return max(
        MIN_JOIN_S,
        1.5 * distance / JOIN_SPEED[0],
        1.5 * turn / JOIN_SPEED[1],
        1.5 * reach / JOIN_SPEED[2],
    )
