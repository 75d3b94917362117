"""``workcell annotate``: record a reviewer's decision on a trial (who, when, why).

The decision is a row of its own; the trial row is never changed. ``workcell audit``
applies the latest include/exclude decision of each trial over its automatic rules.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from workcell.errors import ConfigError

if TYPE_CHECKING:
    from workcell.cli.command import Subparsers
    from workcell.record.entries import TrialRecord

MIN_PREFIX = 6


def register(subparsers: Subparsers) -> None:
    parser = subparsers.add_parser(
        "annotate",
        help="record a reviewer's include/exclude decision (or a note) on a trial",
        description=(
            "Record who decided what about a trial and why, as its own row in the store. "
            "'workcell audit' applies each trial's latest --include/--exclude over its "
            "automatic rules and shows it as the reviewer's decision; stored trials are "
            "never changed."
        ),
    )
    parser.add_argument("--store", required=True, type=Path, metavar="PATH", help="a store")
    parser.add_argument(
        "--trial",
        required=True,
        metavar="ID",
        help=f"trial id (or a unique prefix of {MIN_PREFIX}+)",
    )
    kind = parser.add_mutually_exclusive_group(required=True)
    kind.add_argument("--exclude", dest="kind", action="store_const", const="exclude")
    kind.add_argument("--include", dest="kind", action="store_const", const="include")
    kind.add_argument(
        "--note", dest="kind", action="store_const", const="note", help="comment only"
    )
    parser.add_argument("--reason", required=True, metavar="TEXT", help="why (required)")
    parser.add_argument("--by", required=True, metavar="NAME", help="who decides (required)")
    parser.set_defaults(func=run)


def _find(trials: list[TrialRecord], given: str) -> TrialRecord:
    exact = [t for t in trials if t.trial_id == given]
    if exact:
        return exact[0]
    matches = [t for t in trials if len(given) >= MIN_PREFIX and t.trial_id.startswith(given)]
    if len(matches) == 1:
        return matches[0]
    if matches:
        raise ConfigError([f"--trial {given}: {len(matches)} trials start with it; give more"])
    raise ConfigError([f"--trial {given}: no such trial in the store (ids: 'workcell audit')"])


def run(args: argparse.Namespace) -> int:
    from workcell.record.columns import COMPLETE_OUTCOMES  # noqa: PLC0415
    from workcell.record.store import Store  # noqa: PLC0415

    problems = [
        f"--{name} must not be empty"
        for name in ("reason", "by")
        if not getattr(args, name).strip()
    ]
    if problems:
        raise ConfigError(problems)
    if not args.store.is_file():
        raise ConfigError([f"--store {args.store}: no such store"])
    with Store.open(args.store, writer=True) as store:
        for trial_id in store.recovered:
            print(
                f"recovered: trial {trial_id} closed as interrupted (crash_recovered)",
                file=sys.stderr,
            )
        trial = _find(store.trials(), args.trial)
        if args.kind == "include" and trial.outcome not in COMPLETE_OUTCOMES:
            raise ConfigError(
                [
                    f"--include: trial {trial.trial_id} is {trial.outcome or 'still open'}; an "
                    "incomplete trial has no outcome to count (use --note to comment)"
                ]
            )
        annotation_id = store.annotate(
            trial.trial_id, args.kind, args.reason.strip(), args.by.strip()
        )
    print(
        f"annotated trial {trial.trial_id}: {args.kind} by {args.by.strip()} "
        f"({args.reason.strip()}); annotation {annotation_id}"
    )
    return 0
