"""What a correction is worth (issue 35, item 5): success gained per minute of corrections
against per minute of fresh demonstrations, on box transfer in D1, in one run.

a. Base: the expert's demonstrations in D0 worlds (``--base-demos``, seed 0), a state-only
   ACT trained on them (``--steps``), evaluated in D1: a policy that fails there.
b. Corrections: the base policy drives D1 collection trials (seed 1000 + j for the j-th
   chunk) with the scripted corrector watching (``workcell collect --corrector expert``:
   the task's expert takes over when the stage has not advanced for ``--stall-s`` or a
   grasped box is dropped, drives to the next stage and hands back). The minutes of
   correction are read from the record: the frames with ``intervention`` 1 over the frame
   rate.
c. Fresh demonstrations: the expert's D1 demonstrations (seed 2000 + chunk) until their
   minutes (all their frames over the frame rate) reach the corrections' minutes.
d. Retrained from scratch, the same ``--steps``: base demonstrations + corrections
   (``workcell train --correction-weight K``, HG-DAgger's aggregate) against base
   demonstrations + fresh demonstrations.

Each point of the curve (``--correction-rollouts 10,20,40``: the corrections of the first
R rollouts, chunks of the difference, and demonstrations of as many minutes) is evaluated
in D1 with ``--rollouts`` on one seed (3000), as the base; printed: success, its Wilson
95 % interval, the minutes of data added to the base demonstrations and the success gained
per added minute. The figures go to ``WORK/intervene.json`` (and ``WORK/intervene.png``
with matplotlib). Everything runs through the README's commands (``workcell collect``,
``merge``, ``export``, ``train``, ``evaluate``), logged to ``WORK/commands.log``; a step
whose output is there is not run again.

    .venv/bin/python -m bench.intervene --work /tmp/intervene              # hours of CPU
    .venv/bin/python -m bench.intervene --work /tmp/intervene-smoke --smoke  # the pipeline
"""

from __future__ import annotations

import argparse
import json
import math
import shutil
from collections.abc import Callable
from dataclasses import asdict, dataclass
from pathlib import Path

from bench.learn_d1 import workcell
from workcell.audit.ladder import Rung
from workcell.audit.store_source import StoreSource
from workcell.evaluate.table import recorded_rungs
from workcell.record.store import Store

BASE_SEED = 0
CORRECTION_SEED = 1000
DEMO_SEED = 2000
EVAL_SEED = 3000
EXPERT_DEMO_S = 22.0
"""About how long an expert demonstration lasts (s): the first guess of how many make the
minutes asked; later chunks use the measured mean."""


@dataclass(frozen=True)
class Settings:
    work: Path
    base_demos: int
    steps: int
    threads: int
    rollouts: int
    correction_rollouts: tuple[int, ...]
    correction_weight: int
    stall_s: float
    time_limit_s: float | None
    workers: int = 1
    """Evaluation processes per policy (``workcell evaluate --workers``)."""


@dataclass(frozen=True)
class Point:
    """One evaluated policy: what was added to the base demonstrations and how it did."""

    name: str
    added: str
    minutes: float
    successes: int
    rollouts: int
    rate: float
    low: float
    high: float
    gain_per_minute: float | None
    """Success gained over the base per added minute (fraction per minute)."""
    stages: dict[str, int]


def limit(settings: Settings) -> list[str]:
    t = settings.time_limit_s
    return [] if t is None else ["--set", f"task.time_limit_s={t:g}"]


def recorded(store: Path, record: Callable[[], object]) -> None:
    """``record()`` into ``store`` unless a finished run did (``store``.done); what a run cut
    short left is removed first."""
    done = store.with_name(store.name + ".done")
    if done.exists():
        return
    for leftover in store.parent.glob(store.name + "*"):
        leftover.unlink()
    record()
    done.touch()


def collect(settings: Settings, store: Path, *args: str) -> None:
    def run() -> None:
        print(f"collecting {store.name} ...", flush=True)
        workcell(settings.work, "collect", "--mode", "collection", "--writer", "inline",
                 "--store", str(store), *args)  # fmt: skip

    recorded(store, run)


def frames(stores: list[Path]) -> tuple[int, int, int]:
    """Trials, frames and corrected frames (``intervention`` 1) of ``stores``."""
    trials = total = corrected = 0
    for path in stores:
        with Store.open(path, writer=False) as reader:
            for trial in reader.trials():
                flags = reader.frames(trial.trial_id)["intervention"]
                trials, total = trials + 1, total + len(flags)
                corrected += int((flags == 1.0).sum())
    return trials, total, corrected


def dataset(settings: Settings, name: str, stores: list[Path]) -> Path:
    """The LeRobot export of ``stores`` merged (``merged-NAME``.sqlite, ``NAME``-export;
    not ``NAME``-dataset, where ``workcell train --correction-weight`` writes its
    aggregate)."""
    out = settings.work / f"{name}-export"
    if not (out / "meta" / "info.json").exists():
        merged = settings.work / f"merged-{name}.sqlite"
        for leftover in settings.work.glob(merged.name + "*"):
            leftover.unlink()
        workcell(settings.work, "merge", "--out", str(merged), *map(str, stores))
        shutil.rmtree(out, ignore_errors=True)
        workcell(settings.work, "export", "--format", "lerobot", "--store", str(merged),
                 "--out", str(out))  # fmt: skip
    return out


def train(settings: Settings, name: str, data: Path, *args: str) -> Path:
    """The last checkpoint of a policy trained on ``data``; a training cut short (no
    ``name``.done) starts again."""
    out = settings.work / name
    done = settings.work / f"{name}.done"
    if not done.exists():
        print(f"training {name} ({settings.steps} steps) ...", flush=True)
        shutil.rmtree(out, ignore_errors=True)
        shutil.rmtree(Path(f"{out}-dataset"), ignore_errors=True)
        workcell(settings.work, "train", "--dataset", str(data), "--out", str(out), "--steps",
                 str(settings.steps), "--threads", str(settings.threads), *args)  # fmt: skip
        done.touch()
    return out / "checkpoints" / "last" / "pretrained_model"


def evaluate(settings: Settings, name: str, policy: Path) -> Rung:
    store = settings.work / f"eval-{name}.sqlite"

    def run() -> None:
        print(f"evaluating {name} in D1 ({settings.rollouts} rollouts) ...", flush=True)
        workcell(settings.work, "evaluate", "--policy", str(policy), "--world", "D1",
                 "--rollouts", str(settings.rollouts), "--seed", str(EVAL_SEED),
                 "--store", str(store), "--workers", str(settings.workers),
                 *limit(settings))  # fmt: skip

    recorded(store, run)
    source = StoreSource(store)
    try:
        sessions = {s.session_id for s in source.sessions()}
    finally:
        source.close()
    (rung,) = recorded_rungs(store, sessions)
    return rung


def point(name: str, added: str, minutes: float, rung: Rung, base: Rung | None) -> Point:
    gain = None if base is None or minutes <= 0 else (rung.rate - base.rate) / minutes
    return Point(
        name=name,
        added=added,
        minutes=minutes,
        successes=rung.successes,
        rollouts=rung.rollouts,
        rate=rung.rate,
        low=rung.low,
        high=rung.high,
        gain_per_minute=gain,
        stages=dict(rung.stages),
    )


def line(p: Point) -> str:
    gain = "" if p.gain_per_minute is None else f"  {100 * p.gain_per_minute:+6.2f} pts/min"
    return (
        f"{p.name:14s} {p.added:34s} {p.minutes:6.2f} min  {p.successes:3d}/{p.rollouts:<3d}"
        f" = {100 * p.rate:5.1f} % [Wilson 95 % {100 * p.low:5.1f}, {100 * p.high:5.1f}]{gain}"
    )


def fresh_demos(settings: Settings, minutes: float, have: list[Path], fps: float) -> list[Path]:
    """``have`` and as many more chunks of D1 expert demonstrations as bring their minutes
    to at least ``minutes``."""
    stores = list(have)
    while True:
        trials, total, _ = frames(stores)
        need_s = minutes * 60 - total / fps
        if need_s <= 0:
            return stores
        mean_s = total / fps / trials if trials else EXPERT_DEMO_S
        chunk = settings.work / f"fresh-{len(stores)}.sqlite"
        collect(settings, chunk, "--world", "D1", "--seed", str(DEMO_SEED + len(stores)),
                "--trials", str(max(1, math.ceil(need_s / mean_s))))  # fmt: skip
        stores.append(chunk)


def run(settings: Settings) -> list[Point]:
    work = settings.work
    base_store = work / "base-demos.sqlite"
    collect(settings, base_store, "--world", "D0", "--seed", str(BASE_SEED), "--trials",
            str(settings.base_demos))  # fmt: skip
    base_data = dataset(settings, "base", [base_store])
    fps = float(json.loads((base_data / "meta" / "info.json").read_text())["fps"])
    base_policy = train(settings, "base", base_data)
    base_rung = evaluate(settings, "base", base_policy)
    points = [point("base", f"{settings.base_demos} D0 demos", 0.0, base_rung, None)]
    print(line(points[0]), flush=True)
    corrections: list[Path] = []
    demos: list[Path] = []
    done = 0
    for r in settings.correction_rollouts:
        chunk = work / f"corrections-{len(corrections)}.sqlite"
        collect(settings, chunk, "--operator", f"policy:{base_policy}", "--corrector",
                "expert", "--stall-s", f"{settings.stall_s:g}", "--world", "D1", "--seed",
                str(CORRECTION_SEED + len(corrections)), "--trials", str(r - done),
                *limit(settings))  # fmt: skip
        corrections.append(chunk)
        done = r
        _, _, corrected = frames(corrections)
        minutes = corrected / fps / 60
        demos = fresh_demos(settings, minutes, demos, fps)
        demo_trials, demo_frames, _ = frames(demos)
        k = str(settings.correction_weight)
        data = dataset(settings, f"corrected-{r}", [base_store, *corrections])
        policy = train(settings, f"corrected-{r}", data, "--correction-weight", k)
        rung = evaluate(settings, f"corrected-{r}", policy)
        added = f"{r} corrected rollouts x{k}"
        points.append(point(f"corrected-{r}", added, minutes, rung, base_rung))
        print(line(points[-1]), flush=True)
        data = dataset(settings, f"demos-{r}", [base_store, *demos])
        rung = evaluate(settings, f"demos-{r}", train(settings, f"demos-{r}", data))
        added = f"{demo_trials} D1 demos"
        points.append(point(f"demos-{r}", added, demo_frames / fps / 60, rung, base_rung))
        print(line(points[-1]), flush=True)
    return points


def figure(points: list[Point], out: Path) -> bool:
    """Success against added minutes, one curve per kind of data; False without matplotlib."""
    try:
        import matplotlib  # noqa: PLC0415

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt  # noqa: PLC0415
    except ImportError:
        return False
    fig, ax = plt.subplots(figsize=(6, 4))
    base = points[0]
    for kind, label in (("corrected", "+ corrections"), ("demos", "+ fresh D1 demos")):
        curve = [base, *(p for p in points if p.name.startswith(kind))]
        x = [p.minutes for p in curve]
        y = [100 * p.rate for p in curve]
        err = [[100 * (p.rate - p.low) for p in curve], [100 * (p.high - p.rate) for p in curve]]
        ax.errorbar(x, y, yerr=err, marker="o", capsize=3, label=label)
    ax.set_xlabel("minutes of data added to the D0 demonstrations")
    ax.set_ylabel("D1 success, % (Wilson 95 %)")
    ax.set_ylim(0, 100)
    ax.legend()
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)
    return True


def parse(argv: list[str] | None) -> Settings:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--work", type=Path, required=True, help="directory kept between runs")
    parser.add_argument("--base-demos", type=int, default=50, help="D0 expert demonstrations")
    parser.add_argument("--steps", type=int, default=10_000, help="training steps, each policy")
    parser.add_argument("--threads", type=int, default=1, help="torch threads while training")
    parser.add_argument("--rollouts", type=int, default=100, help="D1 evaluation rollouts")
    parser.add_argument("--correction-rollouts", default="10,20,40", metavar="R,R,...")
    parser.add_argument("--correction-weight", type=int, default=1, metavar="K")
    parser.add_argument("--stall-s", type=float, default=8.0, help="the corrector's stall rule")
    parser.add_argument("--time-limit", type=float, default=60.0, help="policy rollouts, s")
    parser.add_argument("--workers", type=int, default=1, help="evaluation processes")
    parser.add_argument("--smoke", action="store_true", help="tiny: the pipeline, not a result")
    args = parser.parse_args(argv)
    try:
        rollouts = tuple(int(r) for r in args.correction_rollouts.split(","))
    except ValueError:
        parser.error(f"--correction-rollouts = {args.correction_rollouts!r}: must be R,R,...")
    if not rollouts or list(rollouts) != sorted(set(rollouts)) or rollouts[0] < 1:
        parser.error("--correction-rollouts: must be increasing whole numbers from 1")
    if args.smoke:
        smoke = (2, 2, args.threads, 2, (1, 2), args.correction_weight, 2.0, 20.0, args.workers)
        return Settings(args.work, *smoke)
    return Settings(
        args.work,
        args.base_demos,
        args.steps,
        args.threads,
        args.rollouts,
        rollouts,
        args.correction_weight,
        args.stall_s,
        args.time_limit,
        args.workers,
    )


def main(argv: list[str] | None = None) -> None:
    settings = parse(argv)
    settings.work.mkdir(parents=True, exist_ok=True)
    print(f"settings: {json.dumps(asdict(settings), default=str)}", flush=True)
    points = run(settings)
    print("\nD1 success per point (gain: success over the base per minute of added data):")
    for p in points:
        print(line(p))
    out = settings.work / "intervene.json"
    settings_json = json.loads(json.dumps(asdict(settings), default=str))
    figures = {"settings": settings_json, "points": [asdict(p) for p in points]}
    out.write_text(json.dumps(figures, indent=2) + "\n")
    drawn = figure(points, settings.work / "intervene.png")
    print(f"figures: {out}" + (f", {settings.work / 'intervene.png'}" if drawn else ""))


if __name__ == "__main__":
    main()
