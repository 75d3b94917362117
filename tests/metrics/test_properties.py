"""Properties that hold for any frames: invariances, zeros and ranges."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from tests.metrics.builders import columns
from workcell.metrics import (
    REQUIRED_COLUMNS,
    FrameArrays,
    MetricThresholds,
    compute_trial_metrics,
    describe,
    wilson_interval,
)
from workcell.sim.joints import arm_joint_names

DEFAULT = MetricThresholds()
coordinate = st.floats(-10.0, 10.0)
Matrix = npt.NDArray[np.float64]


def _positions(n: int) -> st.SearchStrategy[Matrix]:
    return arrays(np.float64, (n, 6), elements=coordinate)


@given(st.integers(0, 8).flatmap(_positions), st.tuples(coordinate, coordinate, coordinate))
def test_path_length_ignores_a_common_translation(
    xyz: Matrix, shift: tuple[float, float, float]
) -> None:
    n = len(xyz)
    moved = xyz + np.array(shift * 2)
    lengths = []
    for points in (xyz, moved):
        cols = columns(n)
        for i, name in enumerate(("tcp_l_x", "tcp_l_y", "tcp_l_z", "tcp_r_x", "tcp_r_y")):
            cols[name] = points[:, i]
        cols["tcp_r_z"] = points[:, 5]
        trial = FrameArrays.from_columns(cols)
        lengths.append(compute_trial_metrics(trial, False, DEFAULT).path_length_m)
        # the path is never shorter than the straight line from first to last midpoint
        if n >= 2:
            mid = (points[:, :3] + points[:, 3:]) / 2
            assert lengths[-1] >= np.linalg.norm(mid[-1] - mid[0]) - 1e-9
    assert math.isclose(lengths[0], lengths[1], rel_tol=1e-9, abs_tol=1e-9)


@given(
    st.integers(3, 8),
    arrays(np.float64, 14, elements=st.floats(-3.0, 3.0)),
    arrays(np.float64, 14, elements=st.floats(-0.1, 0.1)),
)
def test_smoothness_is_zero_for_linear_joint_motion(n: int, start: Matrix, rate: Matrix) -> None:
    cols = columns(n, grip_l=[1.0] * n, grip_r=[1.0] * n)
    steps = np.arange(n)
    for j, joint in enumerate(arm_joint_names("l") + arm_joint_names("r")):
        cols[f"q_{joint}"] = start[j] + rate[j] * steps
    smoothness = compute_trial_metrics(FrameArrays.from_columns(cols), False, DEFAULT).smoothness
    assert 0.0 <= smoothness < 1e-12


@given(
    st.integers(0, 8).flatmap(
        lambda n: arrays(np.float64, (len(REQUIRED_COLUMNS), n), elements=st.floats())
    )
)
def test_shares_stay_in_unit_interval_for_any_values(values: Matrix) -> None:
    # any floats, NaN and infinities included: no exception, shares within [0, 1]
    cols = dict(zip(REQUIRED_COLUMNS, values, strict=True))
    result = compute_trial_metrics(FrameArrays.from_columns(cols), True, DEFAULT)
    n = values.shape[1]
    assert result.n_frames == n
    if n:
        assert 0.0 <= result.active_ratio <= 1.0
        assert 0.0 <= result.nonfinite_share <= 1.0
        assert result.nonfinite_share == 0.0 or not np.isfinite(values).all()
    smoothness = result.smoothness
    assert math.isnan(smoothness) or smoothness >= 0.0


@given(st.integers(1, 500).flatmap(lambda n: st.tuples(st.integers(0, n), st.just(n))))
def test_wilson_brackets_the_observed_rate(counts: tuple[int, int]) -> None:
    successes, n = counts
    low, high = wilson_interval(successes, n)
    assert 0.0 <= low <= successes / n <= high <= 1.0


@given(st.lists(st.floats(-1e6, 1e6), min_size=1, max_size=30))
def test_describe_orders_its_summaries(values: list[float]) -> None:
    stats = describe(values)
    tol = 1e-9 * (1 + max(abs(v) for v in values))
    assert stats.minimum <= stats.q1 <= stats.median <= stats.q3 <= stats.maximum
    assert stats.minimum - tol <= stats.mean <= stats.maximum + tol
