"""Demonstrations that show recoveries (src/workcell/expert/noise.py): the expert's base
is pushed off its course while it drives, it steers back and still delivers; nothing is
added while it holds the base still; the pushes are the trial seed's; the CLI records who
drove and refuses what it cannot do."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from workcell.cli.main import main
from workcell.control.command import BaseTwist, Command
from workcell.control.simulation import Simulation
from workcell.errors import ConfigError
from workcell.expert import ExpertConfig
from workcell.expert.noise import NoisyBase
from workcell.record.store import Store
from workcell.sim.config import WorldConfig
from workcell.sim.world import World
from workcell.task.operator import Operator
from workcell.tasks.box_transfer.episode import deliver_one_box
from workcell.tasks.box_transfer.task import BoxTransfer
from workcell.tasks.elements.expert import ExpertOperator


class Twists:
    """An operator that keeps the base twist of every command it passes on."""

    def __init__(self, operator: Operator) -> None:
        self.operator = operator
        self.bases: list[BaseTwist] = []

    def start_trial(self, trial_seed: int) -> None:
        self.operator.start_trial(trial_seed)

    def act(self, world: World) -> Command:
        command = self.operator.act(world)
        self.bases.append(command.base)
        return command


def _drive(seed: int, noise: float) -> tuple[list[BaseTwist], list[BaseTwist], bool]:
    """The expert's and the executed base twists of one delivery, and whether it delivered."""
    sim = Simulation(WorldConfig(), BoxTransfer().scene())
    asked = Twists(ExpertOperator(ExpertConfig(), seed))
    executed = Twists(NoisyBase(asked, noise))
    result = deliver_one_box(sim, executed, seed, 120.0)  # type: ignore[arg-type]
    return asked.bases, executed.bases, result.delivered


def test_a_pushed_expert_steers_back_and_delivers_and_still_bases_are_left_alone() -> None:
    asked, executed, delivered = _drive(3, 0.1)
    assert delivered
    still = [i for i, twist in enumerate(asked) if twist == BaseTwist()]
    assert still and all(executed[i] == BaseTwist() for i in still)
    pushed = [i for i, (a, e) in enumerate(zip(asked, executed, strict=True)) if a != e]
    assert len(pushed) > 100  # it drove for seconds, pushed all the way
    # a push at full speed is about the standard deviation asked for
    full = [i for i in pushed if np.hypot(asked[i].vx, asked[i].vy) > 0.3]
    offsets = np.array([[executed[i].vx - asked[i].vx, executed[i].vy - asked[i].vy] for i in full])
    assert 0.03 < float(np.std(offsets)) < 0.3


def test_the_pushes_are_the_trial_seeds() -> None:
    _, first, _ = _drive(5, 0.1)
    _, again, _ = _drive(5, 0.1)
    _, other, _ = _drive(6, 0.1)
    assert first == again
    assert first[: len(other)] != other[: len(first)]


@pytest.mark.parametrize("noise", [-0.1, 0.6, float("nan")])
def test_a_base_noise_outside_its_range_is_refused(noise: float) -> None:
    with pytest.raises(ConfigError, match="base_noise"):
        ExpertConfig(base_noise=noise)


def test_collect_records_the_pushed_expert_under_its_own_name(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    store = tmp_path / "noisy.sqlite"
    argv = ["collect", "--mode", "collection", "--world", "D1", "--trials", "2", "--seed", "4"]
    assert main([*argv, "--base-noise", "0.1", "--store", str(store)]) == 0
    with Store.open(store, writer=False) as reading:
        (session,) = reading.sessions()
        trials = reading.trials(session.session_id)
    assert session.operator_id == "expert-noise0.1"
    assert [t.outcome for t in trials] == ["success", "success"]
    assert main(["collect", "--base-noise", "0.1", "--operator", "policy:act", "--no-store"]) == 2
    assert "--base-noise: perturbs the expert's demonstrations" in capsys.readouterr().err
