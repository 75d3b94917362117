"""The replay draws a trial's own scene: a D2 palletize trial's pallet where that trial had
it (:func:`workcell.sim.trial_start.start_trial` from its recorded seed), not where the
configured world puts it."""

from __future__ import annotations

from pathlib import Path

import mujoco
import pytest

from workcell.cli.main import main
from workcell.control.simulation import Simulation
from workcell.protocol.scene import BodyDescription
from workcell.record.store import Store
from workcell.server.replay import _config, trial_replay
from workcell.server.scene import describe
from workcell.sim.world import World
from workcell.tasks.registry import load_task


def _pallet_xy(model: mujoco.MjModel, data: mujoco.MjData) -> tuple[float, float]:
    """Where the scene description a client draws puts the pallet."""
    mujoco.mj_kinematics(model, data)
    return _drawn(describe(model, data).bodies)


def _drawn(bodies: tuple[BodyDescription, ...]) -> tuple[float, float]:
    pallet = next(b for b in bodies if b.name == "pallet")
    assert not pallet.dynamic
    return round(pallet.pose[0], 4), round(pallet.pose[1], 4)


def test_a_d2_trial_replays_with_its_own_pallet(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    store_path = tmp_path / "s.sqlite"
    argv = ["collect", "--task", "palletize", "--world", "D2", "--mode", "collection"]
    short = ["--set", "task.time_limit_s=0.5", "--seed", "5", "--trials", "2"]
    assert main([*argv, *short, "--store", str(store_path), "--json"]) == 0
    capsys.readouterr()
    with Store.open(store_path, writer=False) as store:
        session = store.sessions()[0]
        trials = sorted(store.trials(), key=lambda t: t.trial_index)
        replays = [trial_replay(store, t.trial_id, 1) for t in trials]
    config = _config(session.parameters)
    task = load_task(config.task.kind)
    configured = World(config.world, task.scene())  # the old replay's: never reset
    configured_xy = _pallet_xy(configured.model, configured.data)
    sim = Simulation(config.world, task.scene())
    seen = []
    for trial, replay in zip(trials, replays, strict=True):
        assert trial.trial_seed is not None
        sim.reset(trial.trial_seed)  # the world the trial ran in
        drawn = _drawn(replay.scene.bodies)
        assert drawn == _pallet_xy(sim.world.model, sim.world.data)
        seen.append(drawn)
    assert len(set(seen)) == 2  # D2 moved the pallet from one trial to the next
    assert configured_xy not in seen  # and off the configured spot
