"""``GET /api/defaults`` and ``GET /api/settings/hints``: every session setting with its
default, documentation and form hint, generated from the declarations of the
:class:`~workcell.session.config.SessionConfig` dataclasses."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from typing import Any, Literal, get_args, get_origin

from workcell.protocol.api import Defaults, SectionInfo, SettingInfo, SettingKind
from workcell.protocol.codec import to_json_value
from workcell.protocol.messages import PROTOCOL_VERSION
from workcell.session.config import SessionConfig
from workcell.settings.hints import SettingHints, setting_hints
from workcell.settings.validate import described
from workcell.settings.walk import Declared, walk
from workcell.tasks.registry import BUILT_IN

REGISTERED_CHOICES: dict[str, Callable[[], tuple[str, ...]]] = {
    "task.kind": lambda: tuple(BUILT_IN),
}
"""Text settings whose usual values a registry lists: the setup page offers them as a
choice (a task of one's own, ``module:Class``, is set with ``--set`` or a config file)."""


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


def session_defaults() -> Defaults:
    sections: list[SectionInfo] = []
    fields: list[SettingInfo] = []
    for item in walk(SessionConfig):
        if isinstance(item, Declared):
            kind, choices = setting_kind(item.hint)
            listed = REGISTERED_CHOICES.get(item.key)
            if listed is not None:
                kind, choices = "choice", listed()
            default = to_json_value(item.default)
            doc = described(item.spec, item.hint)
            fields.append(SettingInfo(item.key, kind, default, doc, choices))
        else:
            sections.append(SectionInfo(key=item.key, doc=item.doc))
    settings: dict[str, object] = to_json_value(dataclasses.asdict(SessionConfig()))
    return Defaults(
        protocol=PROTOCOL_VERSION,
        settings=settings,
        sections=tuple(sections),
        fields=tuple(fields),
    )


def session_hints() -> SettingHints:
    """The setup page's form hint of every session setting."""
    return setting_hints(SessionConfig)
