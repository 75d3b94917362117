"""The setup page's form hints, generated from the declarations: per setting its unit, the
allowed values in words and the bounds a form can check as the operator types (the
server stays the one validator: a hint only warns early)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import get_args, get_origin

from workcell.settings.validate import allowed_text
from workcell.settings.walk import leaf_settings


@dataclass(frozen=True)
class SettingHint:
    """One setting's hint: ``key`` as in the TOML file; ``unit`` (empty for a choice or
    text, ``1`` for a dimensionless number); ``allowed`` in words, as in the template and
    the README; ``low`` / ``high`` bound a number or each item of a list (``low_open``:
    ``low`` excluded), ``whole``: whole numbers only."""

    key: str
    unit: str
    allowed: str
    low: float | None
    high: float | None
    low_open: bool
    whole: bool


@dataclass(frozen=True)
class SettingHints:
    """``GET /api/settings/hints``: a hint for every setting, in declaration order."""

    hints: tuple[SettingHint, ...]


def setting_hints(cls: type) -> SettingHints:
    """The hints of every setting of the configuration dataclass ``cls``."""
    hints = []
    for declared in leaf_settings(cls):
        hint, spec = declared.hint, declared.spec
        item = get_args(hint)[0] if get_origin(hint) is tuple else hint
        hints.append(
            SettingHint(
                key=declared.key,
                unit=spec.unit,
                allowed=allowed_text(spec, hint),
                low=spec.low,
                high=spec.high,
                low_open=spec.low_open,
                whole=item is int,
            )
        )
    return SettingHints(hints=tuple(hints))
