"""Domain randomization: drawn per trial from its seed, applied without recompiling,
recorded with the trial, and the expert still delivers."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from workcell.cli.main import main
from workcell.control.command import Command
from workcell.control.simulation import Simulation
from workcell.errors import ConfigError
from workcell.record import Store
from workcell.sim.config import TargetConfig, WorldConfig
from workcell.sim.randomization import RandomizationConfig
from workcell.sim.trial_conditions import TrialConditions
from workcell.tasks.box_transfer.episode import deliver_one_box
from workcell.tasks.box_transfer.task import BoxTransfer
from workcell.tasks.elements.expert import ExpertOperator

WIDE = RandomizationConfig(
    box_size=0.15,
    box_mass=0.3,
    box_colour=0.2,
    conveyor_speed=0.3,
    release_interval=0.3,
    target_shift=0.2,
    start_shift=0.2,
    start_yaw=0.3,
)


def test_off_by_default_and_nominal() -> None:
    config = WorldConfig()
    assert not config.randomization.enabled
    rng = np.random.default_rng(0)
    assert TrialConditions.draw(config, rng) == TrialConditions.nominal(config)


def test_draws_are_reproducible_and_within_range() -> None:
    config = WorldConfig(randomization=WIDE)
    nominal = TrialConditions.nominal(config)
    draws = [TrialConditions.draw(config, np.random.default_rng(s)) for s in range(50)]
    again = [TrialConditions.draw(config, np.random.default_rng(s)) for s in range(50)]
    assert draws == again
    assert len({d.box_mass for d in draws}) == 50
    for d in draws:
        assert np.all(np.abs(np.array(d.box_size) / nominal.box_size - 1) <= 0.15 + 1e-12)
        assert abs(d.conveyor_speed / nominal.conveyor_speed - 1) <= 0.3 + 1e-12
        assert np.all(np.abs(np.subtract(d.target_center, nominal.target_center)) <= 0.2)
        assert abs(d.start_pose[2] - nominal.start_pose[2]) <= 0.3


@pytest.mark.parametrize(
    ("make", "field"),
    [
        (lambda: RandomizationConfig(box_size=0.5), "randomization.box_size"),
        (lambda: RandomizationConfig(start_yaw=-0.1), "randomization.start_yaw"),
        (
            lambda: WorldConfig(
                target=TargetConfig(center=(0.5, 0.95)),
                randomization=RandomizationConfig(target_shift=0.3),
            ),
            "world.target.center",
        ),
    ],
)
def test_bad_ranges_are_rejected(make: object, field: str) -> None:
    with pytest.raises(ConfigError) as caught:
        make()  # type: ignore[operator]
    assert caught.value.problems[0].startswith(f"{field} = ")


def test_conditions_are_applied_to_the_model() -> None:
    sim = Simulation(WorldConfig(randomization=WIDE), BoxTransfer().scene())
    conditions = sim.reset(3)
    model = sim.world.model
    slot = sim.world.boxes.slots[0]
    np.testing.assert_allclose(model.geom_size[slot.geom], np.array(conditions.box_size) / 2)
    assert model.body_mass[slot.body] == pytest.approx(conditions.box_mass)
    assert model.geom_surfacevel[model.geom("belt").id, 0] == pytest.approx(
        conditions.conveyor_speed
    )
    np.testing.assert_allclose(sim.world.base_pose, conditions.start_pose, atol=1e-9)
    # the box rides at the drawn belt speed
    xs, ts = [], []
    while sim.time < 6.0:
        sim.step(Command())
        if sim.time > 2.0:
            xs.append(sim.world.boxes.position(sim.world.data, slot)[0])
            ts.append(sim.time)
    speed = np.polyfit(ts, xs, 1)[0]
    assert speed == pytest.approx(conditions.conveyor_speed, rel=0.02)


def test_expert_delivers_under_randomized_conditions() -> None:
    sim = Simulation(WorldConfig(randomization=WIDE), BoxTransfer().scene())
    delivered = 0
    for seed in range(5):
        delivered += deliver_one_box(sim, ExpertOperator(seed=seed), seed, 120.0).delivered
    assert delivered >= 4


def test_each_trials_draw_is_recorded(tmp_path: Path) -> None:
    store = tmp_path / "r.sqlite"
    args = ["collect", "--mode", "collection", "--trials", "2", "--store", str(store), "--json"]
    args += [
        "--set",
        "world.randomization.box_mass=0.4",
        "--set",
        "world.randomization.target_shift=0.1",
    ]
    assert main(args) == 0
    with Store.open(store, writer=False) as reader:
        started = [e for e in reader.events() if e.kind == "trial_started"]
    masses = [e.payload["conditions"]["box_mass"] for e in started]
    assert len(masses) == 2 and masses[0] != masses[1]
    assert all(1.2 <= m <= 2.8 for m in masses)
