"""``workcell audit``: recompute every metric, classify every trial, write the report."""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from collections.abc import Sequence

    from workcell.audit.comparison import RankTest
    from workcell.audit.counts import DispositionCounts
    from workcell.audit.run import AuditResult
    from workcell.audit.stats import GroupStats, SuccessRate
    from workcell.audit.trial_audit import TrialAudit
    from workcell.cli.command import Subparsers

PROGRESS_EVERY_S = 1.0


def register(subparsers: Subparsers) -> None:
    parser = subparsers.add_parser(
        "audit",
        help="recompute metrics, classify trials and write report.html + summary.json",
        description=(
            "Recompute every trial's metrics from its frames and check them against the "
            "stored values, flag sustained arm oscillation, sampling gaps, clocks, "
            "non-finite data and slow successes (beyond 1.5x the median completion time of "
            "the set's valid successes of their task), decide which trials are valid "
            "(incomplete and low-quality successes are excluded, timeouts kept; reviewer "
            "annotations override), read how far each trial got (the furthest task stage "
            "it reached, as `workcell tasks` lists its task's stages), print a summary with "
            "one line per operator and write report.html, summary.json and trials.csv into a "
            "new or empty folder. Reads a store or a CSV export; needs no simulator."
        ),
    )
    what = parser.add_mutually_exclusive_group(required=True)
    what.add_argument("--store", type=Path, metavar="PATH", help="a store file")
    what.add_argument("--csv", type=Path, metavar="DIR", help="a directory written by export")
    parser.add_argument(
        "--out", required=True, type=Path, metavar="DIR", help="new or empty output folder"
    )
    parser.add_argument(
        "--force", action="store_true", help="write into a non-empty folder (overwrites the report)"
    )
    parser.add_argument(
        "--trajectories",
        type=int,
        default=30,
        metavar="N",
        help="successful trials drawn in the trajectory figure (default: 30)",
    )
    parser.add_argument(
        "--workers",
        type=_workers,
        default=None,
        metavar="N",
        help="processes auditing a store's trials (default: one per core for large stores)",
    )
    parser.add_argument(
        "--by",
        choices=("operator", "condition"),
        help="compare groups of trials by operator or by study condition: success (Fisher's "
        "exact test), completion time and path (Mann-Whitney U), learning curves per "
        "participant, in the report, summary.json and one line per pair; by condition on a "
        "within-subject study (every participant runs every condition) a participant x "
        "condition table and paired tests instead (Wilcoxon signed-rank on each "
        "participant's values, rank-biserial r with its bootstrap interval, order effect)",
    )
    parser.add_argument(
        "--study",
        type=Path,
        metavar="FILE",
        help="the study file the trials belong to: the report names the study and says how "
        "much of each participant's plan is done, and compares its conditions within "
        "participants (implies --by condition unless --by is given)",
    )
    parser.add_argument(
        "--from-rows",
        action="store_true",
        help="read a store's frames from the frame rows, not from the per-trial frame "
        "blocks (slower; the same result when 'workcell verify' passes)",
    )
    parser.set_defaults(func=run)


def _workers(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"{text!r}: must be a whole number of processes >= 1")
    return value


class _Progress:
    """Prints how far the audit is to stderr, at most once a second."""

    def __init__(self) -> None:
        self.last = time.monotonic()

    def __call__(self, done: int, total: int, frames: int) -> None:
        now = time.monotonic()
        if now - self.last >= PROGRESS_EVERY_S:
            self.last = now
            print(f"audit: {done}/{total} trials, {frames} frames", file=sys.stderr, flush=True)


def run(args: argparse.Namespace) -> int:
    from workcell.audit.config import AuditConfig, CompareChoice  # noqa: PLC0415
    from workcell.audit.csv_source import CsvSource  # noqa: PLC0415
    from workcell.audit.run import run_audit  # noqa: PLC0415
    from workcell.audit.source import AuditSource  # noqa: PLC0415
    from workcell.audit.store_source import StoreSource  # noqa: PLC0415
    from workcell.audit.write import check_output, write_outputs  # noqa: PLC0415

    study = None
    if args.study is not None:
        from workcell.study.config import load_study  # noqa: PLC0415

        study = load_study(args.study)
    by: CompareChoice = args.by or ("condition" if study is not None else "none")
    config = AuditConfig(trajectories=args.trajectories, compare_by=by, study=study)
    check_output(args.out, args.force)
    source: AuditSource = (
        StoreSource(args.store, use_blocks=not args.from_rows)
        if args.store
        else CsvSource(args.csv)
    )
    try:
        result = run_audit(source, config, _Progress(), workers=args.workers)
    finally:
        source.close()
    paths = write_outputs(result, args.out)
    print(_summary_line(result))
    print(f"  task stages (how far each trial got): {_stages_text(result.trials)}")
    for line in _operator_lines(result) + _comparison_lines(result):
        print(line)
    print(f"wrote {', '.join(str(p) for p in paths.values())}")
    return 0


def _summary_line(result: AuditResult) -> str:
    from workcell.audit.counts import DispositionCounts, counted  # noqa: PLC0415
    from workcell.audit.stats import SuccessRate  # noqa: PLC0415

    c = DispositionCounts.of(result.trials)
    rate = _rate_text(SuccessRate.of(result.trials))
    return (
        f"audited {counted(c.raw, 'trial')} ({result.frames_read} frames): {c.valid} valid "
        f"({_outcomes_text(c)}), {rate}; "
        f"{c.incomplete} incomplete, {c.excluded_low_quality} low quality, "
        f"{c.excluded_by_reviewer} excluded by reviewer, {_marked_text(c)}; "
        f"{counted(len(result.findings), 'finding')}"
    )


def _outcomes_text(c: DispositionCounts) -> str:
    """The valid trials' outcomes: '1 success, 2 timeouts'."""
    from workcell.audit.counts import counted  # noqa: PLC0415

    successes = counted(c.valid_successes, "success", "successes")
    failed = f", {c.valid_failures} failed" if c.valid_failures else ""
    return f"{successes}, {counted(c.valid_timeouts, 'timeout')}{failed}"


def _marked_text(counts: DispositionCounts) -> str:
    """Valid trials kept despite a flag (left out of ``export --audited``)."""
    marked = counts.marked_successes + counts.marked_timeouts + counts.marked_failures
    return f"{marked} marked by a quality flag"


def _operator_lines(result: AuditResult) -> list[str]:
    """One line per operator, one operator included (with several: an evaluated policy
    beside the demonstrations it learned from)."""
    from workcell.audit.stats import GROUP_KEYS, GroupStats  # noqa: PLC0415

    operator_of = GROUP_KEYS["operator"]
    operators = dict.fromkeys(operator_of(t) for t in result.trials)
    groups = [
        GroupStats.of(name, [t for t in result.trials if operator_of(t) == name])
        for name in operators
    ]
    return _group_lines("operator", groups)


def _group_lines(key: str, groups: Sequence[GroupStats]) -> list[str]:
    from workcell.audit.counts import counted  # noqa: PLC0415

    lines = []
    for group in groups:
        c, rate = group.counts, _rate_text(group.rate)
        lines.append(
            f"  {key} {group.value}: {counted(c.raw, 'trial')}, {c.valid} valid "
            f"({_outcomes_text(c)}), {rate}, "
            f"{_marked_text(c)}; got to: {_stages_of_group(group)}"
        )
    return lines


def _stages_of_group(group: GroupStats) -> str:
    from workcell.audit.task_stages import counts_text  # noqa: PLC0415

    return counts_text(group.task_stages)


def _stages_text(trials: Sequence[TrialAudit]) -> str:
    """The stages trials got to; per task where they ran several."""
    from workcell.audit.task_funnel import task_funnels  # noqa: PLC0415
    from workcell.audit.task_stages import counts_text  # noqa: PLC0415

    funnels = task_funnels(trials)
    if len(funnels) == 1:
        return counts_text(funnels[0].ended_at)
    return "; ".join(f"{f.task}: {counts_text(f.ended_at)}" for f in funnels)


def _comparison_lines(result: AuditResult) -> list[str]:
    """With ``--by``: the groups (unless the operator lines showed them) and one line per
    pair of groups with its tests."""
    from workcell.audit.comparison import compare_result, result_study  # noqa: PLC0415
    from workcell.audit.paired_text import paired_lines  # noqa: PLC0415

    comparison = compare_result(result)
    if comparison is None:
        study = result_study(result)
        return [] if study is None else [f"  {study.text()}"]
    by = comparison.by
    lines = [] if by == "operator" else _group_lines(by, comparison.groups)
    if comparison.within is not None:
        return lines + paired_lines(comparison.within)
    if comparison.study is not None:
        lines.append(f"  {comparison.study.text()}")
    for pair in comparison.pairs:
        success = pair.success
        parts = [f"  {pair.first} vs {pair.second}: success"]
        if not math.isnan(success.p_value):
            parts.append(
                f" {100 * success.risk_difference:+.1f} points (Fisher p = {success.p_value:.3g})"
            )
        else:
            parts.append(" not compared (a group has no valid trial)")
        parts += [_rank_text(pair.first, pair.second, rank) for rank in pair.ranks]
        lines.append("".join(parts))
    if comparison.pairs:
        lines.append("  (repeated trials of one person are not independent: see the report)")
    return lines


def _rank_text(first: str, second: str, rank: RankTest) -> str:
    """A compared metric's medians and test; a group without a valid success is named as
    such (not a median of nan)."""
    from workcell.audit.comparison import RANKED_METRICS  # noqa: PLC0415

    name, unit = RANKED_METRICS[rank.metric]
    medians = {
        first: (rank.n_first, rank.median_first),
        second: (rank.n_second, rank.median_second),
    }
    without = [group for group, (n, _) in medians.items() if n == 0]
    if without:
        text = f"; {name}: no valid success in {' or '.join(without)}"
        with_values = [f"{m:.3g} {unit} in {group}" for group, (n, m) in medians.items() if n]
        return text + (f" (median {with_values[0]})" if with_values else "")
    text = f"; {name} median {rank.median_first:.3g} vs {rank.median_second:.3g} {unit}"
    if not math.isnan(rank.p_value):
        text += f" (Mann-Whitney p = {rank.p_value:.3g}, r = {rank.rank_biserial:+.2f})"
    return text


def _rate_text(rate: SuccessRate) -> str:
    """``success rate P % [low, high]`` (Wilson), or ``no valid trial``."""
    if not rate.n:
        return "no valid trial"
    return f"success rate {100 * rate.rate:.2f} % [{100 * rate.low:.2f}, {100 * rate.high:.2f}]"
