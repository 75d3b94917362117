"""The invite tokens of a study that ``workcell serve --study`` runs: one per participant
and one for the admin page.

They are kept in a file beside the store (``<store>.<study>.invites.json``, readable by its
owner only), so invite links stay valid across server restarts. A study that grows keeps
the tokens it had and gains new ones; a participant's token opens only their own session.
The invites are those of the current study file: a participant it no longer holds (its
``participants`` shrank) loses their invite, dropped from the file (:attr:`Invites.dropped`
says whose), so that growing the study again issues them a new one. Each invite records
when it was issued; with the study's ``invite_days`` it expires that many days later.
"""

from __future__ import annotations

import contextlib
import json
import os
import secrets
import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path

from workcell.errors import ConfigError
from workcell.study.config import StudyConfig
from workcell.study.plan import participant_ids

TOKEN_BYTES = 18
SECONDS_PER_DAY = 86_400.0


@dataclass(frozen=True)
class Invites:
    study: str
    admin: str
    participants: Mapping[str, str]
    """Participant id -> token."""
    issued: Mapping[str, float] = field(default_factory=dict)
    """Participant id -> when their invite was issued (Unix seconds)."""
    dropped: tuple[str, ...] = ()
    """Participants whose invites this load dropped: the study no longer holds them."""

    def expires(self, participant: str, days: float) -> float | None:
        """When ``participant``'s invite stops opening anything (Unix seconds), for invites
        valid ``days`` days; None when they never expire (``days`` 0)."""
        if days <= 0:
            return None
        return self.issued[participant] + days * SECONDS_PER_DAY


def invites_path(store: Path, study: StudyConfig) -> Path:
    return store.with_name(f"{store.name}.{study.name}.invites.json")


def _new_token() -> str:
    return secrets.token_urlsafe(TOKEN_BYTES)


def _read(path: Path) -> dict[str, object]:
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as error:
        raise ConfigError(
            [f"{path}: cannot read the study's invites ({error}); move it away to issue new ones"]
        ) from None
    if not isinstance(data, dict):
        raise ConfigError([f"{path}: not an invites file (a JSON object)"])
    return data


def _tokens(data: Mapping[str, object], key: str, path: Path) -> dict[str, str]:
    value = data.get(key, {})
    if not isinstance(value, dict) or not all(
        isinstance(k, str) and isinstance(v, str) and len(v) >= 8 for k, v in value.items()
    ):
        raise ConfigError([f"{path}: {key} must map names to tokens of 8 or more characters"])
    return dict(value)


def _issued(data: Mapping[str, object], path: Path) -> dict[str, float]:
    """When each invite was issued, as the file says (UTC times, ISO 8601)."""
    value = data.get("issued", {})
    if not isinstance(value, dict):
        raise ConfigError([f"{path}: issued must map participants to the times (UTC)"])
    issued = {}
    for participant, when in value.items():
        try:
            moment = datetime.fromisoformat(when) if isinstance(when, str) else None
        except ValueError:
            moment = None
        if moment is None or moment.tzinfo is None:
            raise ConfigError(
                [
                    f"{path}: issued.{participant} = {str(when)[:40]!r}: must be a time with "
                    'its zone, e.g. "2026-01-31T09:00:00Z"'
                ]
            )
        issued[participant] = moment.timestamp()
    return issued


def load_or_create(path: Path, study: StudyConfig) -> Invites:
    """The study's invites from ``path``: issued now to participants who have none,
    dropped for those the study no longer holds, and written back when that changed
    anything."""
    data = _read(path) if path.exists() else {}
    if data and data.get("study") != study.name:
        raise ConfigError(
            [f"{path}: holds the invites of study {data.get('study')!r}, not {study.name!r}"]
        )
    now = time.time()
    admin = data.get("admin")
    held = _tokens(data, "participants", path)
    issued = _issued(data, path)
    changed = not isinstance(admin, str) or len(admin) < 8
    if changed:
        admin = _new_token()
    current = participant_ids(study)
    participants, when = {}, {}
    for participant in current:
        kept = participant in held and participant in issued
        participants[participant] = held.get(participant) or _new_token()
        when[participant] = issued[participant] if kept else now
        changed = changed or not kept
    assert isinstance(admin, str)
    dropped = tuple(p for p in held if p not in participants)
    invites = Invites(study.name, admin, participants, when, dropped)
    if changed or set(held) | set(issued) != set(current):
        _write(path, invites)
    return invites


def _write(path: Path, invites: Invites) -> None:
    body = {
        "study": invites.study,
        "admin": invites.admin,
        "participants": invites.participants,
        "issued": {p: _utc(t) for p, t in invites.issued.items()},
    }
    temporary = path.with_name(path.name + ".tmp")
    with contextlib.suppress(FileNotFoundError):
        temporary.unlink()
    descriptor = os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    with os.fdopen(descriptor, "w", encoding="utf-8") as file:
        json.dump(body, file, indent=2, sort_keys=True)
        file.write("\n")
        file.flush()
        os.fsync(file.fileno())
    temporary.replace(path)


def minute_utc(moment: float) -> str:
    """``moment`` (Unix seconds) as people read it: ``2026-01-31 09:00 UTC``."""
    return time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime(moment))


def _utc(moment: float) -> str:
    return datetime.fromtimestamp(moment, UTC).isoformat(timespec="seconds").replace("+00:00", "Z")
