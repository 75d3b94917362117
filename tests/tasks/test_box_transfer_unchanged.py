"""Box transfer on the task API records the trials it recorded before, bit for bit: the
same seeds give the same frames, events and trial results in every column the record had
then (``golden_trials.json``; see :mod:`tests.tasks.recorded_fingerprint`)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from tests.tasks.recorded_fingerprint import (
    CASES,
    ENV_CASES,
    GOLDEN,
    env_fingerprint,
    fingerprint,
    record,
)


@pytest.mark.parametrize("case", sorted(CASES))
def test_a_recorded_session_is_what_it_was(case: str, tmp_path: Path) -> None:
    golden = json.loads(GOLDEN.read_text())
    store = tmp_path / "s.sqlite"
    record(store, CASES[case])
    assert fingerprint(store, golden["columns"]) == golden["cases"][case]


@pytest.mark.parametrize("case", sorted(ENV_CASES))
def test_an_environment_episode_is_what_it_was(case: str) -> None:
    """The environment's observations, rewards and ends over an episode the expert drives
    (the first delivers its box at step 437) are what they were before the task API."""
    golden = json.loads(GOLDEN.read_text())
    assert env_fingerprint(*ENV_CASES[case]) == golden["environments"][case]
