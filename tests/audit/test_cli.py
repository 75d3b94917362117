"""``workcell audit`` and ``workcell annotate``, run through their own parsers.

Errors are WorkcellErrors with a one-line message: ``workcell.cli.main`` prints them as
one line and exits 2.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import cast

import pytest

from tests.audit import synthetic
from workcell.cli import annotate, audit
from workcell.cli.main import EXIT_USAGE, Subparsers, _Parser
from workcell.errors import ConfigError, WorkcellError
from workcell.record import Store
from workcell.record.export_csv import export_csv


def _run(argv: Sequence[str]) -> int:
    parser = _Parser(prog="workcell")
    subparsers = cast(Subparsers, parser.add_subparsers(dest="command", required=True))
    audit.register(subparsers)
    annotate.register(subparsers)
    args = parser.parse_args(argv)
    status: int = args.func(args)
    return status


def _one_line_error(argv: Sequence[str]) -> str:
    with pytest.raises(WorkcellError) as caught:
        _run(argv)
    message = str(caught.value)
    assert message and "\n" not in message
    return message


@pytest.fixture
def store(tmp_path: Path) -> tuple[Path, list[str]]:
    path = tmp_path / "s.sqlite"
    return path, synthetic.fill(path, ["success", "timeout", "success", "interrupted"])


def test_one_trial_is_counted_in_the_singular(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "one.sqlite"
    synthetic.fill(path, ["success"])
    assert _run(["audit", "--store", str(path), "--out", str(tmp_path / "report")]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    assert first.startswith("audited 1 trial (40 frames): 1 valid (1 success, 0 timeouts)")
    assert first.endswith("; 0 findings")


def test_audit_writes_the_report_and_refuses_a_non_empty_folder(
    store: tuple[Path, list[str]], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path, _ = store
    out = tmp_path / "report"
    assert _run(["audit", "--store", str(path), "--out", str(out)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].startswith("audited 4 trials (")
    assert "3 valid (2 successes, 1 timeout)" in lines[0]
    assert lines[1] == "  task stages (how far each trial got): 2 delivered, 2 none"
    assert lines[2].startswith("  operator ")  # one line per operator, one operator too
    assert ": 4 trials, 3 valid (2 successes, 1 timeout), success rate 66.67 %" in lines[2]
    assert lines[2].endswith("got to: 2 delivered, 2 none")
    assert lines[3].startswith("wrote ")
    assert sorted(p.name for p in out.iterdir()) == ["report.html", "summary.json", "trials.csv"]
    message = _one_line_error(["audit", "--store", str(path), "--out", str(out)])
    assert message.startswith(f"output folder {out} is not empty;") and "--force" in message
    (out / "notes.txt").write_text("mine")
    assert _run(["audit", "--store", str(path), "--out", str(out), "--force"]) == 0
    assert (out / "notes.txt").read_text() == "mine"


def test_bad_input_is_one_line(tmp_path: Path, store: tuple[Path, list[str]]) -> None:
    path, ids = store
    out = str(tmp_path / "out")
    assert "no store at" in _one_line_error(["audit", "--store", str(tmp_path / "x"), "--out", out])
    assert "no manifest.json" in _one_line_error(["audit", "--csv", str(tmp_path), "--out", out])
    assert "not allowed with argument" in _one_line_error(
        ["audit", "--store", str(path), "--csv", str(tmp_path), "--out", out]
    )
    with pytest.raises(ConfigError, match="trajectories = 0"):
        _run(["audit", "--store", str(path), "--out", out, "--trajectories", "0"])
    assert "'0': must be a whole number of processes >= 1" in _one_line_error(
        ["audit", "--store", str(path), "--out", out, "--workers", "0"]
    )
    base = ["annotate", "--store", str(path), "--reason", "r", "--by", "me"]
    assert "no such trial" in _one_line_error([*base, "--trial", "nope", "--exclude"])
    assert "is interrupted" in _one_line_error([*base, "--trial", ids[3], "--include"])
    assert "--include" in _one_line_error([*base, "--trial", ids[0], "--include", "--exclude"])
    assert "--reason must not be empty" in _one_line_error(
        [
            "annotate",
            "--store",
            str(path),
            "--trial",
            ids[0],
            "--note",
            "--reason",
            " ",
            "--by",
            "x",
        ]
    )
    assert not (tmp_path / "out").exists()
    assert EXIT_USAGE == 2  # what main() returns for every WorkcellError


def test_workers_and_frame_rows_change_nothing_in_the_report(
    store: tuple[Path, list[str]], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path, _ = store
    assert _run(["audit", "--store", str(path), "--out", str(tmp_path / "a")]) == 0
    argv = ["audit", "--store", str(path), "--out", str(tmp_path / "b"), "--workers", "2"]
    assert _run([*argv, "--from-rows"]) == 0
    lines = [line for line in capsys.readouterr().out.splitlines() if not line.startswith("wrote")]
    first, second = lines[: len(lines) // 2], lines[len(lines) // 2 :]
    assert first[0].startswith("audited") and first == second
    for name in ("summary.json", "trials.csv"):
        assert (tmp_path / "a" / name).read_text() == (tmp_path / "b" / name).read_text()


def test_annotate_then_audit_shows_the_reviewer(
    store: tuple[Path, list[str]], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path, ids = store
    argv = ["annotate", "--store", str(path), "--trial", ids[2][:8], "--exclude"]
    assert _run([*argv, "--reason", "operator distracted", "--by", "ana"]) == 0
    out = capsys.readouterr().out
    assert out.startswith(f"annotated trial {ids[2]}: exclude by ana (operator distracted)")
    with Store.open(path, writer=False) as reader:
        (note,) = reader.annotations()
        assert (note.trial_id, note.kind, note.by) == (ids[2], "exclude", "ana")
        assert reader.trials()[2].included  # the trial row is untouched
    assert _run(["audit", "--store", str(path), "--out", str(tmp_path / "r")]) == 0
    assert "1 excluded by reviewer" in capsys.readouterr().out
    report = (tmp_path / "r" / "report.html").read_text()
    assert "excluded_by_reviewer" in report and "reviewer ana: operator distracted" in report


def test_help_names_every_option(capsys: pytest.CaptureFixture[str]) -> None:
    for command in ("audit", "annotate"):
        with pytest.raises(SystemExit):
            _run([command, "--help"])
        text = capsys.readouterr().out
        assert "--store" in text


def test_audit_of_a_csv_export(
    store: tuple[Path, list[str]], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path, _ = store
    export_csv(path, tmp_path / "csv")
    out = tmp_path / "report"
    assert _run(["audit", "--csv", str(tmp_path / "csv"), "--out", str(out)]) == 0
    assert capsys.readouterr().out.startswith("audited 4 trials (160 frames): 3 valid")
    assert (out / "report.html").stat().st_size > 0
