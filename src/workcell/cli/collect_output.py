"""What ``workcell collect`` prints: the trial table or JSON lines, progress, the summary.

Standard output may be a pipe whose reader goes away (``workcell collect --json | head -n
1``). That is not an error of the run: :class:`TrialPrinter` notices it, either when a
write fails or, earlier, when the pipe reports that its reader has closed, and from then
on prints nothing more; the caller ends the run as it does on SIGINT (the running trial
``interrupted``, the session closed) and exits with status 141 (128 + SIGPIPE); so do
the workers of ``collect --workers``, whose shards are merged as after SIGINT (see
:mod:`workcell.cli.closed_output`).
"""

from __future__ import annotations

import contextlib
import json
import sys
from typing import TYPE_CHECKING, Any

from workcell.cli.closed_output import discard_stdout, reader_gone
from workcell.record.columns import INTERRUPTION_REASONS

if TYPE_CHECKING:
    from pathlib import Path

    from workcell.task.runner import SessionRunner, TrialResult

COLUMNS = ("index", "mode", "round", "level", "outcome", "boxes", "score", "elapsed")
OUTCOME_WIDTH = max(len(f"interrupted:{reason}") for reason in INTERRUPTION_REASONS)
"""Wide enough for every outcome label, ``interrupted:application_quit`` the longest."""
WIDTHS = (5, 10, 5, 5, OUTCOME_WIDTH, 5, 6, 8)
CHECK_EVERY = 16
"""Loop iterations between two looks at whether standard output's reader has gone."""


def trial_json(result: TrialResult) -> dict[str, Any]:
    """The JSON line of one trial (keys are public API)."""
    spec = result.spec
    return {
        "trial_index": spec.trial_index,
        "mode": spec.mode,
        "round": spec.round,
        "level": spec.level,
        "required_boxes": spec.required_boxes,
        "time_limit_s": spec.time_limit_s,
        "outcome": result.outcome,
        "interruption_reason": result.interruption_reason,
        "boxes_delivered": result.boxes_done,
        "score": result.score,
        "elapsed_s": round(result.elapsed_s, 6),
    }


def table_row(result: TrialResult) -> str:
    """One trial as a row of the table, aligned under :func:`table_header`."""
    spec = result.spec
    outcome: str = result.outcome
    if result.interruption_reason:
        outcome = f"{outcome}:{result.interruption_reason}"
    values = (
        spec.trial_index,
        spec.mode,
        "-" if spec.round is None else spec.round,
        "-" if spec.level is None else spec.level,
        outcome,
        f"{result.boxes_done}/{spec.required_boxes}",
        result.score,
        f"{result.elapsed_s:.2f}",
    )
    return "  ".join(str(v).rjust(w) for v, w in zip(values, WIDTHS, strict=True))


def table_header() -> str:
    return "  ".join(c.rjust(w) for c, w in zip(COLUMNS, WIDTHS, strict=True))


class TrialPrinter:
    """Prints a run's rows (``as_json``: JSON lines), the progress line on a terminal, and
    notices when standard output's reader has gone (:attr:`output_closed`)."""

    def __init__(self, as_json: bool) -> None:
        self.as_json = as_json
        self.live = sys.stderr.isatty()
        self.output_closed = False
        self._last_progress = -1
        self._checks = 0

    def check_output(self) -> bool:
        """Whether standard output can no longer be written (looked at every few calls)."""
        self._checks += 1
        if not self.output_closed and self._checks % CHECK_EVERY == 0 and reader_gone(sys.stdout):
            self._output_gone()
        return self.output_closed

    def header(self) -> None:
        if not self.as_json:
            self.out(table_header())

    def progress(self, runner: SessionRunner) -> None:
        if not self.live:
            return
        hud = runner.hud()
        second = int(runner.sim.time)
        if second != self._last_progress:
            self._last_progress = second
            where = f"round {hud.round} level {hud.level}, " if hud.round else ""
            self._err(
                f"\r  trial {hud.trial_index + 1}: {where}{hud.phase.value}, "
                f"{hud.remaining_s:5.1f} s left, boxes {hud.boxes_delivered}/"
                f"{hud.required_boxes}   ",
                end="",
            )

    def row(self, result: TrialResult) -> None:
        if self.live:
            self._err("\r" + " " * 70 + "\r", end="")
        self.out(json.dumps(trial_json(result)) if self.as_json else table_row(result))

    def stored(self, path: Path, session_id: str, frames: int) -> None:
        self.note(f"recorded session {session_id} ({frames} frames) in {path}")

    def summary(self, runner: SessionRunner) -> None:
        results = runner.results
        successes = sum(r.outcome == "success" for r in results)
        total = sum(r.score for r in results)
        line = f"{len(results)} trials, {successes} succeeded, total score {total}"
        if runner.config.task.mode == "challenge":
            last = results[-1].spec if results else None
            if runner.campaign_complete:
                line = f"campaign complete: {line}"
            elif last is not None:
                why = "stopped by --trials" if runner.capped else "interrupted"
                line = (
                    f"campaign incomplete ({why}) at round {last.round} level {last.level}: {line}"
                )
        self.note(line)

    def note(self, line: str) -> None:
        """A line about the run: on standard output under the table, on standard error
        beside JSON lines (so that standard output stays one JSON object per line)."""
        if self.as_json:
            self._err(line)
        else:
            self.out(line)

    def out(self, line: str) -> None:
        """A line on standard output, unless its reader has gone."""
        if self.output_closed:
            return
        try:
            print(line, flush=True)
        except BrokenPipeError:
            self._output_gone()

    def _err(self, text: str, end: str = "\n") -> None:
        with contextlib.suppress(OSError):
            print(text, end=end, file=sys.stderr, flush=True)

    def _output_gone(self) -> None:
        """Stop printing; what is left for standard output goes to /dev/null."""
        self.output_closed = True
        discard_stdout()
