"""The workcell command line: help, version, dispatch and one-line errors."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from workcell import __version__
from workcell.cli.main import COMMANDS, main


@pytest.fixture(autouse=True)
def _gl(monkeypatch: pytest.MonkeyPatch) -> None:
    """main() sets MUJOCO_GL; keep that from leaking into other tests."""
    monkeypatch.setenv("MUJOCO_GL", os.environ.get("MUJOCO_GL", "egl"))


def _error_lines(err: str) -> list[str]:
    return [line for line in err.splitlines() if line]


def test_help_lists_the_commands(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--help"]) == 0
    out = capsys.readouterr().out
    assert "usage: workcell" in out
    assert "snapshot" in out


def test_version(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--version"]) == 0
    assert capsys.readouterr().out.strip() == f"workcell {__version__}"


def test_every_command_module_has_register_and_run() -> None:
    for module in COMMANDS:
        assert callable(module.register)
        assert callable(module.run)


def test_missing_command_is_one_error_line(capsys: pytest.CaptureFixture[str]) -> None:
    assert main([]) == 2
    captured = capsys.readouterr()
    lines = _error_lines(captured.err)
    assert len(lines) == 1
    assert lines[0].startswith("workcell: error: ")
    assert "command" in lines[0]
    assert captured.out == ""


@pytest.mark.parametrize("argv", [["fly"], ["snapshot", "--out", "a.png", "--bogus"]])
def test_bad_arguments_are_one_error_line(
    capsys: pytest.CaptureFixture[str], argv: list[str]
) -> None:
    assert main(argv) == 2
    lines = _error_lines(capsys.readouterr().err)
    assert len(lines) == 1
    assert lines[0].startswith("workcell: error: ")
    assert "--help" in lines[0]


@pytest.mark.parametrize(("given", "chosen"), [(None, "egl"), ("osmesa", "osmesa")])
def test_importing_workcell_chooses_egl_unless_told_otherwise(
    given: str | None, chosen: str
) -> None:
    """In a fresh process (MuJoCo reads MUJOCO_GL once, when it is first imported)."""
    environment = {k: v for k, v in os.environ.items() if k != "MUJOCO_GL"}
    if given is not None:
        environment["MUJOCO_GL"] = given
    code = (
        "import os, workcell.cli.main, sys; print(os.environ['MUJOCO_GL'], 'mujoco' in sys.modules)"
    )
    done = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        env=environment,
        check=False,
        timeout=60,
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == [chosen, "False"]


def test_python_dash_m_workcell() -> None:
    done = subprocess.run(
        [sys.executable, "-m", "workcell", "--version"],
        capture_output=True,
        text=True,
        check=False,
        timeout=60,
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == f"workcell {__version__}"


@pytest.mark.parametrize(
    "argv", [["config", "--defaults"], ["study", "--defaults"], ["study", "study.toml", "--json"]]
)
def test_a_closed_standard_output_ends_a_command_without_a_traceback(
    tmp_path: Path, argv: list[str]
) -> None:
    """``workcell ... | head -n 1`` whose reader is gone before the command writes: exit
    141 (128 + SIGPIPE) as a command SIGPIPE ended, and nothing on standard error."""
    from workcell.study.template import TEMPLATE

    (tmp_path / "study.toml").write_text(TEMPLATE)
    read_end, write_end = os.pipe()
    os.close(read_end)
    try:
        done = subprocess.run(
            [sys.executable, "-m", "workcell", *argv],
            check=False,
            stdout=write_end,
            stderr=subprocess.PIPE,
            text=True,
            cwd=tmp_path,
            timeout=120,
        )
    finally:
        os.close(write_end)
    assert (done.returncode, done.stderr) == (128 + signal.SIGPIPE, "")
