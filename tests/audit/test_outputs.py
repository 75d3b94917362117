"""The three output files: report.html opens and holds every figure, summary.json and
trials.csv say everything, and a CSV export audits exactly like its store."""

from __future__ import annotations

import base64
import csv
import json
from dataclasses import dataclass
from html.parser import HTMLParser
from pathlib import Path
from typing import Any

import pytest

from tests.audit.conftest import Scenario
from workcell.audit.csv_source import CsvSource
from workcell.audit.flags import FLAG_NAMES
from workcell.audit.run import run_audit
from workcell.audit.source import AuditSource
from workcell.audit.store_source import StoreSource
from workcell.audit.trials_csv import AUDIT_COLUMNS
from workcell.audit.write import write_outputs
from workcell.record.columns import TRIAL_COLUMNS
from workcell.record.export_csv import export_csv

PNG = b"\x89PNG\r\n\x1a\n"
FIGURES = ("flow", "outcomes", "distributions", "trajectories", "sampling")


@dataclass(frozen=True)
class Outputs:
    store: dict[str, Path]
    csv: dict[str, Path]


def _write(source: AuditSource, out: Path) -> dict[str, Path]:
    try:
        return write_outputs(run_audit(source), out)
    finally:
        source.close()


@pytest.fixture(scope="module")
def outputs(scenario: Scenario, tmp_path_factory: pytest.TempPathFactory) -> Outputs:
    root = tmp_path_factory.mktemp("outputs")
    export_csv(scenario.path, root / "export")
    return Outputs(
        store=_write(StoreSource(scenario.path), root / "from_store"),
        csv=_write(CsvSource(root / "export"), root / "from_csv"),
    )


class _Report(HTMLParser):
    def __init__(self) -> None:
        super().__init__()
        self.images: list[dict[str, str | None]] = []
        self.figures: list[str | None] = []
        self.svgs = 0
        self.links: list[str] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        found = dict(attrs)
        if tag == "img":
            self.images.append(found)
        elif tag == "figure":
            self.figures.append(found.get("id"))
        elif tag == "svg":
            self.svgs += 1
        for name in ("href", "src"):
            value = found.get(name)
            if value is not None and not value.startswith("data:"):
                self.links.append(value)


def test_the_report_opens_and_holds_every_figure(outputs: Outputs) -> None:
    text = outputs.store["report.html"].read_text()
    report = _Report()
    report.feed(text)
    report.close()
    assert report.figures == list(FIGURES)
    assert len(report.images) == len(FIGURES) and report.svgs == 0
    for image in report.images:
        src = image["src"] or ""
        assert src.startswith("data:image/png;base64,")
        data = base64.b64decode(src.removeprefix("data:image/png;base64,"), validate=True)
        assert data.startswith(PNG) and len(data) > 10_000
    assert report.links == []
    assert "http://" not in text and "https://" not in text


def _summary(path: Path) -> dict[str, Any]:
    summary: dict[str, Any] = json.loads(path.read_text())
    return summary


def test_summary_holds_counts_rate_statistics_parameters_and_findings(
    outputs: Outputs, scenario: Scenario
) -> None:
    summary = _summary(outputs.store["summary.json"])
    assert summary["counts"]["valid"] == 5
    assert summary["success_rate"]["successes"] == 3
    assert set(summary["metrics"]) == {
        "completion_time_s",
        "path_length_m",
        "smoothness",
        "active_ratio",
    }
    assert summary["metrics"]["path_length_m"]["n"] == 3
    assert {"hz_wall", "hz_sim", "max_gap_s", "largest_gap_s"} <= set(summary["sampling"])
    detectors = summary["parameters"]["detectors"]
    assert detectors["arm_oscillation"]["version"] == "2"
    assert detectors["arm_oscillation"]["amplitude_rad"] == 0.02
    assert detectors["sampling"]["gap_periods"] == 5.0
    assert summary["parameters"]["arm_oscillation_criteria_by_rate_hz"]["20"]["window_frames"] == 13
    flagged = {
        (f["trial_id"], f["subject"]) for f in summary["findings"] if f["kind"] == "quality_flag"
    }
    assert (scenario.ids["oscillating"], "arm_oscillation") in flagged
    assert (scenario.ids["gap"], "sampling_gap") in flagged


def test_trials_csv_has_the_contract_columns_then_flags_and_dispositions(
    outputs: Outputs, scenario: Scenario
) -> None:
    with outputs.store["trials.csv"].open(newline="") as file:
        rows = list(csv.DictReader(file))
    assert tuple(rows[0]) == TRIAL_COLUMNS + AUDIT_COLUMNS
    assert {f"flag_{name}" for name in FLAG_NAMES} <= set(AUDIT_COLUMNS)
    by_id = {r["trial_id"]: r for r in rows}
    oscillating = by_id[scenario.ids["oscillating"]]
    assert oscillating["outcome"] == "success"
    assert (oscillating["included"], oscillating["disposition"]) == ("0", "excluded_low_quality")
    assert oscillating["flag_arm_oscillation"] == "1"
    assert oscillating["quality_flags"] == "arm_oscillation"
    included = by_id[scenario.ids["reviewer_included"]]
    assert (included["included"], included["review_overridden"], included["review_by"]) == (
        "1",
        "1",
        "ben",
    )
    assert included["automatic_included"] == "0"
    assert by_id[scenario.ids["crashed"]]["review_refused"].startswith("include by ben")


def test_a_csv_export_audits_exactly_like_its_store(outputs: Outputs) -> None:
    from_store = _summary(outputs.store["summary.json"])
    from_csv = _summary(outputs.csv["summary.json"])
    assert from_store.pop("source") != from_csv.pop("source")
    assert from_store == from_csv
    assert outputs.store["trials.csv"].read_bytes() == outputs.csv["trials.csv"].read_bytes()
