"""The invites file: when each invite was issued (written for an older file's invites
without changing them), a bad time in it and a bad ``invite_days`` named in one line."""

from __future__ import annotations

import json
import time
import tomllib
from pathlib import Path

import pytest

from workcell.errors import ConfigError
from workcell.study.config import StudyConfig, study_from_mapping
from workcell.study.invites import SECONDS_PER_DAY, invites_path, load_or_create
from workcell.study.template import TEMPLATE


def test_an_older_invites_file_keeps_its_tokens_and_gains_their_issue_times(
    tmp_path: Path,
) -> None:
    study = StudyConfig(name="pilot", participants=2)
    path = invites_path(tmp_path / "store.sqlite", study)
    tokens = {"p01": "token-of-p01", "p02": "token-of-p02"}
    path.write_text(json.dumps({"study": "pilot", "admin": "admin-token", "participants": tokens}))
    before = time.time()
    invites = load_or_create(path, study)
    assert (invites.admin, dict(invites.participants)) == ("admin-token", tokens)
    assert all(before - 1 <= t <= time.time() for t in invites.issued.values())
    assert invites.expires("p01", 0.0) is None  # invite_days 0: never
    assert invites.expires("p01", 1.5) == invites.issued["p01"] + 1.5 * SECONDS_PER_DAY
    again = load_or_create(path, study)  # the times were written, to the second
    assert {p: round(t) for p, t in again.issued.items()} == {
        p: int(t) for p, t in invites.issued.items()
    }


@pytest.mark.parametrize("when", ["yesterday", "2026-01-31T09:00:00", 17])
def test_a_bad_issue_time_is_one_line_naming_it(tmp_path: Path, when: object) -> None:
    study = StudyConfig(name="pilot", participants=1)
    path = invites_path(tmp_path / "store.sqlite", study)
    load_or_create(path, study)
    held = json.loads(path.read_text("utf-8"))
    held["issued"]["p01"] = when
    path.write_text(json.dumps(held), "utf-8")
    with pytest.raises(ConfigError) as refused:
        load_or_create(path, study)
    assert refused.value.problems == (
        f"{path}: issued.p01 = {str(when)!r}: must be a time with its zone, e.g. "
        '"2026-01-31T09:00:00Z"',
    )


def test_invite_days_is_checked() -> None:
    def days(value: str) -> str:
        return TEMPLATE.replace("invite_days = 0", f"invite_days = {value}")

    assert study_from_mapping(tomllib.loads(days("14"))).invite_days == 14
    with pytest.raises(ConfigError) as refused:
        study_from_mapping(tomllib.loads(days("-1")))
    assert refused.value.problems == ("invite_days = -1: must be between 0 and 3650 days",)
