"""Assisted grasp: squeeze a resting box between both pads, close, lift, carry it 1 m.

The robot starts at (1.4, 0, yaw = pi) facing the conveyor's end; the base frame is x
forward, y left. Each TCP sits on its pad's outer face with z along the approach, so a pad
touches the box side when its TCP target lies on that side's plane.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import pytest
from numpy.typing import NDArray

from workcell.control.command import ArmCommand, BaseTwist, Command
from workcell.control.simulation import Simulation
from workcell.sim.boxes import BoxSlot
from workcell.sim.events import GraspChanged, WorldEvent

Quat = tuple[float, float, float, float]

STANDOFF = 0.63
"""Box centre this far in front of the base centre (m): comfortably inside the arms' reach."""
APPROACH = 0.15
"""Pre-grasp clearance of each pad from its box side (m)."""
HOVER = 0.2
"""The pre-grasp pose starts this high above the grasp height, clear of the box top (m)."""
SQUEEZE = 0.01
"""How far each TCP target goes inside the box side (m)."""
LIFT = 0.10
CARRY = 1.0


@dataclass
class GraspRun:
    """What happened in each phase of the scripted grasp and carry."""

    sim: Simulation
    slot: BoxSlot
    events: dict[str, list[WorldEvent]] = field(default_factory=dict)
    box_start: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))
    in_hand_engaged: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))
    in_hand_end: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))
    box_lifted: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))
    base_travel: float = 0.0
    box_travel: float = 0.0
    attached_after: dict[str, bool] = field(default_factory=dict)
    box_disturbance: float = 0.0


def box_in_tcp_frame(sim: Simulation, slot: BoxSlot, side: str = "l") -> NDArray[np.float64]:
    """The box centre in the TCP frame of one hand."""
    site = sim.world.data.site(f"tcp_{side}")
    rotation = np.asarray(site.xmat).reshape(3, 3)
    offset = sim.world.boxes.position(sim.world.data, slot) - site.xpos
    return np.asarray(rotation.T @ offset, dtype=float)


class Script:
    """The motions a teleoperator (or the expert) makes, as plain Commands."""

    def __init__(self, sim: Simulation, slot: BoxSlot, quats: dict[str, Quat]) -> None:
        self.sim = sim
        self.slot = slot
        self.quats = quats
        self.box = np.zeros(3)  # box centre in the base frame, fixed once the base stopped
        self.half_width = sim.config.box.size[1] / 2

    def run(self, seconds: float, command: Command) -> list[WorldEvent]:
        events: list[WorldEvent] = []
        for _ in range(round(seconds / self.sim.control_dt)):
            events += self.sim.step(command)
        return events

    def drive_to_standoff(self) -> None:
        """P-control the base along its x axis until the box is STANDOFF in front of it."""
        world = self.sim.world
        box = world.boxes.position(world.data, self.slot)
        for _ in range(round(15.0 / self.sim.control_dt)):
            ahead = world.to_base_frame(box)
            error = ahead[0] - STANDOFF
            if abs(error) < 0.003 and np.linalg.norm(world.base_velocity) < 0.01:
                break
            self.sim.step(Command(base=BaseTwist(vx=float(np.clip(1.5 * error, -0.4, 0.4)))))
        else:
            pytest.fail(f"base did not reach the standoff; box at {world.to_base_frame(box)}")
        self.box = world.to_base_frame(world.boxes.position(world.data, self.slot))

    def arms(
        self, gap: float, lift: float = 0.0, close: float = 0.0, base: BaseTwist | None = None
    ) -> Command:
        """Both TCPs on the box's side planes, ``gap`` outside them, ``lift`` above centre."""
        x, y, z = self.box
        offset = self.half_width + gap
        return Command(
            base=base if base is not None else BaseTwist(),
            left=ArmCommand((x, y + offset, z + lift), self.quats["l"], follow=True),
            right=ArmCommand((x, y - offset, z + lift), self.quats["r"], follow=True),
            close_left=close,
            close_right=close,
        )


@pytest.fixture(scope="module")
def grasp_run(settled_box_sim: Callable[..., Simulation], tcp_quats: dict[str, Quat]) -> GraspRun:
    sim = settled_box_sim()
    slot = sim.world.boxes.slots[0]
    script = Script(sim, slot, tcp_quats)
    run = GraspRun(sim, slot, box_start=sim.world.boxes.position(sim.world.data, slot))
    script.drive_to_standoff()
    run.events["approach"] = script.run(2.0, script.arms(APPROACH, HOVER))
    run.events["approach"] += script.run(1.5, script.arms(APPROACH))
    run.box_disturbance = float(
        np.linalg.norm(sim.world.boxes.position(sim.world.data, slot) - run.box_start)
    )
    run.events["touch"] = script.run(1.0, script.arms(0.0))
    run.events["squeeze"] = script.run(1.0, script.arms(-SQUEEZE))
    run.attached_after["squeeze"] = sim.world.grasp.attached is slot
    run.events["close"] = script.run(0.6, script.arms(-SQUEEZE, close=1.0))
    run.attached_after["close"] = sim.world.grasp.attached is slot
    run.in_hand_engaged = box_in_tcp_frame(sim, slot)
    run.events["lift"] = script.run(1.5, script.arms(-SQUEEZE, LIFT, close=1.0))
    run.box_lifted = sim.world.boxes.position(sim.world.data, slot)
    base_start = sim.world.base_pose[:2].copy()
    box_before = sim.world.boxes.position(sim.world.data, slot)
    carry = script.arms(-SQUEEZE, LIFT, close=1.0, base=BaseTwist(vx=-0.3))
    events: list[WorldEvent] = []
    while np.linalg.norm(sim.world.base_pose[:2] - base_start) < CARRY:
        events += sim.step(carry)
        if sim.time > 200.0:
            pytest.fail("the base did not carry the box 1 m")
    events += script.run(1.0, script.arms(-SQUEEZE, LIFT, close=1.0))  # come to a stop
    run.events["carry"] = events
    run.attached_after["carry"] = sim.world.grasp.attached is slot
    run.in_hand_end = box_in_tcp_frame(sim, slot)
    run.base_travel = float(np.linalg.norm(sim.world.base_pose[:2] - base_start))
    run.box_travel = float(
        np.linalg.norm(sim.world.boxes.position(sim.world.data, slot)[:2] - box_before[:2])
    )
    run.events["open"] = script.run(0.6, script.arms(APPROACH, LIFT, close=0.0))
    run.attached_after["open"] = sim.world.grasp.attached is slot
    return run


def grasp_events(events: list[WorldEvent]) -> list[GraspChanged]:
    return [e for e in events if isinstance(e, GraspChanged)]


def test_approach_leaves_the_box_alone(grasp_run: GraspRun) -> None:
    assert grasp_run.box_disturbance < 0.005


def test_weld_engages_when_both_grippers_close_on_the_box(grasp_run: GraspRun) -> None:
    assert not grasp_run.attached_after["squeeze"]
    assert grasp_run.attached_after["close"]
    assert grasp_run.attached_after["carry"]


def test_box_is_lifted(grasp_run: GraspRun) -> None:
    rise = grasp_run.box_lifted[2] - grasp_run.box_start[2]
    assert rise == pytest.approx(LIFT, abs=0.02)


def test_box_travels_with_the_base_without_slipping(grasp_run: GraspRun) -> None:
    assert grasp_run.base_travel >= CARRY
    assert grasp_run.box_travel == pytest.approx(grasp_run.base_travel, abs=0.02)
    slip = float(np.linalg.norm(grasp_run.in_hand_end - grasp_run.in_hand_engaged))
    assert slip < 0.01, f"the box moved {slip * 1000:.1f} mm in the left hand frame"


def test_grasp_event_fires_when_the_grippers_close(grasp_run: GraspRun) -> None:
    """Assisted mode: touching with open grippers is no grasp; closing them is."""
    for phase in ("approach", "touch", "squeeze"):
        assert not grasp_events(grasp_run.events[phase]), (phase, grasp_run.events[phase])
    engaged = grasp_events(grasp_run.events["close"])
    assert [(e.box, e.engaged) for e in engaged] == [(grasp_run.slot.index, True)]
    for phase in ("lift", "carry"):
        assert not grasp_events(grasp_run.events[phase]), phase


def test_opening_the_grippers_releases_the_box(grasp_run: GraspRun) -> None:
    assert not grasp_run.attached_after["open"]
    released = grasp_events(grasp_run.events["open"])
    assert [(e.box, e.engaged) for e in released] == [(grasp_run.slot.index, False)]
