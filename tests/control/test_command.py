"""Commands reject non-finite and out-of-range values with CommandError."""

from __future__ import annotations

import math
from collections.abc import Callable

import pytest

from workcell.control.command import ArmCommand, BaseTwist, Command, CommandError
from workcell.errors import WorkcellError

NAN = math.nan
INF = math.inf

INVALID: dict[str, Callable[[], object]] = {
    "base_vx_nan": lambda: BaseTwist(vx=NAN),
    "base_vy_nan": lambda: BaseTwist(vy=NAN),
    "base_wz_nan": lambda: BaseTwist(wz=NAN),
    "base_vx_inf": lambda: BaseTwist(vx=INF),
    "arm_position_x_nan": lambda: ArmCommand(position=(NAN, 0.0, 0.0)),
    "arm_position_y_nan": lambda: ArmCommand(position=(0.0, NAN, 0.0)),
    "arm_position_z_inf": lambda: ArmCommand(position=(0.0, 0.0, -INF)),
    "arm_quat_w_nan": lambda: ArmCommand(quaternion=(NAN, 0.0, 0.0, 0.0)),
    "arm_quat_z_nan": lambda: ArmCommand(quaternion=(1.0, 0.0, 0.0, NAN)),
    "gripper_left_nan": lambda: Command(close_left=NAN),
    "gripper_right_nan": lambda: Command(close_right=NAN),
    "head_pan_nan": lambda: Command(head=(NAN, 0.3)),
    "head_tilt_inf": lambda: Command(head=(0.0, INF)),
    "gripper_left_above": lambda: Command(close_left=1.01),
    "gripper_left_below": lambda: Command(close_left=-0.01),
    "gripper_right_above": lambda: Command(close_right=2.0),
    "gripper_right_below": lambda: Command(close_right=-1.0),
    "quat_zero": lambda: ArmCommand(quaternion=(0.0, 0.0, 0.0, 0.0)),
    "quat_double": lambda: ArmCommand(quaternion=(2.0, 0.0, 0.0, 0.0)),
    "quat_long": lambda: ArmCommand(quaternion=(1.0, 0.1, 0.1, 0.5)),  # norm 1.13
    "quat_short": lambda: ArmCommand(quaternion=(0.9, 0.0, 0.0, 0.0)),
    "quat_scaled": lambda: ArmCommand(quaternion=(0.6, 0.6, 0.6, 0.6)),  # norm 1.2
}


@pytest.mark.parametrize("make", list(INVALID.values()), ids=list(INVALID))
def test_invalid_command_is_rejected(make: Callable[[], object]) -> None:
    with pytest.raises(CommandError) as caught:
        make()
    assert isinstance(caught.value, WorkcellError)
    assert str(caught.value)


def test_non_unit_quaternion_message_states_the_norm() -> None:
    with pytest.raises(CommandError) as caught:
        ArmCommand(quaternion=(2.0, 0.0, 0.0, 0.0))
    message = str(caught.value)
    assert "{" not in message, message  # no unformatted placeholder
    assert "2" in message.rsplit("norm", maxsplit=1)[-1], message


@pytest.mark.parametrize(
    "command",
    [
        Command(),
        Command(close_left=0.0, close_right=1.0),
        Command(base=BaseTwist(vx=-0.3, vy=0.1, wz=2.0)),
        Command(left=ArmCommand((0.6, 0.15, 0.9), (0.7071068, 0.7071068, 0.0, 0.0), follow=True)),
        Command(right=ArmCommand((0.6, -0.15, 0.9), (0.5, -0.5, 0.5, 0.5), follow=True)),
        # a unit quaternion from float32 device data is slightly off unit length
        Command(left=ArmCommand(quaternion=(1.0 + 1e-6, 0.0, 0.0, 0.0))),
    ],
)
def test_valid_commands_construct(command: Command) -> None:
    assert command.close_left in (0.0, 1.0)
