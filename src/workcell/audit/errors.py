"""Errors of the audit: each message names the input and says what to do."""

from __future__ import annotations

from workcell.errors import WorkcellError


class AuditError(WorkcellError):
    """An audit cannot run as asked (unreadable input, output folder not empty, ...)."""
