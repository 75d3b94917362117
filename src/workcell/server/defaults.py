"""``GET /api/defaults``: every session setting with its default and documentation,
walked from the :class:`~workcell.session.config.SessionConfig` dataclasses."""

from __future__ import annotations

import dataclasses
from typing import Any, Literal, get_args, get_origin, get_type_hints

from workcell.protocol.api import Defaults, SectionInfo, SettingInfo, SettingKind
from workcell.protocol.codec import to_json_value
from workcell.protocol.messages import PROTOCOL_VERSION
from workcell.session.config import SessionConfig
from workcell.settings import field_doc


def setting_kind(hint: Any) -> tuple[SettingKind, tuple[str, ...] | None]:
    """The setup page's kind of input for a field type (and a choice's values)."""
    if get_origin(hint) is Literal:
        return "choice", tuple(str(a) for a in get_args(hint))
    if hint is bool:
        return "bool", None
    if hint is int:
        return "int", None
    if hint is float:
        return "float", None
    if get_origin(hint) is tuple:
        items = {a for a in get_args(hint) if a is not Ellipsis}
        return ("int_list" if items == {int} else "float_list"), None
    return "text", None


def _walk(cls: type, prefix: str, sections: list[SectionInfo], fields: list[SettingInfo]) -> None:
    hints = get_type_hints(cls)
    defaults = cls()
    for f in dataclasses.fields(cls):
        key, hint = f"{prefix}{f.name}", hints[f.name]
        if dataclasses.is_dataclass(hint):
            sections.append(SectionInfo(key=key, doc=field_doc(f)))
            _walk(hint, f"{key}.", sections, fields)  # type: ignore[arg-type]
            continue
        kind, choices = setting_kind(hint)
        default = to_json_value(getattr(defaults, f.name))
        fields.append(SettingInfo(key, kind, default, field_doc(f), choices))


def session_defaults() -> Defaults:
    sections: list[SectionInfo] = []
    fields: list[SettingInfo] = []
    _walk(SessionConfig, "", sections, fields)
    settings: dict[str, object] = to_json_value(dataclasses.asdict(SessionConfig()))
    return Defaults(
        protocol=PROTOCOL_VERSION,
        settings=settings,
        sections=tuple(sections),
        fields=tuple(fields),
    )
