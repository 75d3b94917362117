"""FrameArrays from frames.csv columns: grouping, validation, immutability."""

from __future__ import annotations

import numpy as np
import pytest

from tests.metrics.builders import columns
from workcell.errors import WorkcellError
from workcell.metrics import REQUIRED_COLUMNS, FrameArrays, MetricsError
from workcell.record.columns import FRAME_CONTRACT_COLUMNS


def test_required_columns_are_contract_columns() -> None:
    # 2 times + 3 base velocities + 2 x 3 TCP positions + 4 x 7 arm q/dq + 2 grips = 41
    assert len(REQUIRED_COLUMNS) == 41
    assert set(REQUIRED_COLUMNS) <= set(FRAME_CONTRACT_COLUMNS)


def test_columns_land_in_their_blocks_in_order() -> None:
    cols = columns(4)
    cols["base_wz"] = np.array([1.0, 2.0, 3.0, 4.0])
    cols["tcp_r_y"] = np.array([5.0, 6.0, 7.0, 8.0])
    cols["q_arm_l_7"] = np.array([0.1, 0.2, 0.3, 0.4])
    cols["dq_arm_r_1"] = np.array([-1.0, -2.0, -3.0, -4.0])
    cols["grip_r"] = np.array([0.0, 0.5, 1.0, 0.5])
    cols["tcp_l_qw"] = np.ones(4)  # a further column: ignored
    arrays = FrameArrays.from_columns(cols)
    assert len(arrays) == 4
    assert arrays.base_v.shape == (4, 3)
    assert arrays.q_l.shape == arrays.dq_r.shape == (4, 7)
    assert arrays.base_v[:, 2].tolist() == [1.0, 2.0, 3.0, 4.0]
    assert arrays.tcp_r[:, 1].tolist() == [5.0, 6.0, 7.0, 8.0]
    assert arrays.q_l[:, 6].tolist() == [0.1, 0.2, 0.3, 0.4]
    assert arrays.q_l[:, :6].tolist() == [[0.0] * 6] * 4
    assert arrays.dq_r[:, 0].tolist() == [-1.0, -2.0, -3.0, -4.0]
    assert arrays.grip_r.tolist() == [0.0, 0.5, 1.0, 0.5]
    assert arrays.t_sim.tolist() == [0.0, 0.05, 0.1, 0.15000000000000002]


def test_plain_lists_are_accepted() -> None:
    cols: dict[str, list[float]] = {name: [0.0, 1.0] for name in REQUIRED_COLUMNS}
    arrays = FrameArrays.from_columns(cols)
    assert arrays.t_wall.dtype == np.float64
    assert arrays.tcp_l.tolist() == [[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]]


def test_missing_columns_are_all_named() -> None:
    cols = columns(3)
    del cols["grip_r"], cols["q_arm_l_3"]
    with pytest.raises(MetricsError, match=r"missing column\(s\) q_arm_l_3, grip_r"):
        FrameArrays.from_columns(cols)
    assert issubclass(MetricsError, WorkcellError)


def test_ragged_columns_are_named_with_their_lengths() -> None:
    cols = columns(3)
    cols["tcp_l_z"] = np.zeros(2)
    with pytest.raises(MetricsError, match=r"t_sim's length 3; not tcp_l_z \(2\)"):
        FrameArrays.from_columns(cols)


def test_non_numeric_and_two_dimensional_columns_are_named() -> None:
    cols = columns(2)
    bad: dict[str, object] = dict(cols)
    bad["grip_l"] = ["open", "shut"]
    bad["base_vx"] = np.zeros((2, 2))
    with pytest.raises(MetricsError, match="base_vx, grip_l must be one-dimensional"):
        FrameArrays.from_columns(bad)  # type: ignore[arg-type]


def test_direct_construction_checks_shapes() -> None:
    good = FrameArrays.from_columns(columns(3))
    with pytest.raises(MetricsError, match=r"q_r has shape \(3, 6\), expected \(3, 7\)"):
        FrameArrays(
            good.t_sim,
            good.t_wall,
            good.base_v,
            good.tcp_l,
            good.tcp_r,
            good.q_l,
            np.zeros((3, 6)),
            good.dq_l,
            good.dq_r,
            good.grip_l,
            good.grip_r,
        )


def test_arrays_are_read_only_and_the_callers_stay_writable() -> None:
    cols = columns(3)
    arrays = FrameArrays.from_columns(cols)
    with pytest.raises(ValueError, match="read-only"):
        arrays.t_sim[0] = 5.0
    cols["t_sim"][0] = 5.0  # the caller's own array is neither frozen nor shared
    assert arrays.t_sim[0] == 0.0


def test_zero_frames() -> None:
    arrays = FrameArrays.from_columns(columns(0))
    assert len(arrays) == 0
    assert arrays.q_r.shape == (0, 7)
