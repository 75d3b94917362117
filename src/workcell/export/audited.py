"""Inclusion as the audit decides it: the trials a quality-conscious dataset keeps.

``workcell export --audited`` runs the audit over the store (the metrics recomputed from
the frames, the quality detectors, the dispositions of the paper's Fig. 4, reviewers'
decisions) and keeps a trial when the audit finds it valid and raised no quality flag on
it: a flagged timeout, which the audit keeps as a genuine failure, is left out too, since
a dataset for imitation wants clean demonstrations (``marked by a quality flag: <flags>``).
The reason each other trial is left out is the audit's, in the words of
:mod:`workcell.record.inclusion` (``incomplete: ...``, ``low quality: ...``, ``excluded by
reviewer ...``).
"""

from __future__ import annotations

from pathlib import Path

from workcell.record.inclusion import Inclusion

MARKED = "marked by a quality flag"
"""The reason ``--audited`` leaves out a valid trial the audit marked (as its lines say)."""


def audited_inclusions(path: Path) -> dict[str, Inclusion]:
    """The audit's decision on every trial of the store at ``path``, by trial id."""
    from workcell.audit.run import run_audit  # noqa: PLC0415  (the audit only when asked)
    from workcell.audit.store_source import StoreSource  # noqa: PLC0415

    source = StoreSource(path)
    try:
        result = run_audit(source, workers=None)
    finally:
        source.close()
    decisions = {}
    for trial in result.trials:
        disposition = trial.disposition
        if not disposition.included:
            reason = disposition.exclusion_reason or disposition.stage
            decisions[trial.trial_id] = Inclusion(False, reason, disposition.review)
        elif trial.flags and not (disposition.review and disposition.review.kind == "include"):
            flags = ", ".join(flag.name for flag in trial.flags)
            reason = f"{MARKED}: {flags}"
            decisions[trial.trial_id] = Inclusion(False, reason, None)
        else:
            decisions[trial.trial_id] = Inclusion(True, None, disposition.review)
    return decisions
