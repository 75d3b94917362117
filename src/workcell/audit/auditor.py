"""Auditing trials one by one: each with its session's thresholds, rate and reviews.

Used by :func:`workcell.audit.run.run_audit` in its own process and by the worker
processes of :mod:`workcell.audit.parallel`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from workcell.audit.config import AuditConfig
from workcell.audit.disposition import latest_decisions
from workcell.audit.oscillation import OscillationCriteria
from workcell.audit.rows import SessionRow, TrialRow
from workcell.audit.source import Pauses
from workcell.audit.trial_audit import TrialAudit, audit_trial
from workcell.metrics import FrameArrays
from workcell.record.entries import AnnotationRecord


class TrialAuditor:
    """Audits trials one by one with their session's thresholds, rate and reviews."""

    def __init__(
        self,
        sessions: Sequence[SessionRow],
        annotations: Sequence[AnnotationRecord],
        config: AuditConfig,
        pauses: Mapping[str, Pauses] | None = None,
    ) -> None:
        self.config = config
        self.pauses = pauses or {}
        """Each paused trial's pauses (:meth:`~workcell.audit.source.AuditSource.trial_pauses`)."""
        self.sessions = {s.session_id: s for s in sessions}
        self.decisions = latest_decisions(annotations)
        self.criteria: dict[float, OscillationCriteria | None] = {}

    def audit(self, row: TrialRow, frames: FrameArrays) -> TrialAudit:
        session = self.sessions[row.session_id]
        if session.rate_hz not in self.criteria:
            self.criteria[session.rate_hz] = OscillationCriteria.of(
                self.config.oscillation, session.rate_hz
            )
        return audit_trial(
            row,
            session,
            frames,
            review=self.decisions.get(row.trial_id),
            config=self.config,
            criteria=self.criteria[session.rate_hz],
            pauses=self.pauses.get(row.trial_id, ()),
        )
