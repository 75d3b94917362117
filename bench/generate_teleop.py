"""Generation from people's demonstrations (issue 34, item 3): source trials recorded
through ``workcell serve`` by a scripted remote operator over the WebSocket
(``bench/teleop_sources.py``) against source trials of the scripted expert
(``workcell collect``), in the same run: the same number of sources, in the same D0 worlds
(the same session seed), each set generating the same attempts in D1 and D2.

Per source set: what the sources are like (length, the share of frames an arm was not
following, the times a stage was left and re-entered: the corrections a person's trials
carry), then per world the acceptance with its Wilson interval and n, false successes
caught by the re-check, and why attempts were rejected.

    .venv/bin/python -m bench.generate_teleop                      # 10 sources, 50 per world
    .venv/bin/python -m bench.generate_teleop --sources 4 --attempts 20 --keep /tmp/gt
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import numpy as np

from bench import teleop_sources
from bench.generate_worlds import record_sources, run_world
from workcell.generate.plan import GenerationPlan
from workcell.generate.references import references_for
from workcell.generate.source import SourceTrial, load_sources
from workcell.generate.tally import Tally
from workcell.tasks import WORLDS
from workcell.tasks.registry import load_task

TASK = "box_transfer"


def describe(sources: tuple[SourceTrial, ...]) -> str:
    """How long the sources are, how much of them an arm did not follow, how often a
    stage came back after another (a correction: a squeeze re-tried, a box re-grasped)."""
    seconds = [float(s.t[-1] - s.t[0]) for s in sources]
    not_following = [float(np.mean(~s.follow)) for s in sources]
    returns = [_returns(s.stage) for s in sources]
    return (
        f"{len(sources)} trials, {np.median(seconds):.1f} s median "
        f"({min(seconds):.1f}-{max(seconds):.1f}), arms not following "
        f"{100 * np.mean(not_following):.0f} % of frames, stages re-entered "
        f"{sum(returns)} times"
    )


def _returns(stages: tuple[str, ...]) -> int:
    seen: set[str] = set()
    count, previous = 0, None
    for stage in stages:
        if stage != previous:
            count += stage in seen
            seen.add(stage)
            previous = stage
    return count


def main() -> None:
    sys.stdout.reconfigure(line_buffering=True)  # type: ignore[union-attr]
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sources", type=int, default=10, help="source trials per set (D0)")
    parser.add_argument("--attempts", type=int, default=50, help="attempts per world and set")
    parser.add_argument("--worlds", default="D1,D2", help="comma-separated: D0, D1, D2")
    parser.add_argument("--seed", type=int, default=1000, help="generation seed")
    parser.add_argument("--source-seed", type=int, default=1, help="source sessions' seed")
    parser.add_argument("--keep", type=Path, help="keep the stores in this folder (reused)")
    args = parser.parse_args()
    worlds = args.worlds.split(",")
    unknown = [w for w in worlds if w not in WORLDS]
    if unknown:
        raise SystemExit(f"--worlds: {', '.join(unknown)} unknown; allowed: {', '.join(WORLDS)}")
    task = load_task(TASK)
    references = references_for(task)
    with tempfile.TemporaryDirectory() as scratch:
        folder = args.keep or Path(scratch)
        folder.mkdir(parents=True, exist_ok=True)
        stores = {"teleop": folder / "teleop.sqlite", "expert": folder / "expert.sqlite"}
        if not stores["teleop"].exists():
            print(f"recording {args.sources} teleop source trials through workcell serve ...")
            recorded = teleop_sources.record(stores["teleop"], args.sources, args.source_seed)
            print(f"  {recorded.successes} of {recorded.trials} succeeded ({recorded.reason})")
        if not stores["expert"].exists():
            record_sources(TASK, stores["expert"], args.sources, args.source_seed)
        results: dict[tuple[str, str], Tally] = {}
        for name, store in stores.items():
            plan = GenerationPlan.of(TASK, load_sources(store, TASK), references)
            print(f"{name} sources as {plan.operator_id}: {describe(plan.sources)}")
            for world in worlds:
                out = folder / f"generated-{name}-{world}.sqlite"
                out.unlink(missing_ok=True)
                results[name, world] = run_world(plan, world, args.attempts, args.seed, out, [])
        print(f"\n{args.sources} sources per set (D0), {args.attempts} attempts per world:")
        for (name, world), tally in results.items():
            print(
                f"  {name:6s} {world}: {tally.rate()}; false successes {tally.false_successes}; "
                f"rejected: {tally.rejections()}"
            )


if __name__ == "__main__":
    main()
