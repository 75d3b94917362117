"""Real stores for the export and environment tests, recorded once per test session.

``mixed``: session 1 has two successful expert trials (the second excluded by a reviewer),
session 2 one timeout (2 s limit), session 3 one interrupted trial (stopped after 1 s).
``short``: two 1.5 s timeouts, cheap enough to render every frame.
"""

from __future__ import annotations

import functools
import os
from dataclasses import dataclass
from pathlib import Path

from workcell.cli.main import main
from workcell.recording.in_process import InProcessStore
from workcell.recording.recorded_session import RecordedSession, RecordedSessionConfig
from workcell.session.load import resolve_session_config
from workcell.task.events import InterruptionReason

INTERRUPT_AFTER_S = 1.0
REVIEWER = "tests"


@dataclass(frozen=True)
class Stores:
    mixed: Path
    short: Path


def collect(store: Path, *args: str) -> None:
    assert main(["collect", "--mode", "collection", "--store", str(store), *args]) == 0


def record_interrupted(store: Path, seed: int) -> None:
    """One collection trial stopped by the operator (``application_quit``) after 1 s."""
    config = resolve_session_config(flags={"task.mode": "collection", "seed": seed})
    recorded = RecordedSessionConfig(session=config, store=store, writer="inline", max_trials=1)
    with RecordedSession.open(recorded) as session:

        def after_one_second() -> InterruptionReason | None:
            running = session.runner.current is not None
            late = running and session.runner.trial_time >= INTERRUPT_AFTER_S
            return "application_quit" if late else None

        assert session.run(should_stop=after_one_second) == "application_quit"


def exclude_trial(store: Path, index: int, reason: str) -> str:
    """A reviewer's ``exclude`` annotation on the store's ``index``-th trial; its id."""
    with InProcessStore.open(store, writer=True) as writer:
        trial_id = writer.trials()[index].trial_id
        writer.annotate(trial_id, "exclude", reason, REVIEWER)
    return trial_id


@functools.cache
def build(root: Path) -> Stores:
    """Record both stores under ``root`` (once per ``root``)."""
    os.environ.setdefault("MUJOCO_GL", "egl")
    root.mkdir(parents=True, exist_ok=True)
    mixed = root / "mixed.sqlite"
    collect(mixed, "--trials", "2", "--seed", "0")
    collect(mixed, "--trials", "1", "--seed", "1", "--set", "task.time_limit_s=2")
    record_interrupted(mixed, seed=2)
    exclude_trial(mixed, 1, "operator bumped the conveyor")
    short = root / "short.sqlite"
    collect(short, "--trials", "2", "--seed", "3", "--set", "task.time_limit_s=1.5")
    return Stores(mixed, short)
