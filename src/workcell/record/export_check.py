"""Verifying a CSV export against its manifest: files, sha256, headers and row counts."""

from __future__ import annotations

import csv
import json
import os
from pathlib import Path
from typing import Any

from workcell.record.csv_format import FILES, MANIFEST, file_sha256, known_header
from workcell.record.findings import IntegrityFinding


def verify_export(out_dir: str | os.PathLike[str]) -> list[IntegrityFinding]:
    """Every problem found in the export at ``out_dir`` (empty when it verifies): a file
    missing, unlisted or changed since export (its sha256 differs from the manifest's),
    a header that is not the contract's columns, a row count that differs."""
    out = Path(out_dir)
    where = str(out)
    try:
        manifest = json.loads((out / MANIFEST).read_text())
        files: dict[str, Any] = manifest["files"]
    except (OSError, ValueError, KeyError, TypeError) as error:
        return [
            IntegrityFinding(where, MANIFEST, "", f"cannot be read ({error}); re-export the store")
        ]
    findings = []

    def add(name: str, problem: str) -> None:
        findings.append(IntegrityFinding(where, name, "", problem))

    for name in FILES:
        if name not in files:
            add(name, "not listed in manifest.json")
    present = {p.name for p in out.iterdir() if p.is_file()} - {MANIFEST}
    for name in sorted(present - set(files)):
        add(name, "not listed in manifest.json: it was not part of the export")
    for name, entry in sorted(files.items()):
        path = out / name
        if not path.is_file():
            add(name, "listed in manifest.json but missing")
            continue
        digest = file_sha256(path)
        if digest != entry.get("sha256"):
            add(
                name,
                f"sha256 {digest[:12]}… differs from the manifest's "
                f"{str(entry.get('sha256'))[:12]}…: the file was changed after export",
            )
        layout = FILES.get(name)
        if layout is None:
            continue
        header, rows = _header_and_rows(path)
        if not known_header(layout, header):
            add(
                name,
                "header is not the contract's columns "
                f"(first difference: {_first_difference(header, layout.names)})",
            )
        elif rows != entry.get("rows"):
            add(name, f"{rows} rows, the manifest says {entry.get('rows')}")
    return findings


def _header_and_rows(path: Path) -> tuple[list[str], int]:
    try:
        with path.open(newline="", errors="replace") as file:
            reader = csv.reader(file)
            header = next(reader, [])
            return header, sum(1 for _ in reader)
    except csv.Error:
        return [], -1


def _first_difference(found: list[str], expected: tuple[str, ...]) -> str:
    for i, (a, b) in enumerate(zip(found, expected, strict=False)):
        if a != b:
            return f"column {i + 1} is {a!r}, expected {b!r}"
    return f"{len(found)} columns, expected {len(expected)}"
