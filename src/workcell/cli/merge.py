"""``workcell merge``: combine store shards into one store and verify it."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from workcell.cli.command import Subparsers


def register(subparsers: Subparsers) -> None:
    parser = subparsers.add_parser(
        "merge",
        help="combine store shards into one store and verify it",
        description=(
            "Copy every session, trial, event, frame and annotation of the SHARD stores into "
            "--out (created if absent), recovering shards a dead worker left open, then "
            "verify the result. Shards of another schema version or joint order are refused."
        ),
    )
    parser.add_argument("--out", type=Path, required=True, metavar="PATH", help="merged store")
    parser.add_argument(
        "--key",
        type=Path,
        metavar="FILE",
        help="the key the shards were recorded with (collect/serve --key): recovering a "
        "crashed shard signs what it closes with it",
    )
    parser.add_argument("shards", type=Path, nargs="+", metavar="SHARD", help="stores to merge")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from workcell.record.chain import ChainKey  # noqa: PLC0415
    from workcell.record.merge import merge_stores  # noqa: PLC0415

    key = None if args.key is None else ChainKey.from_file(args.key)
    report = merge_stores(
        args.shards, args.out, progress=lambda m: print(m, file=sys.stderr), key=key
    )
    print(
        f"merged {report.shards} shards into {args.out}: {report.sessions} sessions, "
        f"{report.trials} trials, {report.frames} frames, verified"
        + (
            f" ({report.recovered_trials} crashed trials recovered)"
            if report.recovered_trials
            else ""
        )
    )
    return 0
