"""Regenerate the README's settings table from the session settings' declarations.

Run ``python -m workcell.session.readme`` to rewrite the table in ``README.md``,
``--check`` to fail when the committed table differs from the declarations (the drift
test does this).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

from workcell.session.config import SessionConfig
from workcell.settings.table import markdown_table, replace_table

README = Path(__file__).resolve().parents[3] / "README.md"
REGENERATE = "python -m workcell.session.readme"


def updated(readme: str) -> str:
    """``readme`` with its settings table generated from :class:`SessionConfig`."""
    return replace_table(readme, markdown_table(SessionConfig))


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog=REGENERATE)
    parser.add_argument("--check", action="store_true", help="fail if the table is stale")
    parser.add_argument("--readme", type=Path, default=README, help="default: %(default)s")
    args = parser.parse_args(argv)
    path: Path = args.readme
    current = path.read_text(encoding="utf-8")
    text = updated(current)
    if args.check:
        if current != text:
            print(f"the settings table in {path} is stale: run `{REGENERATE}`", file=sys.stderr)
            return 1
        return 0
    path.write_text(text, encoding="utf-8")
    print(f"wrote the settings table of {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
