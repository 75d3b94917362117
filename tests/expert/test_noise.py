"""Demonstrations that show recoveries (src/workcell/expert/noise.py): the expert's base
is pushed off its course while it drives, it steers back and still delivers; nothing is
added while it holds the base still; the record keeps the expert's own command (DART); the
pushes are the trial seed's; the CLI records who drove and refuses what it cannot do."""

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
from workcell.recording.frame_capture import input_from_command
from workcell.recording.frame_format import build_frame
from workcell.sim.config import WorldConfig
from workcell.sim.world import World
from workcell.task.operator import Operator
from workcell.tasks.box_transfer.episode import deliver_one_box
from workcell.tasks.box_transfer.task import BoxTransfer
from workcell.tasks.elements.expert import ExpertOperator


class Twists:
    """An operator that keeps the base twist of every command it passes on (as recorded and
    as executed)."""

    def __init__(self, operator: Operator) -> None:
        self.operator = operator
        self.bases: list[BaseTwist] = []
        self.executed: list[BaseTwist] = []

    def start_trial(self, trial_seed: int) -> None:
        self.operator.start_trial(trial_seed)

    def act(self, world: World) -> Command:
        command = self.operator.act(world)
        self.bases.append(command.base)
        self.executed.append(command.executed_base)
        return command


def _run(seed: int, noise: float) -> tuple[Twists, Twists, bool]:
    """The expert's commands and the pushed expert's of one delivery, and whether it
    delivered."""
    sim = Simulation(WorldConfig(), BoxTransfer().scene())
    asked = Twists(ExpertOperator(ExpertConfig(), seed))
    pushed = Twists(NoisyBase(asked, noise))
    result = deliver_one_box(sim, pushed, seed, 120.0)
    return asked, pushed, result.delivered


def _drive(seed: int, noise: float) -> tuple[list[BaseTwist], list[BaseTwist], bool]:
    """The expert's and the executed base twists of one delivery, and whether it delivered."""
    asked, pushed, delivered = _run(seed, noise)
    return asked.bases, pushed.executed, delivered


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


def test_the_recorded_command_is_the_experts_own() -> None:
    asked, pushed, _ = _run(3, 0.1)
    assert pushed.bases == asked.bases  # what frames record: the expert's twist (DART)
    executed = np.array([(t.vx, t.vy, t.wz) for t in pushed.executed])
    twist = np.array([(t.vx, t.vy, t.wz) for t in pushed.bases])
    assert np.abs(executed - twist).max() > 0.05  # the base was driven with the pushes


def test_the_controller_executes_the_push_and_a_frame_records_the_operators_twist() -> None:
    asked = BaseTwist(0.2, 0.0, 0.1)
    pushed = Command(base=asked, base_push=BaseTwist(0.0, 0.05, -0.1))
    assert pushed.executed_base == BaseTwist(0.2, 0.05, 0.0)
    assert Command(base=asked).executed_base == asked
    runs = []
    for command in (pushed, Command(base=BaseTwist(0.2, 0.05, 0.0))):
        sim = Simulation(WorldConfig(), BoxTransfer().scene())
        sim.reset(1)
        for _ in range(50):
            sim.step(command)
        operator_input = input_from_command(command)
        row = build_frame(
            sim.world,
            sim.controller,
            command,
            operator_input,
            t_sim=1.0,
            t_wall=0.0,
            step_wall_ms=0.0,
        )
        runs.append((sim.world.base_pose.tolist(), (row["cmd_vx"], row["cmd_vy"], row["cmd_wz"])))
    (pose_pushed, recorded_pushed), (pose_plain, recorded_plain) = runs
    assert pose_pushed == pose_plain  # the push moved the base as the same twist given
    assert recorded_pushed == (0.2, 0.0, 0.1) and recorded_plain == (0.2, 0.05, 0.0)


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
