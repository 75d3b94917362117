"""Running attempts: each one a recorded session of one trial, judged, re-checked, explained.

An attempt is a session of its own in the output store (operator ``generated-<hash>``, its
seed drawn from the generation's seed and the attempt's number), its one trial run by the
session runner like any operator's: the world drawn from the session's ranges, the judge
deciding success. After a success the simulation runs on for the re-check
(:mod:`workcell.generate.recheck`). Then a session event ``generation`` records the
attempt's provenance and verdict: the source trial it replayed (and the whole source set),
each segment's boundaries and motion, accepted or rejected and why. A success that fails
the re-check is also excluded by an ``exclude`` annotation (by ``workcell generate``), so
the audit and the exports leave it out like any reviewer's exclusion.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass
from pathlib import Path

from workcell.generate.operator import GeneratedOperator
from workcell.generate.plan import GenerationPlan
from workcell.generate.recheck import Recheck, recheck
from workcell.record.store import Store
from workcell.recording.drivers import GeneratedDriver
from workcell.recording.recorded_session import RecordedSession, RecordedSessionConfig, StopReason
from workcell.session.config import SessionConfig
from workcell.task.hud import HudPhase
from workcell.task.runner import trial_seed

EVENT_KIND = "generation"
"""The session event that holds an attempt's provenance and verdict."""
REVIEWER = "workcell generate"
"""Who excludes a false success (the annotation's ``by``)."""


@dataclass(frozen=True)
class AttemptResult:
    """How one attempt went."""

    attempt: int
    session_id: str
    trial_id: str
    source_trial_id: str
    outcome: str
    stage: str
    accepted: bool
    false_success: bool
    reason: str | None
    """Why it was rejected (None when accepted)."""
    cpu_s: float


def attempt_seed(seed: int, attempt: int) -> int:
    """The session seed of attempt number ``attempt`` of a generation seeded ``seed``."""
    return trial_seed(seed, attempt)


def run_attempt(
    plan: GenerationPlan,
    config: SessionConfig,
    attempt: int,
    store: Path,
    should_stop: StopReason | None = None,
) -> AttemptResult | None:
    """Run and record attempt number ``attempt`` into ``store``; None when it was stopped
    before its trial ended (the store holds it interrupted)."""
    began = time.process_time()
    session_config = dataclasses.replace(
        config, seed=attempt_seed(config.seed, attempt), operator_id=plan.operator_id
    )
    recorded = RecordedSessionConfig(
        session=session_config,
        driver=GeneratedDriver(plan),
        store=store,
        writer="inline",
        max_trials=1,
    )
    verdict: list[AttemptResult] = []
    with RecordedSession.open(recorded) as session:
        operator = session.operator
        assert isinstance(operator, GeneratedOperator)

        def after_step() -> None:
            if session.runner.phase is HudPhase.FINISHED and not verdict and session.runner.results:
                verdict.append(_judge(session, operator, plan, attempt, began))

        session.run(should_stop, after_step)
    return verdict[0] if verdict else None


def _judge(
    session: RecordedSession,
    operator: GeneratedOperator,
    plan: GenerationPlan,
    attempt: int,
    began: float,
) -> AttemptResult:
    """Re-check a success, then record the attempt's verdict and provenance."""
    (result,) = session.runner.results
    check: Recheck | None = None
    if result.outcome == "success":
        check = recheck(session.sim, operator, session.runner.task)
    accepted = check is not None and check.held
    false_success = check is not None and not check.held
    if accepted:
        reason = None
    elif false_success:
        assert check is not None
        reason = f"false success: {check.reason}"
    else:
        reason = f"{result.outcome} at stage {result.stage}"
    recorder = session.recorder
    assert recorder is not None
    store = recorder.store
    assert isinstance(store, Store), "generation writes its store in its own process"
    (trial,) = store.trials(session.session_id)
    provenance = operator.provenance
    store.add_event(
        session.session_id,
        EVENT_KIND,
        {
            "trial_id": trial.trial_id,
            "attempt": attempt,
            "operator_id": plan.operator_id,
            "source_trial_id": provenance.source_trial_id,
            "source_trial_ids": plan.source_ids,
            "segments": [run.as_dict() for run in provenance.segments],
            "outcome": result.outcome,
            "stage": result.stage,
            "recheck": None if check is None else check.as_dict(),
            "accepted": accepted,
            "reason": reason,
        },
    )
    if false_success:
        store.annotate(trial.trial_id, "exclude", reason or "false success", REVIEWER)
    return AttemptResult(
        attempt=attempt,
        session_id=session.session_id,
        trial_id=trial.trial_id,
        source_trial_id=provenance.source_trial_id,
        outcome=result.outcome,
        stage=result.stage,
        accepted=accepted,
        false_success=false_success,
        reason=reason,
        cpu_s=time.process_time() - began,
    )
