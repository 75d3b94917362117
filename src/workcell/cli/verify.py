"""``workcell verify``: check a store or a CSV export and name every problem found."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING

from workcell.errors import ConfigError

if TYPE_CHECKING:
    from workcell.cli.main import Subparsers

EXIT_PROBLEMS = 1


def register(subparsers: Subparsers) -> None:
    parser = subparsers.add_parser(
        "verify",
        help="check a store or a CSV export for damage and tampering",
        description=(
            "Check a store's schema, links, monotonic timestamps, finite values, frame "
            "counts and content checksums, or a CSV export's files against its manifest. "
            "Prints 'ok: ...' or one line per problem (store, table, row) and exits 1."
        ),
    )
    what = parser.add_mutually_exclusive_group(required=True)
    what.add_argument("--store", type=Path, metavar="PATH", help="a store file")
    what.add_argument("--csv", type=Path, metavar="DIR", help="a directory written by export")
    parser.add_argument(
        "--recover",
        action="store_true",
        help="first close trials a dead recorder left open (as crash_recovered); "
        "needs the store not to be open for writing elsewhere",
    )
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from workcell.record.verify import verify_export, verify_store  # noqa: PLC0415

    if args.csv is not None:
        if args.recover:
            raise ConfigError(["--recover applies to --store only"])
        findings = verify_export(args.csv)
        summary = _export_summary(args.csv) if not findings else ""
    else:
        if args.recover:
            _recover(args.store)
        findings = verify_store(args.store)
        summary = _store_summary(args.store) if not findings else ""
    for finding in findings:
        print(finding)
    if findings:
        return EXIT_PROBLEMS
    print(f"ok: {summary} verified")
    return 0


def _recover(path: Path) -> None:
    from workcell.record.store import Store  # noqa: PLC0415

    with Store.open(path, writer=True) as store:
        for trial_id in store.recovered:
            print(f"recovered: trial {trial_id} closed as interrupted (crash_recovered)")


def _store_summary(path: Path) -> str:
    from workcell.record.store import Store  # noqa: PLC0415

    with Store.open(path, writer=False) as store:
        counts = store.counts()
    return f"{counts.sessions} sessions, {counts.trials} trials, {counts.frames} frames"


def _export_summary(path: Path) -> str:
    import json  # noqa: PLC0415

    files = json.loads((path / "manifest.json").read_text())["files"]
    rows = {name: files[name]["rows"] for name in ("sessions.csv", "trials.csv", "frames.csv")}
    return (
        f"{rows['sessions.csv']} sessions, {rows['trials.csv']} trials, {rows['frames.csv']} frames"
    )
