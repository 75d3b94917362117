"""``workcell evaluate``: the generalization ladder of a policy (or the expert), recorded."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from workcell.cli.task_options import add_task_argument
from workcell.errors import ConfigError, WorkcellError

if TYPE_CHECKING:
    from workcell.cli.command import Subparsers
    from workcell.evaluate.plan import EvaluationPlan, Share
    from workcell.evaluate.run import Ran
    from workcell.learn.checkpoint import PolicyCheckpoint
    from workcell.recording.drivers import Driver
    from workcell.session.config import SessionConfig
    from workcell.task.runner import TrialResult
    from workcell.tasks.worlds import WorldName

EXPERT = "expert"
DEFAULT_WORLDS = "D0,D1,D2"
MAX_WORKERS = 64


def register(subparsers: Subparsers) -> None:
    parser = subparsers.add_parser(
        "evaluate",
        help="run a policy (or the expert) N times in each named world and print the ladder",
        description=(
            "Run N rollouts of a learned policy (a LeRobot checkpoint; needs the learn extra) "
            "or of the scripted expert in each named world of the task, record them into "
            "--store like any collect session, and print one table: per world the successes, "
            "the success rate with its Wilson 95 % interval, the median completion time of "
            "the successes and the stages the rollouts reached. Rollout i of every world "
            "starts from the same trial seed of --seed, for every policy evaluated with it, "
            "so two policies compare on the same worlds; 'workcell audit' draws the ladder."
        ),
    )
    parser.add_argument(
        "--policy",
        required=True,
        metavar="PATH|expert",
        help="the LeRobot policy at PATH (a pretrained_model directory, or a 'workcell "
        "train' output), or 'expert' for the scripted expert (the baseline)",
    )
    add_task_argument(parser)
    parser.add_argument(
        "--world",
        default=DEFAULT_WORLDS,
        metavar="D0,D1,D2",
        help=f"the task's named worlds to evaluate in, comma-separated (default: {DEFAULT_WORLDS})",
    )
    parser.add_argument(
        "--rollouts", type=int, required=True, metavar="N", help="rollouts per world"
    )
    parser.add_argument(
        "--seed",
        type=int,
        required=True,
        metavar="S",
        help="the evaluation seed: rollout i of every world starts from trial seed i of S "
        "(use seeds none of the demonstrations used)",
    )
    parser.add_argument(
        "--store",
        type=Path,
        required=True,
        metavar="OUT",
        help="SQLite store to record into (created if absent; may hold other sessions)",
    )
    parser.add_argument("--config", type=Path, metavar="FILE", help="session settings (TOML)")
    parser.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="override one setting, e.g. --set task.time_limit_s=60 (repeatable)",
    )
    parser.add_argument(
        "--workers",
        type=int,
        default=1,
        metavar="W",
        help="run each world's rollouts in W worker processes, one store shard each, merged "
        "into --store (the same seeds as with one)",
    )
    parser.set_defaults(func=run)


def _problems(args: argparse.Namespace) -> list[str]:
    from workcell.evaluate.plan import rollout_problems  # noqa: PLC0415
    from workcell.evaluate.sessions import override_problems  # noqa: PLC0415

    problems = rollout_problems(args.rollouts) + override_problems(args.set)
    if not 0 <= args.seed < 2**63:
        problems.append(f"--seed = {args.seed}: must be a whole number from 0 to 2^63-1")
    if not 1 <= args.workers <= MAX_WORKERS:
        problems.append(f"--workers = {args.workers}: must be 1 to {MAX_WORKERS}")
    return problems


def _checkpoint(policy: str) -> PolicyCheckpoint | None:
    if policy == EXPERT:
        return None
    from workcell.learn.checkpoint import PolicyCheckpoint  # noqa: PLC0415

    return PolicyCheckpoint.locate(policy)


def _driver(checkpoint: PolicyCheckpoint | None) -> Driver:
    from workcell.recording.drivers import ExpertDriver, PolicyDriver  # noqa: PLC0415

    return ExpertDriver() if checkpoint is None else PolicyDriver(checkpoint)


def _plan(args: argparse.Namespace) -> tuple[EvaluationPlan, PolicyCheckpoint | None]:
    """The plan and the policy, every problem with them named at once."""
    from workcell.evaluate.plan import EvaluationPlan, parse_worlds  # noqa: PLC0415
    from workcell.evaluate.sessions import base_config  # noqa: PLC0415

    problems = _problems(args)
    worlds: tuple[WorldName, ...] = ()
    try:
        worlds = parse_worlds(args.world)
    except ConfigError as error:
        problems += error.problems
    try:
        base_config(args.config, args.set, args.task)
    except ConfigError as error:
        problems += error.problems
    checkpoint = None
    try:
        checkpoint = _checkpoint(args.policy)
    except WorkcellError as error:
        problems.append(f"{error}; or --policy expert for the scripted expert")
    if problems:
        raise ConfigError(problems)
    return EvaluationPlan(worlds, args.rollouts, args.seed), checkpoint


def run(args: argparse.Namespace) -> int:
    from workcell.audit.counts import counted  # noqa: PLC0415
    from workcell.evaluate.sessions import share_config  # noqa: PLC0415
    from workcell.evaluate.table import recorded_rungs, table_lines  # noqa: PLC0415

    plan, checkpoint = _plan(args)
    operator = EXPERT if checkpoint is None else checkpoint.operator_id
    shares: list[tuple[Share, SessionConfig]] = [
        (
            share,
            share_config(
                args.config, args.set, args.task, share, seed=plan.seed, operator_id=operator
            ),
        )
        for world in plan.worlds
        for share in plan.shares(world, args.workers)
    ]
    task = shares[0][1].task.kind
    _say(
        f"evaluate {operator} on {task}: {counted(plan.rollouts, 'rollout')} in each of "
        f"{', '.join(plan.worlds)} (seed {plan.seed}), recorded into {args.store}"
    )
    progress = _Progress(plan)
    driver = _driver(checkpoint)
    if args.workers > 1:
        from workcell.evaluate.parallel import run_in_workers  # noqa: PLC0415

        ran = run_in_workers(shares, driver, args.store, progress)
    else:
        from workcell.evaluate.run import run_shares  # noqa: PLC0415

        ran = run_shares(shares, driver, args.store, progress)
    rungs = recorded_rungs(args.store, ran.session_ids)
    print(f"{operator} on {task}, seed {plan.seed}: {counted(plan.rollouts, 'rollout')} per world")
    for line in table_lines(rungs):
        print(line)
    print(f"recorded {counted(len(ran.session_ids), 'session')} into {args.store}")
    if ran.signal_name is not None:
        print(f"stopped by {ran.signal_name}: the table counts the rollouts that ran")
    return _status(ran)


def _status(ran: Ran) -> int:
    from workcell.recording.headless import EXIT_STORAGE  # noqa: PLC0415
    from workcell.recording.shutdown import exit_status  # noqa: PLC0415

    for death in ran.worker_deaths:
        print(f"workcell: error: {death}", file=sys.stderr)
    if ran.failure is not None:
        print(f"workcell: error: {ran.failure}", file=sys.stderr)
        return EXIT_STORAGE
    if ran.signal_name is not None:
        return exit_status(ran.signal_name)
    return EXIT_STORAGE if ran.worker_deaths else 0


class _Progress:
    """One line on standard error per rollout as it ends, with the world's count so far."""

    def __init__(self, plan: EvaluationPlan) -> None:
        self.plan = plan
        self.done: dict[str, list[bool]] = {w: [] for w in plan.worlds}

    def __call__(self, share: Share, result: TrialResult) -> None:
        outcomes = self.done[share.world]
        outcomes.append(result.outcome == "success")
        outcome: str = result.outcome
        if result.interruption_reason:
            outcome = f"{outcome}:{result.interruption_reason}"
        width = len(str(self.plan.rollouts))
        _say(
            f"  {share.world} rollout {result.spec.trial_index + 1:>{width}}/{self.plan.rollouts}: "
            f"{outcome}, stage {result.stage}, {result.elapsed_s:.2f} s; "
            f"{sum(outcomes)} of {len(outcomes)} succeeded so far"
        )


def _say(line: str) -> None:
    print(line, file=sys.stderr, flush=True)
