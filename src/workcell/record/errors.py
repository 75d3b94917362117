"""Errors of the record: each message names the store or value and says what to do."""

from __future__ import annotations

from workcell.errors import WorkcellError


class StoreError(WorkcellError):
    """A store cannot be opened or used as asked (missing, not a store, newer, locked)."""


class StorageError(StoreError):
    """A write to the store failed (disk full, I/O error); recording has stopped.

    The failed transaction was rolled back: everything committed before it is intact.
    """


class RecordError(WorkcellError):
    """A value handed to the store is malformed (unknown column, wrong type, bad outcome)."""


class ExportError(WorkcellError):
    """An export cannot be written as asked (output not empty, format not available)."""
