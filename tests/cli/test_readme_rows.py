"""The README's table of commands and each command's ``--help`` say the same things."""

from __future__ import annotations

import argparse
import re
from pathlib import Path

import pytest

from workcell.cli.main import build_parser

README = Path(__file__).resolve().parents[2] / "README.md"


def _subparser(name: str) -> argparse.ArgumentParser:
    parser = build_parser()
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            found: argparse.ArgumentParser = action.choices[name]
            return found
    raise AssertionError("no subcommands")


def _commands() -> list[str]:
    parser = build_parser()
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return sorted(action.choices)
    raise AssertionError("no subcommands")


def _row(name: str) -> str:
    rows = [
        line for line in README.read_text().splitlines() if line.startswith(f"| `workcell {name} ")
    ]
    assert len(rows) == 1, f"README has {len(rows)} rows for workcell {name}"
    return rows[0]


@pytest.mark.parametrize("name", _commands())
def test_the_readme_row_names_every_option(name: str) -> None:
    usage = _row(name).split("` |")[0]
    options = {
        option
        for action in _subparser(name)._actions
        for option in action.option_strings
        if option.startswith("--") and option != "--help"
    }
    missing = sorted(o for o in options if not re.search(re.escape(o) + r"(?![\w-])", usage))
    assert missing == [], f"README's workcell {name} row lacks {missing}"


def test_collect_and_the_readme_give_the_same_camera_speed_up() -> None:
    quality = next(
        a for a in _subparser("collect")._actions if "--camera-quality" in a.option_strings
    )
    assert "six times as fast per frame" in str(quality.help)
    assert "six times as fast per frame" in README.read_text()


def test_audit_help_names_its_flags_and_the_task_stages() -> None:
    description = _subparser("audit").description or ""
    for part in ("oscillation", "sampling gaps", "clocks", "non-finite", "slow", "task stage"):
        assert part in description, part
