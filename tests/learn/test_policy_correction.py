"""A person corrects a learned policy (issue 35): a tiny ACT policy trained a few steps with
the real LeRobot drives a live session (``driver = "policy:PATH"``) over a real socket; the
person takes over, and at the hand-back the policy drops its queued actions and decides
afresh from the state it finds; the record names the policy as the driver."""

from __future__ import annotations

import asyncio
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from tests.learn_extra import require_learn_extra
from tests.server.harness import client, hand, running_server
from workcell.cli.main import main
from workcell.learn.checkpoint import PolicyCheckpoint
from workcell.protocol import messages as m
from workcell.record.store import Store
from workcell.task import events as ev

TINY_ACT = (
    "--lerobot=--policy.dim_model=32",
    "--lerobot=--policy.dim_feedforward=64",
    "--lerobot=--policy.n_heads=2",
    "--lerobot=--policy.latent_dim=8",
)


@pytest.fixture(scope="module")
def tiny_policy(lerobot_dir: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """``workcell train`` for 2 steps on the export tests' dataset."""
    require_learn_extra()
    out = tmp_path_factory.mktemp("train") / "tiny-act"
    done = subprocess.run(
        [sys.executable, "-m", "workcell", "train", "--dataset", str(lerobot_dir),
         "--out", str(out), "--steps", "2", *TINY_ACT],
        capture_output=True, text=True, timeout=600, check=False,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-3000:] + done.stdout[-2000:]
    return out


@pytest.mark.slow
def test_the_person_takes_over_from_a_policy_and_hands_back(
    tiny_policy: Path, tmp_path: Path
) -> None:
    operator_id = PolicyCheckpoint.locate(tiny_policy).operator_id
    settings: dict[str, object] = {
        "driver": f"policy:{tiny_policy}",
        "task": {"countdown_s": 0.0, "time_limit_s": 6.0},
    }

    async def scenario() -> None:
        with running_server(tmp_path) as server:
            async with client(server) as person:
                await person.hello()
                await person.send(m.StartSession(settings=settings))
                state = await person.wait_for(
                    lambda x: (
                        isinstance(x, m.State | m.Error)
                        and (not isinstance(x, m.State) or x.t_sim > 1.0)
                    ),
                    120,
                )
                assert isinstance(state, m.State) and state.hud is not None, state
                assert state.hud.driver == f"policy:{operator_id}"
                await person.send(m.TakeOver(reason="it drifts"))
                took = await person.wait_for(lambda x: isinstance(x, ev.TookOver), 30)
                assert isinstance(took, ev.TookOver) and took.driver == f"policy:{operator_id}"
                for _ in range(20):
                    await person.input(left=hand(grip=1.0), right=hand(grip=1.0))
                    await asyncio.sleep(0.03)
                await person.send(m.HandBack())
                await person.wait_for(lambda x: isinstance(x, ev.HandedBack), 30)
                ended = await person.wait_for(lambda x: isinstance(x, m.SessionEnded), 120)
                assert isinstance(ended, m.SessionEnded) and ended.reason == "completed"

    asyncio.run(scenario())
    with Store.open(tmp_path / "store.sqlite", writer=False) as store:
        (trial,) = store.trials()
        flags = np.asarray(store.frames(trial.trial_id)["intervention"])
        kinds = [
            e.kind for e in store.events(trial.trial_id) if e.kind in ("take_over", "hand_back")
        ]
    assert trial.driver == f"policy:{operator_id}" and trial.outcome == "timeout"
    corrected = np.flatnonzero(flags == 1.0)
    assert len(corrected) > 0 and flags[-1] == 0.0  # the policy drove again to the end
    assert kinds == ["take_over", "hand_back"]


@pytest.mark.slow
def test_the_scripted_corrector_takes_over_from_a_policy_and_hands_back(
    tiny_policy: Path, tmp_path: Path
) -> None:
    """``workcell collect --operator policy:PATH --corrector expert``: the policy (2 steps
    trained) stalls, the expert takes over, brings the box to its next stage and hands back;
    the policy drives again from there (its queued actions dropped)."""
    store = tmp_path / "corrected.sqlite"
    args = ["collect", "--operator", f"policy:{tiny_policy}", "--corrector", "expert",
            "--stall-s", "1", "--mode", "collection", "--trials", "1", "--set",
            "task.time_limit_s=25", "--set", "task.countdown_s=0", "--writer", "inline",
            "--store", str(store)]  # fmt: skip
    assert main(args) == 0
    operator_id = PolicyCheckpoint.locate(tiny_policy).operator_id
    with Store.open(store, writer=False) as reader:
        (trial,) = reader.trials()
        flags = np.asarray(reader.frames(trial.trial_id)["intervention"])
        switches = [
            (e.kind, e.payload["reason"], e.payload["operator_id"], e.payload["driver"])
            for e in reader.events(trial.trial_id)
            if e.kind in ("take_over", "hand_back")
        ]
    driver = f"policy:{operator_id}"
    assert trial.driver == driver
    assert switches[0] == ("take_over", "stalled 1 s at none", "expert", driver)
    assert switches[1][0] == "hand_back" and switches[1][1].startswith("reached ")
    # one stretch of corrected frames per take-over, the policy's frames between them
    starts = np.flatnonzero(np.diff(flags) == 1.0)
    assert flags[0] == 0.0 and len(starts) == [s[0] for s in switches].count("take_over")
    ends = np.flatnonzero(np.diff(flags) == -1.0)
    assert len(ends) == [s[0] for s in switches].count("hand_back")
