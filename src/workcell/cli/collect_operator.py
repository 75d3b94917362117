"""Who drives a ``workcell collect`` session: the scripted expert or a learned policy.

A session records its operator's id. Unless one is given (``--operator-id`` or the
configuration), it is ``expert`` (``expert-skill<X>`` below full skill) or the policy's
:attr:`~workcell.learn.checkpoint.PolicyCheckpoint.operator_id`: its type, training run
and weights hash, so the audit groups sessions by who drove them. With ``--corrector`` it
is the corrector's (who watched, as in a live session a person corrects; the trials record
who drove).
"""

from __future__ import annotations

import argparse
import dataclasses
from typing import TYPE_CHECKING

from workcell.session.config import SessionConfig

if TYPE_CHECKING:
    from workcell.intervene.corrector import ScriptedCorrector
    from workcell.learn.checkpoint import PolicyCheckpoint
    from workcell.recording.drivers import Driver
    from workcell.recording.recorded_session import RecordedSession

POLICY_PREFIX = "policy:"
DEFAULT_OPERATOR_ID = SessionConfig().operator_id


def policy_checkpoint(args: argparse.Namespace) -> PolicyCheckpoint | None:
    """The checkpoint ``--operator policy:PATH`` names (raises a LearnError when there is
    none), or None for the expert."""
    if not args.operator.startswith(POLICY_PREFIX):
        return None
    from workcell.learn.checkpoint import PolicyCheckpoint  # noqa: PLC0415

    return PolicyCheckpoint.locate(args.operator[len(POLICY_PREFIX) :])


def with_operator_id(
    config: SessionConfig, args: argparse.Namespace, checkpoint: PolicyCheckpoint | None
) -> SessionConfig:
    """``config`` with the operator's own id, unless the user chose one. With a scripted
    corrector the session is recorded as a live one a person watches: its ``driver``
    setting is ``--operator`` and its operator (who watched) the corrector, ``expert``."""
    if args.corrector is not None:
        config = dataclasses.replace(config, driver=args.operator)
    if args.operator_id is not None or config.operator_id != DEFAULT_OPERATOR_ID:
        return config
    if args.corrector is not None:
        name = args.corrector
    elif checkpoint is not None:
        name = checkpoint.operator_id
    else:
        name = expert_operator_id(args.skill, args.base_noise)
    return dataclasses.replace(config, operator_id=name)


def expert_operator_id(skill: float, base_noise: float) -> str:
    """``expert``, with ``-skill<X>`` below full skill and ``-noise<V>`` when its base is
    pushed (``--base-noise``)."""
    name = "expert" if skill >= 1.0 else f"expert-skill{skill:g}"
    return name if base_noise <= 0 else f"{name}-noise{base_noise:g}"


def driver(args: argparse.Namespace, checkpoint: PolicyCheckpoint | None) -> Driver:
    """Who ``--operator`` (and ``--skill``) name, as the recorded session builds it; with
    ``--corrector expert`` the task's expert stands by to take over."""
    from workcell.recording.drivers import (  # noqa: PLC0415
        ExpertDriver,
        InterveningDriver,
        PolicyDriver,
    )

    autonomous: ExpertDriver | PolicyDriver
    if checkpoint is None:
        from workcell.expert.skill import ExpertConfig  # noqa: PLC0415

        autonomous = ExpertDriver(ExpertConfig(skill=args.skill, base_noise=args.base_noise))
    else:
        autonomous = PolicyDriver(checkpoint, verbose=args.verbose)
    if args.corrector is None:
        return autonomous
    return InterveningDriver(autonomous, corrector=ExpertDriver())


def corrector(args: argparse.Namespace, session: RecordedSession) -> ScriptedCorrector | None:
    """The scripted corrector watching ``session`` (``--corrector``), or None."""
    if args.corrector is None:
        return None
    from workcell.intervene.corrector import ScriptedCorrector  # noqa: PLC0415
    from workcell.intervene.operator import InterveningOperator  # noqa: PLC0415
    from workcell.intervene.rules import CorrectorRules  # noqa: PLC0415

    operator = session.operator
    assert isinstance(operator, InterveningOperator)
    rules = CorrectorRules() if args.stall_s is None else CorrectorRules(stall_s=args.stall_s)
    return ScriptedCorrector(operator, session.runner, rules)
