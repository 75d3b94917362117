"""Learning that holds in its own distribution (issue 34, item 0), measured.

50 expert demonstrations in D1 worlds (``workcell collect --world D1 --seed 0``), a
state-only ACT trained on them with ``workcell train`` (its defaults, ``--threads 1``),
then ``workcell evaluate`` in D1 on two seeds: seed 0, the very worlds of the
demonstrations (an evaluation's rollout ``i`` meets the world of the collection's trial
``i`` of the same seed: condition *own worlds*), and seed 1000, new worlds of the same
distribution (*new worlds*). The expert is evaluated on the same seeds in the same run: the
success a perfect imitation would reach.

The policy is evaluated as trained (``whole``: ACT executes each chunk open loop, with
``workcell train``'s defaults 10 actions, a policy call every half second at 20 frames/s;
``n20`` is the same variant's name from when the chunk was 20) and in variants that differ
only in how the chunks are executed, which training does not depend on (ACT's loss covers
the whole chunk whatever ``n_action_steps`` is): ``n5`` replans every 5 frames; ``ens``
replans every frame and averages the overlapping chunks (ACT's temporal ensembling,
coefficient 0.01). ``--chunk N`` trains with chunks of N actions instead of the default. A variant
is the checkpoint's directory copied with its ``config.json`` changed, so it is an operator
of its own in the store. Everything runs through the README's commands; a step whose output
is there is not run again.

    .venv/bin/python bench/learn_d1.py --work /tmp/learn-d1
    .venv/bin/python bench/learn_d1.py --work /tmp/learn-d1 --checkpoint 003000 --time-limit 60

What the policy observes is what the export gives it (``observation.state`` and
``observation.environment_state``). To compare observations on the same demonstrations
and seeds, run the bench from two checkouts with the same demonstration store copied into
each work directory, e.g. before (ee99439: the world-frame boxes and goal only) and after
(the robot-relative features of :mod:`workcell.export.relative` added)::

    git worktree add --detach /tmp/before ee99439
    mkdir /tmp/d1-before && cp /tmp/learn-d1/demos.sqlite /tmp/d1-before/
    PYTHONPATH=/tmp/before/src .venv/bin/python /tmp/before/bench/learn_d1.py --work /tmp/d1-before

``--checkpoint`` evaluates an earlier checkpoint of the training (it writes one every
1,000 steps); ACT's learning rate is constant in LeRobot, so step N of a 10,000-step run is
what an N-step run gives. ``--time-limit`` cuts every rollout (the expert's and the
policy's) short: a policy that stalls otherwise spends the task's 120 s in each.
"""

from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
import time
from pathlib import Path

from workcell.audit.ladder import Rung
from workcell.audit.store_source import StoreSource
from workcell.audit.task_stages import counts_text
from workcell.evaluate.table import recorded_rungs
from workcell.learn.checkpoint import PolicyCheckpoint

DEMO_SEED = 0
NEW_SEED = 1000
VARIANTS: dict[str, dict[str, object]] = {
    "whole": {},
    "n20": {},
    "n5": {"n_action_steps": 5},
    "ens": {"n_action_steps": 1, "temporal_ensemble_coeff": 0.01},
}
"""How each evaluated variant executes the policy's action chunks (``config.json`` changes)."""


def workcell(work: Path, *args: str) -> str:
    """Run ``workcell ARGS`` (this interpreter), its output appended to ``work/commands.log``."""
    command = [sys.executable, "-m", "workcell", *args]
    done = subprocess.run(command, capture_output=True, text=True, check=False)
    with (work / "commands.log").open("a") as out:
        out.write(f"$ workcell {' '.join(args)}\n{done.stdout}{done.stderr}\n")
    if done.returncode != 0:
        raise SystemExit(f"workcell {' '.join(args)} failed ({done.returncode}); see commands.log")
    return done.stdout


def variant(policy: Path, name: str, work: Path) -> Path:
    """A copy of ``policy``'s checkpoint executing its chunks as :data:`VARIANTS` says."""
    out = work / f"act-d1-{name}"
    if not out.exists():
        source = PolicyCheckpoint.locate(policy).path
        shutil.copytree(source, out)
        config = json.loads((out / "config.json").read_text())
        config.update(VARIANTS[name])
        (out / "config.json").write_text(json.dumps(config, indent=2))
    return out


def evaluate(  # noqa: PLR0917 - a benchmark's knobs
    work: Path, name: str, policy: str, seed: int, rollouts: int, limit_s: float | None
) -> Rung:
    store = work / f"eval-{name}-seed{seed}-r{rollouts}.sqlite"
    if not store.exists():
        print(f"evaluating {name} on seed {seed} ({rollouts} rollouts) ...", flush=True)
        limit = [] if limit_s is None else ["--set", f"task.time_limit_s={limit_s:g}"]
        workcell(work, "evaluate", "--policy", policy, "--world", "D1", "--rollouts",
                 str(rollouts), "--seed", str(seed), "--store", str(store), *limit)  # fmt: skip
    source = StoreSource(store)
    try:
        sessions = {s.session_id for s in source.sessions()}
    finally:
        source.close()
    (rung,) = recorded_rungs(store, sessions)
    return rung


def line(name: str, condition: str, rung: Rung) -> str:
    return (
        f"{name:8s} {condition:10s} {rung.successes:3d}/{rung.rollouts:<3d}"
        f" = {100 * rung.rate:5.1f} % [Wilson 95 % {100 * rung.low:5.1f}, {100 * rung.high:5.1f}]"
        f"  got to: {counts_text(rung.stages)}"
    )


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--work", type=Path, required=True, help="directory kept between runs")
    parser.add_argument("--demos", type=int, default=50)
    parser.add_argument(
        "--base-noise",
        type=float,
        default=0.0,
        help="collect the demonstrations with the expert's base pushed (m/s; collect --base-noise)",
    )
    parser.add_argument("--steps", type=int, default=10_000)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument(
        "--rollouts",
        type=int,
        default=20,
        help="per condition; in the own worlds at most --demos (there are no more of them)",
    )
    parser.add_argument(
        "--checkpoint",
        default="last",
        help="which checkpoint of the training to evaluate (a step, e.g. 004000; default last)",
    )
    parser.add_argument(
        "--time-limit",
        type=float,
        help="each rollout's time limit, s (default: the task's); the expert takes about 22 s",
    )
    parser.add_argument("--variants", default="whole,ens", help="of " + ",".join(VARIANTS))
    parser.add_argument(
        "--chunk",
        type=int,
        help="train with action chunks of this many frames (default: workcell train's)",
    )
    args = parser.parse_args(argv)
    work: Path = args.work
    work.mkdir(parents=True, exist_ok=True)
    demos, dataset, policy = work / "demos.sqlite", work / "dataset", work / "act-d1"
    if not demos.exists():
        print(f"collecting {args.demos} expert demonstrations in D1 ...", flush=True)
        noise = ["--base-noise", f"{args.base_noise:g}"] if args.base_noise > 0 else []
        workcell(work, "collect", "--mode", "collection", "--world", "D1", "--trials",
                 str(args.demos), "--seed", str(DEMO_SEED), "--store", str(demos),
                 *noise)  # fmt: skip
    if not (dataset / "meta" / "info.json").exists():
        workcell(work, "export", "--format", "lerobot", "--store", str(demos),
                 "--out", str(dataset), "--successes")  # fmt: skip
    if not (policy / "checkpoints" / args.checkpoint / "pretrained_model").exists():
        print(f"training {policy.name} ({args.steps} steps) ...", flush=True)
        started = time.perf_counter()
        chunk = (
            []
            if args.chunk is None
            else [
                f"--lerobot=--policy.chunk_size={args.chunk}",
                f"--lerobot=--policy.n_action_steps={args.chunk}",
            ]
        )
        workcell(work, "train", "--dataset", str(dataset), "--out", str(policy),
                 "--steps", str(args.steps), "--threads", str(args.threads), *chunk)  # fmt: skip
        (work / "train.minutes").write_text(f"{(time.perf_counter() - started) / 60:.1f}\n")
    trained = policy / "checkpoints" / args.checkpoint / "pretrained_model"
    conditions = {
        "own worlds": (DEMO_SEED, min(args.rollouts, args.demos)),
        "new worlds": (NEW_SEED, args.rollouts),
    }
    print(f"\n{args.demos} expert demonstrations in D1, state-only ACT ({trained}), D1 rollouts:")
    for condition, (seed, rollouts) in conditions.items():
        rung = evaluate(work, "expert", "expert", seed, rollouts, args.time_limit)
        print(line("expert", condition, rung), flush=True)
    for name in args.variants.split(","):
        path = variant(trained, name, work)
        for condition, (seed, rollouts) in conditions.items():
            rung = evaluate(work, name, str(path), seed, rollouts, args.time_limit)
            print(line(name, condition, rung), flush=True)


if __name__ == "__main__":
    main()
