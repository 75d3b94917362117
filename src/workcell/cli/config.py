"""``workcell config``: print the default or the resolved session settings as TOML."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from workcell.cli.command import Subparsers


def register(subparsers: Subparsers) -> None:
    parser = subparsers.add_parser(
        "config",
        help="print session settings as commented TOML",
        description=(
            "Print every session setting with its documentation as TOML. With --defaults, "
            "the defaults (a complete file to start from); otherwise the settings resolved "
            "from --config FILE and --set KEY=VALUE, after validation."
        ),
    )
    parser.add_argument("--defaults", action="store_true", help="print the default settings")
    parser.add_argument("--config", type=Path, metavar="FILE", help="session settings (TOML)")
    parser.add_argument(
        "--set", action="append", default=[], metavar="KEY=VALUE", help="override a setting"
    )
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from workcell.session.config import SessionConfig  # noqa: PLC0415
    from workcell.session.load import resolve_session_config  # noqa: PLC0415
    from workcell.settings.template import to_toml  # noqa: PLC0415

    defaults = args.defaults
    config = SessionConfig() if defaults else resolve_session_config(args.config, args.set)
    print("# Workcell session settings (workcell collect --config FILE)\n")
    print(to_toml(config), end="")
    return 0
