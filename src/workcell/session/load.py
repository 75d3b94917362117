"""Resolve a session configuration: defaults, then a TOML file, then command-line flags."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from workcell.session.config import SessionConfig
from workcell.session.toml_io import apply_overrides, from_mapping, load_toml


def resolve_session_config(
    config_file: Path | None = None,
    overrides: Sequence[str] = (),
    flags: Mapping[str, Any] | None = None,
) -> SessionConfig:
    """The session configuration from ``config_file`` (optional), ``--set KEY=VALUE``
    ``overrides`` and dedicated ``flags`` (dotted keys, None values skipped), in that order.
    Raises ConfigError with one line per problem."""
    data: dict[str, Any] = load_toml(config_file) if config_file is not None else {}
    data = apply_overrides(data, overrides)
    for key, value in (flags or {}).items():
        if value is not None:
            _put(data, key, value)
    return from_mapping(SessionConfig, data)


def _put(data: dict[str, Any], key: str, value: Any) -> None:
    """``value`` at the dotted ``key`` of ``data``, unless a value stands where ``key``
    needs a section (``task = 3`` in the file): that is reported when the file is read."""
    table = data
    *parents, leaf = key.split(".")
    for part in parents:
        table = table.setdefault(part, {})
        if not isinstance(table, dict):
            return
    table[leaf] = value
