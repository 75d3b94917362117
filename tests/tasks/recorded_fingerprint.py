"""A recorded trial's fingerprint: a hash of everything its record holds that the
simulation decides (no ids, no wall-clock readings), over a fixed list of columns.

``golden_trials.json`` holds the fingerprints of a few expert sessions recorded before
box transfer moved onto the task API (``src/workcell/tasks/``), with the columns they
cover; columns added since are left out, so a new column never changes a fingerprint but
a changed value in an old one does. Regenerate it only for a deliberate change of the
simulation: ``python -m tests.tasks.recorded_fingerprint --write``.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import sqlite3
import sys
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from workcell.cli.main import main as workcell
from workcell.envs.actions import action_from_command
from workcell.envs.box_transfer import BoxTransferEnv
from workcell.export.boxes import box_feature_names
from workcell.tasks.elements.expert import ExpertOperator

GOLDEN = Path(__file__).with_name("golden_trials.json")

WALL_COLUMNS = frozenset(
    {"session_id", "trial_id", "event_id", "t_wall", "step_wall_ms", "hz_wall", "max_gap_s"}
)
"""Columns read from the wall clock or made at random (and every ``*_wall`` and
``*checksum`` column, which covers them): never part of a fingerprint."""
DISPOSITION_COLUMNS = frozenset({"quality_flags", "included", "exclusion_reason"})
"""Trial columns the audit's wall-clock checks (sampling gaps) can move."""

CASES: dict[str, tuple[str, ...]] = {
    "practice_assisted_seed1": ("--mode", "practice", "--seed", "1"),
    "collection_physical_seed2": (
        *("--mode", "collection", "--trials", "2", "--seed", "2"),
        *("--set", "world.grasp=physical"),
    ),
    "collection_randomized_seed3": (
        *("--mode", "collection", "--trials", "2", "--seed", "3"),
        *("--set", "world.randomization.start_shift=0.1"),
        *("--set", "world.randomization.target_shift=0.1"),
        *("--set", "world.randomization.start_yaw=0.1"),
        *("--set", "world.randomization.box_size=0.1"),
    ),
    "challenge_seed4": ("--mode", "challenge", "--trials", "2", "--seed", "4"),
}
"""Expert sessions whose records are fingerprinted: both grasp modes, every mode, a
randomized world."""


def record(store: Path, arguments: Sequence[str]) -> None:
    """Record one expert session into ``store`` with ``workcell collect``."""
    status = workcell(["collect", "--writer", "inline", "--store", str(store), *arguments])
    if status != 0:
        raise RuntimeError(f"workcell collect {' '.join(arguments)} exited {status}")


def stored_columns(connection: sqlite3.Connection, table: str) -> list[str]:
    """The columns of ``table`` a fingerprint may cover (wall-clock and id columns out)."""
    names = [row[1] for row in connection.execute(f"PRAGMA table_info({table})")]
    return [n for n in names if n not in WALL_COLUMNS and not n.endswith(("_wall", "checksum"))]


def fingerprint(store: Path, columns: dict[str, list[str]]) -> str:
    """SHA-256 of the trials, events and frames of the one session in ``store``, over
    ``columns`` (table -> names), in trial, sequence and frame order."""
    digest = hashlib.sha256()
    with sqlite3.connect(store) as connection:
        order = {
            "trials": "ORDER BY trial_index",
            "events": "ORDER BY seq",
            "frames": "JOIN trials USING (trial_id) ORDER BY trial_index, frame_index",
        }
        for table, names in columns.items():
            selected = ", ".join(f"{table}.{n}" for n in names)
            for row in connection.execute(f"SELECT {selected} FROM {table} {order[table]}"):
                digest.update(json.dumps([_exact(v) for v in row]).encode())
    return digest.hexdigest()


def _exact(value: object) -> object:
    """Floats by their exact bits (``float.hex``), everything else as it is."""
    return value.hex() if isinstance(value, float) else value


def current_columns(store: Path) -> dict[str, list[str]]:
    with sqlite3.connect(store) as connection:
        return {
            "trials": [
                n for n in stored_columns(connection, "trials") if n not in DISPOSITION_COLUMNS
            ],
            "events": stored_columns(connection, "events"),
            "frames": stored_columns(connection, "frames"),
        }


def write_golden(folder: Path) -> None:
    cases: dict[str, str] = {}
    columns: dict[str, list[str]] = {}
    for name, arguments in CASES.items():
        store = folder / f"{name}.sqlite"
        record(store, arguments)
        columns = columns or current_columns(store)
        cases[name] = fingerprint(store, columns)
    environments = {name: env_fingerprint(*case) for name, case in ENV_CASES.items()}
    golden = {"columns": columns, "cases": cases, "environments": environments}
    GOLDEN.write_text(json.dumps(golden, indent=1) + "\n")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--write", action="store_true", help="rewrite golden_trials.json")
    parser.add_argument("--folder", type=Path, required=True, help="where to record")
    options = parser.parse_args()
    if not options.write:
        sys.exit("nothing to do without --write")
    write_golden(options.folder)


ENV_INFO_KEYS = ("t_sim", "boxes_delivered", "is_success", "world_seed")
"""The ``info`` an environment step returned when the fingerprints were taken (keys added
since are left out, as new columns are)."""
ENV_CASES: dict[str, tuple[int, int]] = {"env_seed5": (5, 700), "env_seed6_short": (6, 40)}
"""Environment episodes fingerprinted: (reset seed, steps), the expert's command as each
step's action."""


def env_fingerprint(seed: int, steps: int) -> str:
    """SHA-256 of an environment episode's observations, rewards and ends: reset with
    ``seed``, then the expert's command at every step (as a policy would act), for at most
    ``steps`` steps."""
    env = BoxTransferEnv()
    pool = env.config.session.world.feeder.pool_size
    digest = hashlib.sha256()
    observation, _ = env.reset(seed=seed)
    expert = ExpertOperator(seed=seed)
    for _ in range(steps):
        boxes = observation["environment_state"][: len(box_feature_names(pool))]
        for value in (observation["agent_pos"], boxes):  # the task's goal came later
            digest.update(np.ascontiguousarray(value).tobytes())
        action = action_from_command(expert.act(env.sim.world))
        observation, reward, terminated, truncated, info = env.step(action)
        known = {key: info[key] for key in ENV_INFO_KEYS}
        digest.update(json.dumps([reward, terminated, truncated, known]).encode())
        if terminated or truncated:
            break
    env.close()
    return digest.hexdigest()
