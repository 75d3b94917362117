"""The committed web/src/protocol.ts is what the Python message models generate."""

from __future__ import annotations

from pathlib import Path

from workcell.protocol import messages as m
from workcell.protocol.typescript import OUTPUT, REGENERATE, generate, main, ts_type


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
    assert ts_type(m.Pose) == "Pose"
    assert ts_type(tuple[float, float]) == "readonly [number, number]"
    assert ts_type(m.Pose | None) == "Pose | null"
    assert ts_type(tuple[m.Pose, ...]) == "readonly Pose[]"
    assert ts_type(tuple[str | None, ...]) == "readonly (string | null)[]"
    assert ts_type(tuple[tuple[m.Pose, ...], ...]) == "readonly (readonly Pose[])[]"
    assert ts_type(dict[str, object]) == "{ readonly [key: string]: unknown }"


def test_generated_text_has_unions_and_constants() -> None:
    text = generate()
    assert 'export const SUBPROTOCOL = "workcell.v1" as const;' in text
    assert "export const PROTOCOL_VERSION = 1 as const;" in text
    assert 'readonly type: "input";' in text
    for cls in m.CLIENT_MESSAGES:
        assert f"  | {cls.__name__}" in text.split("export type ClientMessage =")[1].split(";")[0]
    for cls in m.SERVER_MESSAGES:
        assert f"  | {cls.__name__}" in text.split("export type ServerMessage =")[1].split(";")[0]
