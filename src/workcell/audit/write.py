"""Writing an audit's three files into its output folder."""

from __future__ import annotations

import json
from pathlib import Path

from workcell.audit.errors import AuditError
from workcell.audit.figures import render_figures
from workcell.audit.report import build_report
from workcell.audit.run import AuditResult
from workcell.audit.summary import build_summary
from workcell.audit.trials_csv import write_trials_csv

OUTPUT_FILES: tuple[str, ...] = ("report.html", "summary.json", "trials.csv")


def check_output(out: Path, force: bool) -> None:
    """Refuse an output that is a file, or a folder with anything in it (unless
    ``force``, which overwrites OUTPUT_FILES and leaves other files alone)."""
    if out.exists() and not out.is_dir():
        raise AuditError(f"output {out} is a file; give a new or empty folder")
    if out.is_dir() and any(out.iterdir()) and not force:
        raise AuditError(
            f"output folder {out} is not empty; give a new or empty folder, or --force "
            "to overwrite the report in it"
        )


def write_outputs(result: AuditResult, out: Path) -> dict[str, Path]:
    """Write report.html, summary.json and trials.csv; returns their paths by name."""
    try:
        out.mkdir(parents=True, exist_ok=True)
        paths = {name: out / name for name in OUTPUT_FILES}
        summary = build_summary(result)
        paths["summary.json"].write_text(json.dumps(summary, indent=2, allow_nan=False) + "\n")
        write_trials_csv(paths["trials.csv"], result.trials)
        paths["report.html"].write_text(build_report(result, render_figures(result)))
    except OSError as error:
        raise AuditError(f"cannot write the audit into {out}: {error.strerror}") from None
    return paths
