"""Non-finite data: NaN or infinite values in the columns the metrics read.

Definition (version :data:`NONFINITE_VERSION`): ``nonfinite`` is raised when the metric
``nonfinite_share`` of docs/architecture.md (share of frames holding NaN or inf among t_sim,
t_wall, the base velocity, both TCP positions, the 14 arm joint positions and rates and both
grips) is above 0. A metric that touches such a value is NaN or counts it as inactive (see
METRIC_DEFINITIONS), so such a trial's numbers are not comparable with the others.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from workcell.audit.flags import NONFINITE, Flag
from workcell.metrics import TrialMetrics

NONFINITE_VERSION = "1"
"""Bumped whenever the definition above changes meaning."""


@dataclass(frozen=True)
class NonfiniteParams:
    """Whether ``nonfinite`` disqualifies a successful trial."""

    disqualifying: bool = True


def detect_nonfinite(metrics: TrialMetrics, params: NonfiniteParams) -> Flag | None:
    share = metrics.nonfinite_share
    if math.isnan(share) or share == 0:
        return None
    count = round(share * metrics.n_frames)
    detail = f"{count} of {metrics.n_frames} frames ({share:.1%}) hold NaN or inf"
    return Flag(NONFINITE, detail, params.disqualifying)
