"""Generate ``web/src/protocol.ts`` from the protocol dataclasses.

Run ``python -m workcell.protocol.typescript`` to write the file, ``--check`` to fail when
the committed file differs from what the dataclasses give (CI and the drift test do this).
Each dataclass becomes a readonly interface (its docstrings become comments), a
``Literal`` or an ``Enum`` a union of string literals, a fixed tuple a TS tuple,
``X | None`` ``X | null``. The task's events and HUD (:mod:`workcell.task.events`,
:mod:`workcell.task.hud`) are messages too: the events become the discriminated union
``TaskEvent`` (``type`` ``"event"``, told apart by ``kind``).
"""

from __future__ import annotations

import argparse
import ast
import dataclasses
import enum
import inspect
import sys
import types
from collections.abc import Sequence
from pathlib import Path
from typing import Any, Literal, Union, get_args, get_origin, get_type_hints

from workcell.protocol import api, messages, scene
from workcell.session.config import Mode
from workcell.settings import hints
from workcell.task import events, hud

OUTPUT = Path(__file__).resolve().parents[3] / "web" / "src" / "protocol.ts"
REGENERATE = "python -m workcell.protocol.typescript"
_MODULES: tuple[types.ModuleType, ...] = (hud, events, scene, messages, api, hints)
_ALIASES: dict[str, Any] = {
    "Pose": scene.Pose,
    "Role": messages.Role,
    "InputSource": messages.InputSource,
    "HudPhase": hud.HudPhase,
    "Mode": Mode,
    "Outcome": events.Outcome,
    "InterruptionReason": events.InterruptionReason,
    "SessionEndReason": events.SessionEndReason,
    "ErrorCode": messages.ErrorCode,
    "SettingKind": api.SettingKind,
    "ParticipantState": api.ParticipantState,
}
_PRIMITIVES: dict[Any, str] = {
    int: "number",
    float: "number",
    str: "string",
    bool: "boolean",
    type(None): "null",
    object: "unknown",
}


def ts_type(hint: Any, *, use_aliases: bool = True) -> str:
    """The TypeScript spelling of a Python type hint."""
    if use_aliases:
        for name, alias in _ALIASES.items():
            if hint == alias:
                return name
    if hint in _PRIMITIVES:
        return _PRIMITIVES[hint]
    if isinstance(hint, type) and dataclasses.is_dataclass(hint):
        return hint.__name__
    if isinstance(hint, type) and issubclass(hint, enum.Enum):
        return " | ".join(f'"{member.value}"' for member in hint)
    origin, args = get_origin(hint), get_args(hint)
    if origin is Literal:
        return " | ".join(f'"{a}"' if isinstance(a, str) else str(a).lower() for a in args)
    if origin in (Union, types.UnionType):
        return " | ".join(ts_type(a) for a in args)
    if origin is tuple:
        if len(args) == 2 and args[1] is Ellipsis:
            inner = ts_type(args[0])
            compound = "|" in inner or inner.startswith("readonly")
            return f"readonly ({inner})[]" if compound else f"readonly {inner}[]"
        return f"readonly [{', '.join(ts_type(a) for a in args)}]"
    if origin is dict and args and args[0] is str:
        return f"{{ readonly [key: string]: {ts_type(args[1])} }}"
    raise TypeError(f"no TypeScript spelling for {hint!r}: extend workcell.protocol.typescript")


def _docs(module: types.ModuleType) -> tuple[list[str], dict[tuple[str, str], str]]:
    """Class names in source order and their docstrings: ``(name, "")`` for the class,
    ``(name, field)`` for a field's attribute docstring."""
    tree = ast.parse(inspect.getsource(module))
    order: list[str] = []
    field_docs: dict[tuple[str, str], str] = {}
    for node in tree.body:
        if not isinstance(node, ast.ClassDef):
            continue
        order.append(node.name)
        field_docs[(node.name, "")] = ast.get_docstring(node) or ""
        for current, following in zip(node.body, node.body[1:], strict=False):
            if (
                isinstance(current, ast.AnnAssign)
                and isinstance(current.target, ast.Name)
                and isinstance(following, ast.Expr)
                and isinstance(following.value, ast.Constant)
                and isinstance(following.value.value, str)
            ):
                field_docs[(node.name, current.target.id)] = following.value.value
    return order, field_docs


def _comment(text: str | None, indent: str = "") -> list[str]:
    if not text:
        return []
    lines = inspect.cleandoc(text).splitlines()
    if len(lines) == 1:
        return [f"{indent}/** {lines[0]} */"]
    return [f"{indent}/**", *(f"{indent} * {line}".rstrip() for line in lines), f"{indent} */"]


def _interface(cls: type, field_docs: dict[tuple[str, str], str]) -> list[str]:
    hints = get_type_hints(cls)
    out = [*_comment(field_docs[(cls.__name__, "")]), f"export interface {cls.__name__} {{"]
    for f in dataclasses.fields(cls):
        out += _comment(field_docs.get((cls.__name__, f.name)), "  ")
        out.append(f"  readonly {f.name}: {ts_type(hints[f.name])};")
    out.append("}")
    return out


def _union(name: str, members: Sequence[str]) -> list[str]:
    return [f"export type {name} =", *(f"  | {m}" for m in members[:-1]), f"  | {members[-1]};"]


def _server_members() -> list[str]:
    """The server's messages, with the task events named once as ``TaskEvent``."""
    names: list[str] = []
    for cls in messages.SERVER_MESSAGES:
        name = "TaskEvent" if cls in events.TASK_EVENTS else cls.__name__
        if name not in names:
            names.append(name)
    return names


def generate() -> str:
    """The whole text of ``web/src/protocol.ts``."""
    out = [
        f"// GENERATED by `{REGENERATE}` from src/workcell/protocol/",
        "// (messages.py, scene.py, api.py), the task's events and HUD",
        "// (src/workcell/task/events.py, hud.py) and the setup page's setting hints",
        "// (src/workcell/settings/hints.py).",
        "// Do not edit: change the Python dataclasses and regenerate.",
        "",
        f"export const PROTOCOL_VERSION = {messages.PROTOCOL_VERSION} as const;",
        f'export const SUBPROTOCOL = "{messages.SUBPROTOCOL}" as const;',
        "",
    ]
    for name, alias in _ALIASES.items():
        out.append(f"export type {name} = {ts_type(alias, use_aliases=False)};")
    for module in _MODULES:
        order, field_docs = _docs(module)
        for name in order:
            cls = getattr(module, name)
            if isinstance(cls, type) and dataclasses.is_dataclass(cls):
                out += ["", *_interface(cls, field_docs)]
    out += ["", "/** A task event: every transition of a session, told apart by `kind`. */"]
    out += _union("TaskEvent", [cls.__name__ for cls in events.TASK_EVENTS])
    out += ["", "/** What a client may send. */"]
    out += _union("ClientMessage", [cls.__name__ for cls in messages.CLIENT_MESSAGES])
    out += ["", "/** What the server sends. */"]
    out += _union("ServerMessage", _server_members())
    return "\n".join(out) + "\n"


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m workcell.protocol.typescript")
    parser.add_argument("--check", action="store_true", help="fail if the file is stale")
    parser.add_argument("--output", type=Path, default=OUTPUT, help="default: %(default)s")
    args = parser.parse_args(argv)
    text = generate()
    path: Path = args.output
    if args.check:
        current = path.read_text(encoding="utf-8") if path.exists() else ""
        if current != text:
            print(f"{path} is stale: run `{REGENERATE}`", file=sys.stderr)
            return 1
        return 0
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
