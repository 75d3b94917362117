"""``workcell study``: check a study file and print its plan, print a commented one, or run
a participant's remaining sessions headless with the scripted expert (a pilot)."""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from workcell.errors import ConfigError

if TYPE_CHECKING:
    from workcell.cli.command import Subparsers
    from workcell.study.config import StudyConfig
    from workcell.study.plan import PlannedSession


def register(subparsers: Subparsers) -> None:
    parser = subparsers.add_parser(
        "study",
        help="check a study file and print each participant's plan, or pilot it",
        description=(
            "A study compares conditions over many participants: each runs every condition, "
            "in a counterbalanced order, and the study's steps in each. With FILE: check it "
            "and print every participant's sessions (with --store, what is done). With "
            "--participant: run that participant's remaining sessions headless with the "
            "scripted expert at --skill, recorded into --store (a pilot of the study; "
            "stopped runs resume where they left off). --defaults prints a commented file."
        ),
    )
    parser.add_argument("file", nargs="?", type=Path, metavar="FILE", help="the study (TOML)")
    parser.add_argument("--defaults", action="store_true", help="print a commented study file")
    parser.add_argument("--store", type=Path, metavar="PATH", help="the study's store")
    parser.add_argument(
        "--participant", metavar="ID", help="run this participant's remaining sessions (p01...)"
    )
    parser.add_argument(
        "--skill", type=float, default=1.0, help="the simulated participant's skill in [0, 1]"
    )
    parser.add_argument("--json", action="store_true", help="one JSON object per line")
    parser.set_defaults(func=run)


def _check(args: argparse.Namespace) -> list[str]:
    problems = []
    if args.defaults and args.file is not None:
        problems.append("--defaults: prints a new study file; it cannot go with FILE")
    if not args.defaults and args.file is None:
        problems.append("FILE: give a study file (or --defaults for a commented one)")
    if args.participant is not None and args.store is None:
        problems.append("--participant: records into a store; give --store PATH")
    if not (math.isfinite(args.skill) and 0.0 <= args.skill <= 1.0):
        problems.append(f"--skill = {args.skill:g}: must be between 0 and 1")
    return problems


def run(args: argparse.Namespace) -> int:
    problems = _check(args)
    if problems:
        raise ConfigError(problems)
    if args.defaults:
        from workcell.study.template import TEMPLATE  # noqa: PLC0415

        print(TEMPLATE, end="")
        return 0
    from workcell.study.config import load_study  # noqa: PLC0415
    from workcell.study.plan import participant_plan  # noqa: PLC0415

    study = load_study(args.file)
    if args.participant is None:
        _print_plan(study, args.store, args.json)
        return 0
    try:
        plan = participant_plan(study, args.participant)
    except ValueError as error:
        raise ConfigError([f"--participant: {error}"]) from None
    return _run_participant(plan, args.store, args.skill, args.json)


def _steps_text(study: StudyConfig) -> str:
    return ", ".join(
        s.mode if s.mode != "collection" else f"collection of {s.trials}" for s in study.steps
    )


def _print_plan(study: StudyConfig, store: Path | None, as_json: bool) -> None:
    from workcell.study.plan import participant_ids, participant_plan  # noqa: PLC0415
    from workcell.study.progress import remaining  # noqa: PLC0415

    participants = participant_ids(study)
    sessions = len(study.conditions) * len(study.steps)
    if not as_json:
        print(
            f"study {study.name}: {len(participants)} participants x {len(study.conditions)} "
            f"conditions x {len(study.steps)} steps ({_steps_text(study)}) = "
            f"{len(participants) * sessions} sessions; order {study.order}"
        )
    for participant in participants:
        plan = participant_plan(study, participant)
        order = list(dict.fromkeys(p.condition for p in plan))
        done = len(plan) - len(remaining(plan, store)) if store is not None else None
        if as_json:
            row = {"participant": participant, "conditions": order, "sessions": len(plan)}
            print(json.dumps(row | ({} if done is None else {"done": done})))
            continue
        progress = "" if done is None else f"  ({done}/{len(plan)} sessions done)"
        print(f"  {participant}: {' -> '.join(order)}{progress}")


def _run_participant(plan: list[PlannedSession], store: Path, skill: float, as_json: bool) -> int:
    from workcell.expert import ExpertConfig  # noqa: PLC0415
    from workcell.recording.drivers import ExpertDriver  # noqa: PLC0415
    from workcell.recording.headless import headless_status, run_headless  # noqa: PLC0415
    from workcell.recording.recorded_session import (  # noqa: PLC0415
        RecordedSession,
        RecordedSessionConfig,
    )
    from workcell.study.progress import remaining  # noqa: PLC0415

    todo = remaining(plan, store)
    participant = plan[0].participant
    if not as_json:
        print(f"{participant}: {len(plan) - len(todo)} of {len(plan)} sessions done")
    for planned in todo:
        recorded = RecordedSessionConfig(
            session=planned.config, driver=ExpertDriver(ExpertConfig(skill=skill)), store=store
        )
        with RecordedSession.open(recorded) as session:
            signal_name = run_headless(session, lambda result: None)
        results = session.runner.results
        row = {
            "participant": participant,
            "position": planned.position,
            "condition": planned.condition,
            "step": planned.step,
            "mode": planned.config.task.mode,
            "session_id": session.session_id,
            "trials": len(results),
            "successes": sum(r.outcome == "success" for r in results),
        }
        if as_json:
            print(json.dumps(row), flush=True)
        else:
            print(
                f"  session {planned.position}/{len(plan)}: {planned.condition}, step "
                f"{planned.step} ({planned.config.task.mode}): {row['successes']}/"
                f"{row['trials']} successes",
                flush=True,
            )
        status = headless_status(session, signal_name)
        if status != 0:
            print(f"{participant}: stopped; run the same command again to resume", file=sys.stderr)
            return status
    return 0
