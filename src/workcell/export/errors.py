"""Why an export (or a re-render) cannot be made; each message says what to do instead."""

from __future__ import annotations

from workcell.record.errors import ExportError


class OutputNotEmptyError(ExportError):
    """The output folder exists and holds files (or is not a folder)."""


class EmptyStoreError(ExportError):
    """The store holds no trial to export."""


class StoreNotVerifiedError(ExportError):
    """The store fails ``workcell verify``: exporting it would spread damaged records."""


class NothingSelectedError(ExportError):
    """The store has trials, but none is selected (none is included, or none has frames)."""


class IncompatibleSessionsError(ExportError):
    """The selected sessions cannot share one dataset (frame rate, box pool, parameters)."""


class ReplayMismatchError(ExportError):
    """Restoring the recorded states does not reproduce the recorded poses."""


class UnknownTrialError(ExportError):
    """A trial id names no trial of the store."""
