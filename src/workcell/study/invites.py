"""The invite tokens of a study that ``workcell serve --study`` runs: one per participant
and one for the admin page.

They are kept in a file beside the store (``<store>.<study>.invites.json``, readable by its
owner only), so invite links stay valid across server restarts. A study that grows keeps
the tokens it had and gains new ones; a participant's token opens only their own session.
"""

from __future__ import annotations

import contextlib
import json
import os
import secrets
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

from workcell.errors import ConfigError
from workcell.study.config import StudyConfig
from workcell.study.plan import participant_ids

TOKEN_BYTES = 18


@dataclass(frozen=True)
class Invites:
    study: str
    admin: str
    participants: Mapping[str, str]
    """Participant id -> token."""


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


def load_or_create(path: Path, study: StudyConfig) -> Invites:
    """The study's invites from ``path``, created (or completed for new participants) and
    written back when needed."""
    data = _read(path) if path.exists() else {}
    if data and data.get("study") != study.name:
        raise ConfigError(
            [f"{path}: holds the invites of study {data.get('study')!r}, not {study.name!r}"]
        )
    admin = data.get("admin")
    participants = _tokens(data, "participants", path)
    changed = not isinstance(admin, str) or len(admin) < 8
    if changed:
        admin = _new_token()
    for participant in participant_ids(study):
        if participant not in participants:
            participants[participant] = _new_token()
            changed = True
    assert isinstance(admin, str)
    invites = Invites(study.name, admin, participants)
    if changed:
        _write(path, invites)
    return invites


def _write(path: Path, invites: Invites) -> None:
    body = {"study": invites.study, "admin": invites.admin, "participants": invites.participants}
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
