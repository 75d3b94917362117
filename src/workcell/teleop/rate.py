"""The control rate a person drives at.

A person's input waits for the next control period before it acts on the robot: at the
expert's 40 Hz that is up to 25 ms, 12.5 ms on average. A session driven by a person runs
its control and IK at ``world.robot.teleop_control_hz`` instead (100 Hz by default, which
divides the usual physics rates, 400 and 500 Hz) and its IK at ``teleop_ik_hz``, and its
stored parameters say so (their ``world.robot.control_hz`` and ``ik_hz`` are the rates it
ran at).
"""

from __future__ import annotations

from dataclasses import replace

from workcell.session.config import SessionConfig


def at_teleop_rate(config: SessionConfig) -> SessionConfig:
    """``config`` with ``world.robot.teleop_control_hz`` as its control rate and
    ``teleop_ik_hz`` as its IK rate."""
    robot = config.world.robot
    if (robot.control_hz, robot.ik_hz) == (robot.teleop_control_hz, robot.teleop_ik_hz):
        return config
    robot = replace(robot, control_hz=robot.teleop_control_hz, ik_hz=robot.teleop_ik_hz)
    return replace(config, world=replace(config.world, robot=robot))
