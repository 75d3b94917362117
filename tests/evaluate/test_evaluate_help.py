"""The README's row for ``workcell evaluate`` names every option its ``--help`` has."""

from __future__ import annotations

import re

from tests.cli.test_readme_rows import _row, _subparser


def test_the_readme_row_names_every_option() -> None:
    usage = _row("evaluate").split("` |")[0]
    options = {
        option
        for action in _subparser("evaluate")._actions
        for option in action.option_strings
        if option.startswith("--") and option != "--help"
    }
    assert len(options) == 9
    missing = sorted(o for o in options if not re.search(re.escape(o) + r"(?![\w-])", usage))
    assert missing == []
