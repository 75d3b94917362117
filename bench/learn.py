"""Quality-conscious learning, measured: policies trained on Workcell data, evaluated and
audited in Workcell (issue 14).

Everything runs through the README's commands, as a user would run them (``workcell
collect``, ``export``, ``audit``, ``train``, ``collect --operator policy:...``), in a work
directory that keeps every store, dataset, checkpoint and report; a step whose output is
already there is not run again, so an interrupted run continues where it stopped.

a. Learning curve: the expert collects demonstrations (seed 0); a state-only ACT policy is
   trained on the first 25/50/100/200 of them and evaluated on 200 seeded rollouts (seed
   1000: worlds none of the demonstrations saw). Target: success >= 80 % with the Wilson
   lower bound >= 70 % and training <= 60 min for the largest set.
b. Filtering: a mixed dataset of expert demonstrations at full skill and at low skill
   (hesitation, detours, tremor, timeouts); one policy is trained on every trial, one on
   the trials the audit keeps for imitation (valid successes without a quality flag:
   ``workcell export --audited --successes``), both evaluated the same way. Target:
   filtering gains >= 10 points of success.

Baselines measured in the same run: the expert itself on the evaluation seeds (the
success rate a perfect imitation would reach) and its rollout speed.

    .venv/bin/python bench/learn.py --work /tmp/learn            # everything (hours)
    .venv/bin/python bench/learn.py --work /tmp/learn --part curve --demos 200
    .venv/bin/python bench/learn.py --work /tmp/learn --quick     # a smoke run (minutes)
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import json
import os
import sqlite3
import statistics
import subprocess
import sys
import time
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from workcell.audit.task_stages import counts_text
from workcell.metrics import wilson_interval

EXPERT_SEED = 0
MIXED_SEEDS = (10, 11)
EVAL_SEED = 1000


@dataclass(frozen=True)
class Settings:
    work: Path
    demos: tuple[int, ...]
    eval_trials: int
    steps: int
    threads: int
    mixed_trials: int
    low_skill: float
    policy: str
    filter_policies: tuple[str, ...] = ("kept", "all")
    """Which of the filtering experiment's two policies to train and evaluate, in order."""


@dataclass(frozen=True)
class Evaluation:
    name: str
    successes: int
    n: int
    seconds: float
    """Wall time of the evaluation's collect, start-up included."""
    sim_s: float
    """Sim time over all rollouts."""
    stages: dict[str, int]
    """How many rollouts ended at each task stage (``workcell audit``'s ``task_stages``)."""

    @property
    def rate(self) -> float:
        return self.successes / self.n if self.n else float("nan")

    def interval(self) -> tuple[float, float]:
        return wilson_interval(self.successes, self.n)

    def line(self, train_min: float | None = None, episodes: int | None = None) -> str:
        low, high = self.interval()
        trained = "" if train_min is None else f"  trained {train_min:5.1f} min"
        used = "" if episodes is None else f"  {episodes:4d} episodes"
        return (
            f"{self.name:28s}{used}{trained}  success {self.successes:3d}/{self.n}"
            f" = {100 * self.rate:5.1f} % [Wilson 95 % {100 * low:5.1f}, {100 * high:5.1f}]"
            f"  rollouts {self.sim_s / max(self.seconds, 1e-9):5.1f}x real time"
            f"  got to: {counts_text(self.stages)}"
        )


def workcell(*args: str, log: Path) -> subprocess.CompletedProcess[str]:
    """Run ``workcell ARGS`` (this interpreter), appending its output to ``log``."""
    command = [sys.executable, "-m", "workcell", *args]
    done = subprocess.run(command, capture_output=True, text=True, check=False)
    with log.open("a") as out:
        out.write(f"$ workcell {' '.join(args)}\n{done.stdout}{done.stderr}\n")
    if done.returncode != 0:
        raise SystemExit(f"workcell {' '.join(args)} failed ({done.returncode}); see {log}")
    return done


def collect(settings: Settings, store: Path, *args: str) -> None:
    if not store.exists():
        print(f"collecting {store.name} ...", flush=True)
        workcell("collect", "--mode", "collection", "--store", str(store), *args, log=log(settings))


def export(settings: Settings, store: Path, out: Path, *args: str) -> None:
    if not (out / "meta" / "info.json").exists():
        workcell("export", "--format", "lerobot", "--store", str(store), "--out", str(out),
                 *args, log=log(settings))  # fmt: skip


def episode_count(dataset: Path) -> int:
    return int(json.loads((dataset / "meta" / "info.json").read_text())["total_episodes"])


def train(settings: Settings, dataset: Path, out: Path, episodes: int | None = None) -> float:
    """Minutes of training (measured once, kept beside the checkpoint)."""
    minutes_file = out.with_suffix(".minutes")
    if minutes_file.exists():
        return float(minutes_file.read_text())
    arguments = ["train", "--dataset", str(dataset), "--out", str(out), "--policy", settings.policy]
    arguments += ["--steps", str(settings.steps)]
    if episodes is not None:
        arguments += ["--episodes", f"0-{episodes - 1}"]
    arguments += ["--threads", str(settings.threads)]
    print(f"training {out.name} ({settings.steps} steps) ...", flush=True)
    started = time.perf_counter()
    workcell(*arguments, log=log(settings))
    minutes = (time.perf_counter() - started) / 60
    minutes_file.write_text(f"{minutes}\n")
    return minutes


def evaluate(settings: Settings, name: str, operator: str) -> Evaluation:
    """``settings.eval_trials`` seeded rollouts recorded into their own store."""
    store = settings.work / f"eval-{name}.sqlite"
    result = settings.work / f"eval-{name}.json"
    if not result.exists():
        print(f"evaluating {name} on {settings.eval_trials} rollouts ...", flush=True)
        started = time.perf_counter()
        done = workcell(
            "collect", "--operator", operator, "--mode", "collection", "--json",
            "--trials", str(settings.eval_trials), "--seed", str(EVAL_SEED),
            "--store", str(store), log=log(settings),
        )  # fmt: skip
        seconds = time.perf_counter() - started
        rows = [json.loads(line) for line in done.stdout.splitlines() if line.startswith("{")]
        summary = {
            "successes": sum(r["outcome"] == "success" for r in rows),
            "n": len(rows),
            "seconds": seconds,
            "sim_s": sum(r["elapsed_s"] for r in rows),
        }
        result.write_text(json.dumps(summary))
    summary = json.loads(result.read_text())
    audited = audit(settings, store, settings.work / f"eval-{name}-audit")
    stages = audited["task_stages"]
    assert isinstance(stages, dict)
    return Evaluation(
        name,
        summary["successes"],
        summary["n"],
        summary["seconds"],
        summary["sim_s"],
        dict(stages["ended_at"]),
    )


def audit(settings: Settings, store: Path, out: Path) -> dict[str, object]:
    if not (out / "summary.json").exists():
        workcell("audit", "--store", str(store), "--out", str(out), log=log(settings))
    summary: dict[str, object] = json.loads((out / "summary.json").read_text())
    return summary


def log(settings: Settings) -> Path:
    return settings.work / "commands.log"


def curve(settings: Settings, expert: Evaluation) -> None:
    work = settings.work
    largest = max(settings.demos)
    store = work / "expert.sqlite"
    collect(settings, store, "--trials", str(largest), "--seed", str(EXPERT_SEED))
    dataset = work / "expert-dataset"
    export(settings, store, dataset)
    print("\na. learning curve (state-only ACT, evaluated on seed 1000)")
    print(expert.line())
    results: dict[int, tuple[Evaluation, float]] = {}
    for n in settings.demos:
        name = f"{settings.policy}-expert-{n}"
        minutes = train(settings, dataset, work / name, n)
        evaluation = evaluate(settings, name, f"policy:{work / name}")
        results[n] = (evaluation, minutes)
        print(evaluation.line(minutes, n) + f"  = {evaluation.rate / expert.rate:4.2f} x expert")
    final, minutes = results[largest]
    low, _ = final.interval()
    met = final.rate >= 0.8 and low >= 0.7 and minutes <= 60
    print(
        f"target (success >= 80 %, Wilson low >= 70 %, training <= 60 min) with {largest} "
        f"demonstrations: {'met' if met else 'NOT met'}"
    )


def filtering(settings: Settings) -> None:
    work = settings.work
    store = work / "mixed.sqlite"
    half = settings.mixed_trials // 2
    if not store.exists():
        collect(settings, work / "mixed-expert.sqlite", "--trials", str(half),
                "--seed", str(MIXED_SEEDS[0]))  # fmt: skip
        collect(settings, work / "mixed-low.sqlite", "--trials", str(half),
                "--seed", str(MIXED_SEEDS[1]), "--skill", f"{settings.low_skill:g}")  # fmt: skip
        workcell("merge", "--out", str(store), str(work / "mixed-expert.sqlite"),
                 str(work / "mixed-low.sqlite"), log=log(settings))  # fmt: skip
    summary = audit(settings, store, work / "mixed-audit")
    everything, kept = work / "mixed-all", work / "mixed-kept"
    export(settings, store, everything, "--all")
    export(settings, store, kept, "--audited", "--successes")
    print(f"\nb. filtering (a mixed dataset: {half} trials at skill 1, {half} at skill "
          f"{settings.low_skill:g})")  # fmt: skip
    print("   audit:", describe_audit(summary, work / "mixed-audit" / "trials.csv"))
    for line in describe_operators(work / "mixed-audit" / "trials.csv", store):
        print("  ", line)
    results = {}
    datasets = {"kept": kept, "all": everything}
    for name in settings.filter_policies:
        dataset = datasets[name]
        out = work / f"{settings.policy}-mixed-{name}"
        minutes = train(settings, dataset, out)
        results[name] = evaluate(settings, f"{settings.policy}-mixed-{name}", f"policy:{out}")
        print(results[name].line(minutes, episode_count(dataset)))
    if set(results) != set(datasets):
        return
    gain = 100 * (results["kept"].rate - results["all"].rate)
    print(f"filtering gain: {gain:+.1f} points of success (target >= +10): "
          f"{'met' if gain >= 10 else 'NOT met'}")  # fmt: skip


def describe_audit(summary: dict[str, object], trials_csv: Path) -> str:
    counts = summary["counts"]
    assert isinstance(counts, dict)
    with trials_csv.open() as file:
        rows = list(csv.DictReader(file))
    flagged = sum(bool(r["quality_flags"]) for r in rows)
    return (
        f"{counts['raw']} trials: {counts['valid_successes']} valid successes, "
        f"{counts['valid_timeouts']} valid timeouts, {counts['excluded_low_quality']} "
        f"excluded as low quality, {flagged} with a quality flag"
    )


def describe_operators(trials_csv: Path, store: Path) -> list[str]:
    """Per operator of the mixed store: how many trials the audit keeps for imitation, and
    how those differ (completion time, share of frames with motion), which is what a
    quality filter could still act on."""
    with sqlite3.connect(store) as db:
        operator_of = dict(db.execute("SELECT session_id, operator_id FROM sessions"))
    with trials_csv.open() as file:
        rows = list(csv.DictReader(file))
    lines = []
    for operator in dict.fromkeys(operator_of[r["session_id"]] for r in rows):
        mine = [r for r in rows if operator_of[r["session_id"]] == operator]
        kept = [r for r in mine if r["disposition"] == "valid_success" and not r["quality_flags"]]
        times = [float(r["completion_time_s"]) for r in kept]
        active = [float(r["active_ratio"]) for r in kept]
        outcomes = ", ".join(f"{n} {o}" for o, n in Counter(r["outcome"] for r in mine).items())
        flags = Counter(f for r in mine for f in r["quality_flags"].split(";") if f)
        flagged = ", ".join(f"{n} {name}" for name, n in flags.items()) or "none"
        lines.append(
            f"{operator}: {len(mine)} trials ({outcomes}), flags: {flagged};"
            f" {len(kept)} kept; kept trials: completion time median "
            f"{_median(times):.1f} s (max {max(times, default=float('nan')):.1f}), share of "
            f"frames with motion median {_median(active):.2f} (min "
            f"{min(active, default=float('nan')):.2f})"
        )
    return lines


def _median(values: list[float]) -> float:
    return statistics.median(values) if values else float("nan")


def parse(argv: Sequence[str] | None = None) -> tuple[Settings, str]:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--work", type=Path, default=Path("/tmp/workcell-learn-bench"))
    parser.add_argument("--part", choices=("curve", "filter", "all"), default="all")
    parser.add_argument("--demos", default="25,50,100,200", help="learning-curve sizes")
    parser.add_argument("--eval-trials", type=int, default=200)
    parser.add_argument("--steps", type=int, default=10_000)
    parser.add_argument("--threads", type=int, default=1, help="training threads (0: torch's)")
    parser.add_argument("--mixed-trials", type=int, default=200)
    parser.add_argument("--low-skill", type=float, default=0.2)
    parser.add_argument("--policy", default="act")
    parser.add_argument(
        "--filter-policies", default="kept,all",
        help="which filtering policies to train, in order: kept (the audit's keep), all",
    )  # fmt: skip
    parser.add_argument("--quick", action="store_true", help="tiny sizes: checks the pipeline")
    args = parser.parse_args(argv)
    demos = tuple(int(n) for n in args.demos.split(","))
    settings = Settings(
        work=args.work,
        demos=demos,
        eval_trials=args.eval_trials,
        steps=args.steps,
        threads=args.threads,
        mixed_trials=args.mixed_trials,
        low_skill=args.low_skill,
        policy=args.policy,
        filter_policies=tuple(args.filter_policies.split(",")),
    )
    if not set(settings.filter_policies) <= {"kept", "all"}:
        parser.error(f"--filter-policies {args.filter_policies}: allowed are kept and all")
    if args.quick:
        settings = dataclasses.replace(
            settings, demos=(2,), eval_trials=2, steps=20, mixed_trials=4
        )
    return settings, args.part


def main(argv: Sequence[str] | None = None) -> None:
    settings, part = parse(argv)
    settings.work.mkdir(parents=True, exist_ok=True)
    os.environ.setdefault("MUJOCO_GL", "egl")
    print(f"work directory {settings.work}; commands and their output in {log(settings)}")
    expert = evaluate(settings, "expert", "expert")
    if part in ("curve", "all"):
        curve(settings, expert)
    if part in ("filter", "all"):
        filtering(settings)


if __name__ == "__main__":
    main()
