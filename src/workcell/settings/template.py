"""The commented TOML template: every setting of a configuration, each under a comment
with its documentation, unit and allowed values taken from its declaration.

``workcell config --defaults`` prints the template of the defaults; loading it back
(:func:`workcell.session.toml_io.from_mapping`) gives the defaults again.
"""

from __future__ import annotations

import dataclasses
import json

from workcell.settings.declare import field_doc, spec_of
from workcell.settings.validate import described
from workcell.settings.walk import type_hints


def to_toml(config: object) -> str:
    """Every field of a configuration dataclass as commented TOML."""
    lines: list[str] = []
    _emit(config, "", lines)
    return "\n".join(lines).strip() + "\n"


def _emit(config: object, path: str, lines: list[str]) -> None:
    hints = type_hints(type(config))
    sections = []
    for field in dataclasses.fields(config):  # type: ignore[arg-type]
        value = getattr(config, field.name)
        spec = spec_of(field)
        if spec is None:
            sections.append((field, value))
            continue
        lines.append(f"# {described(spec, hints[field.name])}")
        lines.append(f"{field.name} = {_literal(value)}")
    for field, value in sections:
        lines.append("")
        lines.append(f"# {field_doc(field)}")
        lines.append(f"[{path}{field.name}]")
        _emit(value, f"{path}{field.name}.", lines)


def _literal(value: object) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int | float):
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, tuple | list):
        return "[" + ", ".join(_literal(v) for v in value) + "]"
    raise TypeError(f"cannot write {value!r} as TOML")
