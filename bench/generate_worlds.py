"""Demonstration generation across worlds (issue 34, items 1, 2 and 4): expert source
trials recorded in D0 become attempts in D1 and D2; acceptance per world with Wilson
intervals and n, false successes caught by the settled re-check, attempts per CPU-hour.

The source trials are recorded by ``workcell collect`` (the expert, D0, collection mode);
each world's attempts by the generator's own path (``workcell generate`` runs the same
:func:`~workcell.generate.attempts.run_attempt`), one after another in this process, which
also writes the store: the CPU time is this process's, store writes included. Targets
(issue 34): acceptance >= 50 % in D1 and >= 30 % in D2, no accepted attempt that fails the
re-check (every success is re-checked; those that fail are rejected and counted here),
>= 1,000 accepted D1 demonstrations per CPU-hour.

    .venv/bin/python bench/generate_worlds.py                     # 10 sources, 100 per world
    .venv/bin/python bench/generate_worlds.py --attempts 20 --worlds D1
    .venv/bin/python bench/generate_worlds.py --source-store S.sqlite --worlds D2 --keep DIR
    .venv/bin/python bench/generate_worlds.py --naive      # the ablation: no re-targeting
    .venv/bin/python bench/generate_worlds.py --set 'world.target.zone=[0.4,0.4]'  # narrower
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import tempfile
import time
from pathlib import Path

from workcell.cli.main import main as workcell
from workcell.generate.attempts import run_attempt
from workcell.generate.plan import GenerationPlan
from workcell.generate.references import references_for
from workcell.generate.source import load_sources
from workcell.generate.tally import Tally
from workcell.session.load import resolve_session_config
from workcell.tasks import WORLDS, world_overrides
from workcell.tasks.registry import load_task

TASK = "box_transfer"


def record_sources(store: Path, trials: int, seed: int) -> None:
    argv = ["collect", "--mode", "collection", "--trials", str(trials), "--seed", str(seed)]
    if workcell([*argv, "--world", "D0", "--store", str(store), "--writer", "inline"]) != 0:
        raise SystemExit("recording the source trials failed")


def run_world(  # noqa: PLR0917 - a benchmark's knobs
    plan: GenerationPlan, world: str, attempts: int, seed: int, out: Path, sets: list[str]
) -> Tally:
    task = load_task(TASK)
    flags: dict[str, object] = {"task.kind": TASK, "task.mode": "collection", "task.trials": 1}
    flags.update(world_overrides(task.worlds[world]))  # type: ignore[index]
    config = resolve_session_config(None, sets, {**flags, "seed": seed})
    longest = max(float(s.t[-1]) for s in plan.sources)
    limit = min(config.task.time_limit_s, float(int(longest + 21)))
    config = dataclasses.replace(config, task=dataclasses.replace(config.task, time_limit_s=limit))
    tally = Tally()
    began = time.perf_counter()
    for attempt in range(attempts):
        result = run_attempt(plan, config, attempt, out)
        if result is None:
            raise SystemExit("an attempt was stopped")
        tally.add(result)
        verdict = "accepted" if result.accepted else f"rejected: {result.reason}"
        print(f"  {world} attempt {attempt:3d}: {verdict} | {tally.rate()}")
    wall = time.perf_counter() - began
    accepted_per_hour = tally.per_cpu_hour() * tally.accepted / max(1, tally.attempts)
    print(
        f"{world}: {tally.rate()}; false successes caught by the re-check: "
        f"{tally.false_successes}; rejected: {tally.rejections()}; "
        f"{tally.per_cpu_hour():.0f} attempts and {accepted_per_hour:.0f} accepted per "
        f"CPU-hour ({tally.cpu_s / tally.attempts:.2f} CPU s and {wall / tally.attempts:.2f} "
        "wall s per attempt)",
        flush=True,
    )
    return tally


def main() -> None:
    sys.stdout.reconfigure(line_buffering=True)  # type: ignore[union-attr]
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sources", type=int, default=10, help="expert source trials (D0)")
    parser.add_argument("--attempts", type=int, default=100, help="attempts per world")
    parser.add_argument("--worlds", default="D1,D2", help="comma-separated: D0, D1, D2")
    parser.add_argument("--seed", type=int, default=1000, help="generation seed")
    parser.add_argument("--source-seed", type=int, default=1, help="source session seed")
    parser.add_argument("--keep", type=Path, help="keep the stores in this folder")
    parser.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="a setting of the attempts' sessions, e.g. --set world.target.zone=[0.4,0.4]",
    )
    parser.add_argument(
        "--naive",
        action="store_true",
        help="ablation: replay each segment where it was recorded (no re-targeting)",
    )
    parser.add_argument(
        "--source-store", type=Path, help="use the source trials of this store (not recorded)"
    )
    args = parser.parse_args()
    worlds = args.worlds.split(",")
    unknown = [w for w in worlds if w not in WORLDS]
    if unknown:
        raise SystemExit(f"--worlds: {', '.join(unknown)} unknown; allowed: {', '.join(WORLDS)}")
    with tempfile.TemporaryDirectory() as scratch:
        folder = args.keep or Path(scratch)
        folder.mkdir(parents=True, exist_ok=True)
        sources = args.source_store or folder / "sources.sqlite"
        if args.source_store is None:
            record_sources(sources, args.sources, args.source_seed)
        task = load_task(TASK)
        plan = GenerationPlan.of(load_sources(sources, TASK), references_for(TASK, task.stages))
        how = "replayed where recorded (--naive)" if args.naive else "re-targeted"
        print(f"{len(plan.sources)} source trials (expert, D0) as {plan.operator_id}, {how}")
        for world in worlds:
            out = folder / f"generated-{world}.sqlite"
            run_world(plan, world, args.attempts, args.seed, out, args.set)


if __name__ == "__main__":
    main()
