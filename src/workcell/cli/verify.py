"""``workcell verify``: check a store or a CSV export and name every problem found."""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import TYPE_CHECKING, Any

from workcell.errors import ConfigError

if TYPE_CHECKING:
    from workcell.cli.command import Subparsers
    from workcell.record.chain_check import ChainStats

EXIT_PROBLEMS = 1


def register(subparsers: Subparsers) -> None:
    parser = subparsers.add_parser(
        "verify",
        help="check a store or a CSV export for damage and tampering",
        description=(
            "Check a store's schema, links, monotonic timestamps, finite values, frame "
            "counts, content checksums and hash chains (with --key: their signatures; with "
            "--manifest: the chain heads an export recorded), or a CSV export's files "
            "against its manifest. Prints 'ok: ...' or one line per problem (store, table, "
            "row) and exits 1."
        ),
    )
    what = parser.add_mutually_exclusive_group(required=True)
    what.add_argument("--store", type=Path, metavar="PATH", help="a store file")
    what.add_argument("--csv", type=Path, metavar="DIR", help="a directory written by export")
    parser.add_argument(
        "--key",
        type=Path,
        metavar="FILE",
        help="the key the store's chains were signed with (collect/serve --key): every link "
        "and the chain tip must carry its signature, so a chain recomputed, cut short or "
        "grafted without the key is found",
    )
    parser.add_argument(
        "--manifest",
        type=Path,
        metavar="FILE",
        help="an export's manifest.json, kept apart from the store: every session it lists "
        "must still be in the store with the chain head it had when it was exported",
    )
    parser.add_argument(
        "--recover",
        action="store_true",
        help="first open the store for writing: migrate an older schema version and close "
        "trials a dead recorder left open (as crash_recovered); needs the store not to be "
        "open for writing elsewhere",
    )
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from workcell.record.chain import ChainKey  # noqa: PLC0415
    from workcell.record.verify import verify_export, verify_store_report  # noqa: PLC0415

    if args.csv is not None:
        for flag in ("recover", "key", "manifest"):
            if getattr(args, flag):
                raise ConfigError([f"--{flag} applies to --store only"])
        findings = verify_export(args.csv)
        summary = _export_summary(args.csv) if not findings else ""
    else:
        key = None if args.key is None else ChainKey.from_file(args.key)
        manifest = None if args.manifest is None else _manifest(args.manifest)
        if args.recover:
            _recover(args.store, key)
        findings, stats = verify_store_report(args.store, key=key, manifest=manifest)
        summary = _store_summary(args.store, stats, key) if not findings else ""
        if manifest is not None:
            summary += f"; matches the chain heads of {args.manifest}"
    for finding in findings:
        print(finding)
    if findings:
        return EXIT_PROBLEMS
    print(f"ok: {summary} verified")
    return 0


def _manifest(path: Path) -> dict[str, Any]:
    try:
        manifest = json.loads(path.read_text())
    except (OSError, ValueError) as error:
        raise ConfigError([f"--manifest {path}: cannot be read as JSON ({error})"]) from None
    if not isinstance(manifest, dict):
        raise ConfigError([f"--manifest {path}: is not an export manifest (a JSON object)"])
    return manifest


def _recover(path: Path, key: Any) -> None:
    import contextlib  # noqa: PLC0415
    import sqlite3  # noqa: PLC0415
    from urllib.parse import quote  # noqa: PLC0415

    from workcell.record.migrate import CHAINED_BY  # noqa: PLC0415
    from workcell.record.schema import SCHEMA_VERSION  # noqa: PLC0415
    from workcell.record.store import Store  # noqa: PLC0415

    version = SCHEMA_VERSION
    with (
        contextlib.suppress(sqlite3.Error),
        contextlib.closing(
            sqlite3.connect(f"file:{quote(str(path.resolve()))}?mode=ro", uri=True)
        ) as conn,
    ):
        version = conn.execute("PRAGMA user_version").fetchone()[0]
    with Store.open(path, writer=True, key=key) as store:
        for trial_id in store.recovered:
            print(f"recovered: trial {trial_id} closed as interrupted (crash_recovered)")
    if 0 < version < SCHEMA_VERSION:
        chained = (
            "; the hash chains of its sessions were computed from their rows as they are now"
            if version <= CHAINED_BY
            else "; every row, checksum and chain link kept"
        )
        print(f"migrated: {path} from schema version {version} to {SCHEMA_VERSION}{chained}")


def _store_summary(path: Path, stats: ChainStats, key: Any) -> str:
    from workcell.record.store import Store  # noqa: PLC0415

    with Store.open(path, writer=False) as store:
        counts = store.counts()
    text = f"{counts.sessions} sessions, {counts.trials} trials, {counts.frames} frames"
    text += f"; hash chains of {stats.sessions} sessions ({stats.links} links"
    if key is not None:
        text += f", every one signed with key {key.key_id})"
    elif stats.signed:
        ids = ", ".join(sorted(stats.key_ids))
        text += f", {stats.signed} signed with key {ids}: give --key to check the signatures)"
    else:
        text += ", unsigned)"
    if stats.migrated_sessions:
        text += (
            f"; {stats.migrated_sessions} sessions were chained when the store was migrated "
            "from schema version 1: their chains vouch only for what they held then"
        )
    return text


def _export_summary(path: Path) -> str:
    files = json.loads((path / "manifest.json").read_text())["files"]
    rows = {name: files[name]["rows"] for name in ("sessions.csv", "trials.csv", "frames.csv")}
    return (
        f"{rows['sessions.csv']} sessions, {rows['trials.csv']} trials, {rows['frames.csv']} frames"
    )
