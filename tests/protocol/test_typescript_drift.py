"""The committed web/src/protocol.ts is what the Python message models generate."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import get_args, get_type_hints

from workcell.protocol import messages as m
from workcell.protocol.scene import Pose
from workcell.protocol.typescript import OUTPUT, REGENERATE, generate, main, ts_type
from workcell.session.config import Mode
from workcell.task import events as ev
from workcell.task.hud import Hud


def test_committed_typescript_matches_the_message_models() -> None:
    committed = OUTPUT.read_text(encoding="utf-8") if OUTPUT.exists() else "(missing)"
    assert committed == generate(), (
        f"{OUTPUT} is stale: the protocol dataclasses changed. Run `{REGENERATE}` and commit "
        "the regenerated file."
    )


def test_check_mode_reports_a_stale_file(tmp_path: Path) -> None:
    target = tmp_path / "protocol.ts"
    assert main(["--check", "--output", str(target)]) == 1
    assert main(["--output", str(target)]) == 0
    assert main(["--check", "--output", str(target)]) == 0


def test_type_spelling() -> None:
    assert ts_type(Pose) == "Pose"
    assert ts_type(tuple[float, float]) == "readonly [number, number]"
    assert ts_type(Pose | None) == "Pose | null"
    assert ts_type(tuple[Pose, ...]) == "readonly Pose[]"
    assert ts_type(tuple[str | None, ...]) == "readonly (string | null)[]"
    assert ts_type(tuple[tuple[Pose, ...], ...]) == "readonly (readonly Pose[])[]"
    assert ts_type(dict[str, object]) == "{ readonly [key: string]: unknown }"


def test_generated_text_has_unions_and_constants() -> None:
    text = generate()
    assert 'export const SUBPROTOCOL = "workcell.v1" as const;' in text
    assert "export const PROTOCOL_VERSION = 1 as const;" in text
    assert 'readonly type: "input";' in text
    for cls in m.CLIENT_MESSAGES:
        assert f"  | {cls.__name__}" in text.split("export type ClientMessage =")[1].split(";")[0]
    server = text.split("export type ServerMessage =")[1].split(";")[0]
    for cls in m.SERVER_MESSAGES:
        name = "TaskEvent" if cls in ev.TASK_EVENTS else cls.__name__
        assert f"  | {name}" in server


def _union(text: str, name: str) -> str:
    return text.split(f"export type {name} =")[1].split(";", maxsplit=1)[0]


def test_every_task_event_is_a_member_of_the_generated_union_told_apart_by_kind() -> None:
    text = generate()
    members = _union(text, "TaskEvent")
    for cls in ev.TASK_EVENTS:
        assert f"  | {cls.__name__}" in members
        interface = text.split(f"export interface {cls.__name__} {{")[1].split("\n}")[0]
        kind = next(f.default for f in dataclasses.fields(cls) if f.name == "kind")
        assert f'readonly kind: "{kind}";' in interface
        assert 'readonly type: "event";' in interface
    grasp = text.split("export interface GraspChanged {")[1].split("\n}")[0]
    assert "readonly engaged: boolean;" in grasp
    ended = text.split("export interface TrialEnded {")[1].split("\n}")[0]
    assert "readonly outcome: Outcome;" in ended
    assert "readonly interruption_reason: InterruptionReason | null;" in ended


def test_mode_outcome_and_reasons_are_exported_as_unions_of_their_literals() -> None:
    text = generate()
    for name, literal in (
        ("Mode", Mode),
        ("Outcome", ev.Outcome),
        ("InterruptionReason", ev.InterruptionReason),
    ):
        spelled = " | ".join(f'"{value}"' for value in get_args(literal))
        assert f"export type {name} = {spelled};" in text
    assert 'export type HudPhase = "countdown" | "running" | "finished";' in text
    hud = text.split("export interface Hud {")[1].split("\n}")[0]
    assert "readonly mode: Mode;" in hud and "readonly phase: HudPhase;" in hud


def test_the_hud_is_one_type_from_the_task_to_the_wire() -> None:
    assert get_type_hints(m.State)["hud"] == Hud | None
