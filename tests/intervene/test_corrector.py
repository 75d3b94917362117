"""The scripted corrector with the real simulation, expert and store: a driver that holds
still is taken over once its trial's stage has not advanced for ``stall_s``, the expert
drives the trial to its next stage and hands back, and the store records it as a live
correction (events, the corrected frames, the trial's driver)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from workcell.control.command import Command
from workcell.control.simulation import Simulation
from workcell.errors import ConfigError
from workcell.intervene.corrector import ScriptedCorrector
from workcell.intervene.operator import InterveningOperator
from workcell.intervene.rules import CorrectorRules
from workcell.record.store import Store
from workcell.recording.drivers import Driving, ExpertDriver, InterveningDriver
from workcell.recording.recorded_session import RecordedSession, RecordedSessionConfig
from workcell.session.config import SessionConfig
from workcell.session.load import resolve_session_config
from workcell.sim.world import World
from workcell.tasks.box_transfer.stages import TASK_STAGES

STALL_S = 1.0
STILL = "still"


class HoldStill:
    """A driver that never moves (Resumable): its trial's stage never advances."""

    def start_trial(self, trial_seed: int) -> None:
        pass

    def act(self, world: World) -> Command:
        return Command()

    def resume(self, world: World, command: Command) -> None:
        pass


@dataclass(frozen=True)
class StillDriver:
    def build(self, config: SessionConfig, sim: Simulation) -> Driving:
        return Driving(HoldStill(), name=STILL)


def _record(store: Path, time_limit_s: float) -> int:
    """One collection trial of the still driver, watched by the scripted corrector; returns
    its take-overs."""
    config = resolve_session_config(
        flags={
            "task.mode": "collection",
            "task.countdown_s": 0.0,
            "task.time_limit_s": time_limit_s,
            "operator_id": STILL,
        }
    )
    recorded = RecordedSessionConfig(
        session=config,
        driver=InterveningDriver(StillDriver(), corrector=ExpertDriver()),
        store=store,
        writer="inline",
        max_trials=1,
    )
    with RecordedSession.open(recorded) as session:
        operator = session.operator
        assert isinstance(operator, InterveningOperator)
        corrector = ScriptedCorrector(operator, session.runner, CorrectorRules(stall_s=STALL_S))
        assert session.run(after_step=corrector.after_step) == "completed"
    return corrector.take_overs


def test_a_stalled_driver_is_taken_over_driven_to_the_next_stage_and_handed_back(
    tmp_path: Path,
) -> None:
    store = tmp_path / "corrected.sqlite"
    take_overs = _record(store, time_limit_s=20.0)
    with Store.open(store, writer=False) as reader:
        (trial,) = reader.trials()
        frames = reader.frames(trial.trial_id)
        events = [e for e in reader.events(trial.trial_id) if e.kind in ("take_over", "hand_back")]
    assert trial.driver == STILL
    assert take_overs >= 1
    # the first correction: stalled at the start, handed back at the box's next stage
    took, handed = events[0], events[1]
    assert (took.kind, took.payload["reason"]) == ("take_over", f"stalled {STALL_S:g} s at none")
    assert handed.kind == "hand_back" and handed.payload["reason"].startswith("reached ")
    reached = handed.payload["reason"].removeprefix("reached ")
    assert TASK_STAGES.index(reached) > TASK_STAGES.index("none")
    assert took.payload["operator_id"] == "expert" and took.payload["driver"] == STILL
    assert took.t_sim is not None and handed.t_sim is not None
    assert took.t_sim == pytest.approx(STALL_S, abs=0.051)
    # take-overs and hand-backs alternate, one stretch of corrected frames for each
    kinds = [e.kind for e in events]
    assert kinds == ["take_over", "hand_back"] * (len(kinds) // 2) + ["take_over"] * (
        len(kinds) % 2
    )
    assert kinds.count("take_over") == take_overs
    flags = np.asarray(frames["intervention"]) == 1.0
    t = np.asarray(frames["t_sim"])
    starts = np.flatnonzero(flags[1:] & ~flags[:-1]) + 1
    ends = np.flatnonzero(flags[:-1] & ~flags[1:]) + 1
    assert not flags[0] and len(starts) == take_overs
    assert np.all(np.abs(t[starts] - [e.t_sim for e in events if e.kind == "take_over"]) <= 0.051)
    backs = [e.t_sim for e in events if e.kind == "hand_back"]
    assert np.all(np.abs(t[ends[: len(backs)]] - backs) <= 0.051)
    # the still driver never moved a box: every stage past none is the expert's doing
    stages = [str(s) for s in frames["stage"]]
    assert stages[int(ends[0])] == reached
    assert set(stages[: int(starts[0])]) == {"none"}
    # the still driver opens its grippers: the box handed back in them is dropped at once
    assert [(e.kind, e.payload["reason"]) for e in events[2:]] == [
        ("take_over", f"dropped the box at {reached}")
    ]


@pytest.mark.parametrize("field", ["stall_s", "drop_s"])
def test_rules_out_of_range_are_refused_naming_the_range(field: str) -> None:
    with pytest.raises(ConfigError, match=f"{field} = 0: must be .* between 0.1 and 3600"):
        CorrectorRules(**{field: 0.0})  # type: ignore[arg-type]
