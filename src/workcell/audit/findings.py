"""Findings: every anomaly the audit reports, each tied to a trial or session id."""

from __future__ import annotations

from dataclasses import dataclass

from workcell.audit.stage_pass import stage_disagrees
from workcell.audit.trial_audit import TrialAudit

METRIC_MISMATCH = "metric_mismatch"
QUALITY_FLAG = "quality_flag"
REVIEW = "review"
STAGE_MISMATCH = "stage_mismatch"
SESSION = "session"
SOURCE = "source"


@dataclass(frozen=True)
class Finding:
    """``kind`` one of the constants above; ``subject`` the flag or metric concerned."""

    kind: str
    subject: str
    message: str
    trial_id: str | None = None
    session_id: str | None = None


def trial_findings(audit: TrialAudit) -> list[Finding]:
    """Mismatches (of metrics, then of the stage), flags and review notes of one audited
    trial, in that order."""
    ids = {"trial_id": audit.trial_id, "session_id": audit.row.session_id}
    found = [Finding(METRIC_MISMATCH, m.metric, m.describe(), **ids) for m in audit.mismatches]
    if stage_disagrees(audit):
        message = (
            f"recorded stage {audit.row.recorded_stage} (its judge's), but its frames say "
            f"{audit.recomputed_stage}"
        )
        found.append(Finding(STAGE_MISMATCH, "task_stage", message, **ids))
    for flag in audit.flags:
        effect = "disqualifying" if flag.disqualifying else "marked only"
        found.append(Finding(QUALITY_FLAG, flag.name, f"{flag.detail} [{effect}]", **ids))
    disposition = audit.disposition
    if disposition.refused is not None:
        found.append(Finding(REVIEW, "refused", disposition.refused, **ids))
    elif disposition.overridden and disposition.review is not None:
        review = disposition.review
        message = f"{review.kind} by {review.by} overrides the automatic decision: {review.reason}"
        found.append(Finding(REVIEW, review.kind, message, **ids))
    return found
