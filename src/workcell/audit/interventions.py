"""Corrections: how often people took over from an autonomous driver, and what it bought.

A trial's ``driver`` (schema version 6) says who drove it: ``person``, ``expert``,
``policy:<id>``, ``generated``. Where a person watched an autonomous driver they could take
over and hand back (``take_over``/``hand_back`` events; :mod:`workcell.intervene`). Per
driver, and per driver and person (the session's operator id: who watched and corrected;
:data:`UNWATCHED` for sessions nobody watched, as ``workcell collect`` runs them), over the
**rollouts** (complete trials: every outcome but ``interrupted``):

- interventions per trial: take-overs per rollout (mean);
- corrected share: the share of the rollouts' time the person drove, from each take-over
  to its hand-back or the trial's end (frames are at a fixed rate, so this is the share of
  frames recorded with ``intervention`` 1, to a frame per take-over);
- success of the driver alone (rollouts nobody took over) against with corrections
  (rollouts taken over at least once), each with its Wilson 95 % interval and its count.

Trials a person drove, and trials recorded before version 6, are not counted.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass

from workcell.audit.source import Switches
from workcell.audit.trial_audit import TrialAudit
from workcell.metrics import wilson_interval

INTERVENTIONS_VERSION = 1
"""The definitions above; a change of them is a new version."""
AUTONOMOUS_EXCLUDED = ("person",)
UNWATCHED = "(nobody watched)"
"""The person of trials no person watched (a session whose ``driver`` setting is
``person`` while its trials record an autonomous driver: ``workcell collect``,
``workcell evaluate``)."""


@dataclass(frozen=True)
class CorrectedTrial:
    """What the figures need of one trial."""

    driver: str
    person: str
    outcome: str | None
    elapsed_s: float
    take_overs: int
    corrected_s: float


@dataclass(frozen=True)
class Rate:
    """Successes of ``n`` rollouts, with the Wilson 95 % interval (NaN for none)."""

    successes: int
    n: int
    low: float
    high: float

    @property
    def rate(self) -> float:
        return self.successes / self.n if self.n else math.nan


@dataclass(frozen=True)
class InterventionGroup:
    """One driver's rollouts (``person`` empty: everyone's), or those one person watched."""

    driver: str
    person: str
    rollouts: int
    interrupted: int
    take_overs: int
    interventions_per_trial: float
    corrected_share: float
    alone: Rate
    corrected: Rate


def corrected_seconds(switches: Switches, elapsed_s: float) -> float:
    """The trial time the person drove: each take-over to its hand-back, or the end."""
    total, since = 0.0, None
    for kind, t in switches:
        if kind == "take_over" and since is None:
            since = max(t, 0.0)
        elif kind == "hand_back" and since is not None:
            total += max(0.0, min(t, elapsed_s) - since)
            since = None
    if since is not None:
        total += max(0.0, elapsed_s - since)
    return total


def corrected_trials(
    trials: Iterable[TrialAudit], switches: Mapping[str, Switches]
) -> list[CorrectedTrial]:
    """The trials an autonomous driver drove (recorded with a driver other than person)."""
    out: list[CorrectedTrial] = []
    for trial in trials:
        driver = trial.row.driver
        if driver is None or driver in AUTONOMOUS_EXCLUDED:
            continue
        mine = switches.get(trial.trial_id, ())
        elapsed = float(trial.row.stored.get("elapsed_s") or 0.0)
        out.append(
            CorrectedTrial(
                driver=driver,
                person=(
                    UNWATCHED if trial.session.driver == "person" else trial.session.operator_id
                ),
                outcome=trial.row.outcome,
                elapsed_s=elapsed,
                take_overs=sum(kind == "take_over" for kind, _ in mine),
                corrected_s=corrected_seconds(mine, elapsed),
            )
        )
    return out


def _rate(trials: Sequence[CorrectedTrial]) -> Rate:
    successes = sum(t.outcome == "success" for t in trials)
    low, high = wilson_interval(successes, len(trials))
    return Rate(successes, len(trials), low, high)


def group(driver: str, person: str, trials: Sequence[CorrectedTrial]) -> InterventionGroup:
    complete = [t for t in trials if t.outcome is not None and t.outcome != "interrupted"]
    take_overs = sum(t.take_overs for t in complete)
    time = sum(t.elapsed_s for t in complete)
    return InterventionGroup(
        driver=driver,
        person=person,
        rollouts=len(complete),
        interrupted=len(trials) - len(complete),
        take_overs=take_overs,
        interventions_per_trial=take_overs / len(complete) if complete else math.nan,
        corrected_share=sum(t.corrected_s for t in complete) / time if time > 0 else math.nan,
        alone=_rate([t for t in complete if t.take_overs == 0]),
        corrected=_rate([t for t in complete if t.take_overs > 0]),
    )


def intervention_groups(
    trials: Iterable[TrialAudit], switches: Mapping[str, Switches]
) -> list[InterventionGroup]:
    """Per driver (everyone's rollouts), then per driver and person, in order of first
    appearance; empty when no trial had an autonomous driver."""
    rows = corrected_trials(trials, switches)
    drivers: dict[str, dict[str, list[CorrectedTrial]]] = {}
    for row in rows:
        drivers.setdefault(row.driver, {}).setdefault(row.person, []).append(row)
    out: list[InterventionGroup] = []
    for driver, people in drivers.items():
        out.append(group(driver, "", [t for trials_ in people.values() for t in trials_]))
        out.extend(group(driver, person, mine) for person, mine in people.items())
    return out
