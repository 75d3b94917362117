"""From ten demonstrations to a thousand (issue 34, item 6), measured end to end.

1. **Sources**: ``--sources`` trials (10) recorded the way people record them, through a
   ``workcell serve`` of its own and a scripted remote operator over its WebSocket
   (:mod:`bench.teleop_sources`), in D0 (session seed 1).
2. **Generation**: ``workcell generate --world D2 --attempts A --seed 1000`` from them
   (1,000): acceptance with its Wilson interval, false successes caught by the settled
   re-check, attempts per CPU-hour, as ``workcell generate`` reports them.
3. **Datasets** (``workcell export --format lerobot``): the sources' successes
   (``sources``); every accepted generated trial (``generated``: ``--successes``, the
   generator's ``exclude`` annotation keeps false successes out); the audit's keep of
   them (``keep``: ``--audited --successes``, valid successes without a quality flag).
4. **Training**: ``workcell train`` on each (its defaults, ``--threads 1``).
5. **The ladder**: ``workcell evaluate`` in D0, D1 and D2, ``--rollouts`` each (200), seed
   5000 (worlds neither the sources nor the generation drew), for the expert (the
   baseline: what a perfect imitation reaches) and the three policies.

The audit's flags and thresholds are fixed before anything runs: the first run writes
``audit-definition.json`` (the audit's :meth:`~workcell.audit.config.AuditConfig.describe`
and the checkout's commit) into the work directory, and a run resumed with a different
definition stops, so whether the audit's keep helps generated data is not decided after
seeing it. Every step runs a README command (logged to ``commands.log``) and leaves a
marker when it has finished (``sources.done``, ``generate.txt``, ``dataset-*.done``,
``train-*.minutes``, ``eval-*.done``); a run skips the finished steps and starts an
unfinished one again from nothing, so an interrupted run continues where it stopped.

    .venv/bin/python -m bench.learn_generated --work /tmp/learn-gen          # hours (~7 CPU h)
    .venv/bin/python -m bench.learn_generated --work /tmp/learn-gen --workers 2  # on idle cores
    .venv/bin/python -m bench.learn_generated --work /tmp/learn-gen-q --quick  # minutes
"""

from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from workcell.audit.config import AuditConfig
from workcell.audit.ladder import Rung
from workcell.audit.store_source import StoreSource
from workcell.audit.task_stages import counts_text
from workcell.evaluate.table import recorded_rungs

ROOT = Path(__file__).resolve().parents[1]
SOURCE_SEED = 1
GENERATION_SEED = 1000
EVAL_SEED = 5000
WORLDS = ("D0", "D1", "D2")
DATASETS = {
    "sources": ("sources.sqlite", ("--successes",)),
    "generated": ("generated.sqlite", ("--successes",)),
    "keep": ("generated.sqlite", ("--audited", "--successes")),
}
"""Each dataset: the store it is exported from and the export's selection flags."""


@dataclass(frozen=True)
class Settings:
    work: Path
    sources: int
    attempts: int
    steps: int
    rollouts: int
    threads: int
    workers: int
    time_limit_s: float | None = None
    """Each evaluation rollout's limit (None: the task's 120 s)."""

    @staticmethod
    def parse(argv: list[str] | None) -> Settings:
        parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
        parser.add_argument("--work", type=Path, required=True, help="kept between runs")
        parser.add_argument("--sources", type=int, default=10, help="teleop source trials")
        parser.add_argument("--attempts", type=int, default=1000, help="generated in D2")
        parser.add_argument("--steps", type=int, default=10_000, help="training steps")
        parser.add_argument("--rollouts", type=int, default=200, help="per world and policy")
        parser.add_argument("--threads", type=int, default=1, help="training threads")
        parser.add_argument(
            "--workers", type=int, default=1, help="generation's and evaluation's processes"
        )
        parser.add_argument(
            "--quick",
            action="store_true",
            help="tiny sizes (2 sources, 6 attempts, 20 steps, 2 rollouts of at most 30 s)",
        )
        args = parser.parse_args(argv)
        if args.quick:
            return Settings(args.work, 2, 6, 20, 2, args.threads, args.workers, 30.0)
        return Settings(
            args.work,
            args.sources,
            args.attempts,
            args.steps,
            args.rollouts,
            args.threads,
            args.workers,
        )


def run(work: Path, *command: str) -> str:
    """Run ``command`` from the checkout's root, its output written to ``commands.log`` as
    it comes (``tail -f`` it to follow a long step: generation prints every attempt);
    returns that output."""
    with (work / "commands.log").open("ab") as log:
        log.write(f"$ {' '.join(command)}\n".encode())
        log.flush()
        start = log.tell()
        done = subprocess.run(command, cwd=ROOT, stdout=log, stderr=subprocess.STDOUT, check=False)
        log.write(b"\n")
    with (work / "commands.log").open("rb") as log:
        log.seek(start)
        output = log.read().decode(errors="replace")
    if done.returncode != 0:
        raise SystemExit(
            f"{' '.join(command[:4])} ... failed ({done.returncode}); see commands.log"
        )
    return output


def workcell(work: Path, *args: str) -> str:
    return run(work, sys.executable, "-m", "workcell", *args)


def fix_audit_definition(work: Path) -> None:
    """Write the audit's definition on the first run; stop a resumed run that differs."""
    commit = subprocess.run(
        ["git", "rev-parse", "HEAD"], cwd=ROOT, capture_output=True, text=True, check=False
    ).stdout.strip()
    definition = AuditConfig().describe()
    path = work / "audit-definition.json"
    if not path.exists():
        path.write_text(json.dumps({"commit": commit, "audit": definition}, indent=1) + "\n")
        return
    fixed = json.loads(path.read_text())
    if fixed["audit"] != json.loads(json.dumps(definition)):
        raise SystemExit(
            f"the audit's definition differs from the one this run fixed at its start "
            f"(commit {fixed['commit'] or 'unknown'}, {path}): start a new --work directory"
        )


def episodes(dataset: Path) -> int:
    info = json.loads((dataset / "meta" / "info.json").read_text())
    return int(info["total_episodes"])


STORE_SIDECARS = ("", "-wal", "-shm", "-journal", ".lock", ".reserve")


def clear(*paths: Path) -> None:
    """Remove what an interrupted step left (a store with its side files, a directory)."""
    for path in paths:
        for candidate in (path.with_name(path.name + tail) for tail in STORE_SIDECARS):
            if candidate.is_dir():
                shutil.rmtree(candidate)
            elif candidate.exists():
                candidate.unlink()


def pending(done: Path, *leftovers: Path) -> bool:
    """Whether a step is still to run: its marker ``done`` (written only once the step has
    finished) is absent; then what an interrupted run of it left is removed first, so a
    partial store, export or checkpoint is never taken for a finished one."""
    if done.exists():
        return False
    clear(*leftovers)
    return True


def prepare(s: Settings) -> str:
    """Steps 1-4; returns generation's summary line."""
    sources, generated = s.work / "sources.sqlite", s.work / "generated.sqlite"
    if pending(s.work / "sources.done", sources):
        print(f"recording {s.sources} source trials through workcell serve ...", flush=True)
        run(s.work, sys.executable, "-m", "bench.teleop_sources", "--out", str(sources),
            "--trials", str(s.sources), "--seed", str(SOURCE_SEED))  # fmt: skip
        (s.work / "sources.done").write_text(f"{s.sources}\n")
    summary = s.work / "generate.txt"
    if pending(summary, generated):
        print(f"generating {s.attempts} attempts in D2 ...", flush=True)
        out = workcell(s.work, "generate", "--source", str(sources), "--attempts",
                       str(s.attempts), "--seed", str(GENERATION_SEED), "--world", "D2",
                       "--store", str(generated), "--workers", str(s.workers))  # fmt: skip
        summary.write_text(next(x for x in out.splitlines() if " attempts, " in x) + "\n")
    for name, (store, flags) in DATASETS.items():
        dataset = s.work / f"dataset-{name}"
        if pending(s.work / f"dataset-{name}.done", dataset):
            workcell(s.work, "export", "--format", "lerobot", "--store", str(s.work / store),
                     "--out", str(dataset), *flags)  # fmt: skip
            (s.work / f"dataset-{name}.done").write_text(f"{episodes(dataset)}\n")
        policy = s.work / f"act-{name}"
        if pending(s.work / f"train-{name}.minutes", policy):
            print(f"training act-{name} on {episodes(dataset)} episodes ...", flush=True)
            started = time.perf_counter()
            workcell(s.work, "train", "--dataset", str(dataset), "--out", str(policy),
                     "--steps", str(s.steps), "--threads", str(s.threads))  # fmt: skip
            minutes = (time.perf_counter() - started) / 60
            (s.work / f"train-{name}.minutes").write_text(f"{minutes:.1f}\n")
    return summary.read_text().strip()


def evaluate(s: Settings, name: str, policy: str) -> list[Rung]:
    store = s.work / f"eval-{name}-r{s.rollouts}.sqlite"
    done = store.with_name(store.name + ".done")
    if pending(done, store):
        print(f"evaluating {name} ({s.rollouts} rollouts in each of D0, D1, D2) ...", flush=True)
        limit = () if s.time_limit_s is None else ("--set", f"task.time_limit_s={s.time_limit_s:g}")
        workcell(s.work, "evaluate", "--policy", policy, "--world", ",".join(WORLDS),
                 "--rollouts", str(s.rollouts), "--seed", str(EVAL_SEED),
                 "--store", str(store), "--workers", str(s.workers), *limit)  # fmt: skip
        done.write_text("done\n")
    source = StoreSource(store)
    try:
        sessions = {x.session_id for x in source.sessions()}
    finally:
        source.close()
    return sorted(recorded_rungs(store, sessions), key=lambda r: WORLDS.index(r.world))


def line(name: str, rung: Rung) -> str:
    return (
        f"{name:13s} {rung.world}  {rung.successes:3d}/{rung.rollouts:<3d} = "
        f"{100 * rung.rate:5.1f} % [Wilson 95 % {100 * rung.low:5.1f}, {100 * rung.high:5.1f}]"
        f"  got to: {counts_text(rung.stages)}"
    )


def main(argv: list[str] | None = None) -> None:
    s = Settings.parse(argv)
    s.work.mkdir(parents=True, exist_ok=True)
    print(f"work directory {s.work}; commands and their output in {s.work}/commands.log")
    print(f"(follow a long step with: tail -f {s.work}/commands.log)", flush=True)
    fix_audit_definition(s.work)
    generation = prepare(s)
    print(
        f"\ngeneration (D2, seed {GENERATION_SEED}) from {s.sources} teleop sources: {generation}"
    )
    for name in DATASETS:
        minutes = (s.work / f"train-{name}.minutes").read_text().strip()
        print(f"act-{name:9s} {episodes(s.work / f'dataset-{name}'):5d} episodes, "
              f"{s.steps} steps, trained in {minutes} min")  # fmt: skip
    print(f"\nthe ladder (seed {EVAL_SEED}, {s.rollouts} rollouts per world):")
    policies = {"expert": "expert"} | {
        f"act-{name}": str(s.work / f"act-{name}") for name in DATASETS
    }
    for name, policy in policies.items():
        for rung in evaluate(s, name, policy):
            print(line(name, rung), flush=True)


if __name__ == "__main__":
    main()
