"""The feeder releases pooled boxes on schedule; parked boxes cost no contacts."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from workcell.control.command import Command
from workcell.control.simulation import Simulation
from workcell.sim.boxes import BoxState
from workcell.sim.config import FeederConfig, WorldConfig
from workcell.sim.events import BoxReleased


def released_events(sim: Simulation, until: float) -> list[BoxReleased]:
    events: list[BoxReleased] = []
    while sim.time < until:
        events += [e for e in sim.step(Command()) if isinstance(e, BoxReleased)]
    return events


@pytest.mark.parametrize("interval", [3.0, 4.0])
def test_releases_follow_the_schedule_until_the_pool_is_empty(interval: float) -> None:
    pool = 4
    config = WorldConfig(
        feeder=FeederConfig(release_interval_s=interval, first_release_s=0.5, pool_size=pool)
    )
    sim = Simulation(config)
    events = released_events(sim, until=0.5 + (pool + 1) * interval)
    times = [e.t_sim for e in events]
    expected = [0.5 + k * interval for k in range(pool)]
    assert len(times) == pool, times
    assert np.abs(np.array(times) - expected).max() <= sim.control_dt + 1e-9, times
    assert sorted(e.box for e in events) == list(range(pool))
    assert all(slot.state is BoxState.ACTIVE for slot in sim.world.boxes.slots)


def test_interval_is_a_config_value_not_a_model_change() -> None:
    """Two intervals compile to the same model; only the schedule differs."""
    short = Simulation(WorldConfig(feeder=FeederConfig(release_interval_s=3.0)))
    long = Simulation(WorldConfig(feeder=FeederConfig(release_interval_s=5.0)))
    for attr in ("nq", "nv", "nbody", "ngeom", "neq"):
        assert getattr(short.world.model, attr) == getattr(long.world.model, attr)
    t_short = [e.t_sim for e in released_events(short, until=6.0)]
    t_long = [e.t_sim for e in released_events(long, until=6.0)]
    assert len(t_short) == 2
    assert len(t_long) == 2
    assert t_short[1] == pytest.approx(3.5, abs=short.control_dt + 1e-9)
    assert t_long[1] == pytest.approx(5.5, abs=long.control_dt + 1e-9)


def test_feeder_waits_until_the_feed_point_is_clear() -> None:
    """With a tiny interval a new box only appears once the last one moved off the feed."""
    config = WorldConfig(feeder=FeederConfig(release_interval_s=0.5, pool_size=3))
    sim = Simulation(config)
    world = sim.world
    clearance = config.box.size[0]
    releases = 0
    while sim.time < 8.0:
        for event in sim.step(Command()):
            if not isinstance(event, BoxReleased):
                continue
            releases += 1
            new = world.boxes.slots[event.box]
            for slot in world.boxes.active():
                if slot is not new:
                    gap = world.boxes.position(world.data, slot)[0] - world.boxes.feed_position[0]
                    assert gap >= clearance, f"box {slot.index} only {gap:.3f} m ahead"
    assert releases == 3


def box_contacts(model: mujoco.MjModel, data: mujoco.MjData, geom: int) -> int:
    return sum(1 for c in data.contact[: data.ncon] if geom in (c.geom1, c.geom2))


def test_parked_boxes_have_no_contacts_and_stay_put() -> None:
    config = WorldConfig(feeder=FeederConfig(first_release_s=0.5, pool_size=3))
    sim = Simulation(config)
    world = sim.world
    parked = {s.index: world.boxes.position(world.data, s) for s in world.boxes.slots}
    while sim.time < 2.0:
        sim.step(Command())
        for slot in world.boxes.slots:
            contacts = box_contacts(world.model, world.data, slot.geom)
            if slot.state is BoxState.PARKED:
                assert contacts == 0, f"parked box {slot.index} has {contacts} contacts"
                pos = world.boxes.position(world.data, slot)
                np.testing.assert_allclose(pos, parked[slot.index], atol=1e-6)
    released = world.boxes.slots[0]
    assert released.state is BoxState.ACTIVE
    assert box_contacts(world.model, world.data, released.geom) > 0  # it rests on the belt
    assert all(s.state is BoxState.PARKED for s in world.boxes.slots[1:])
