"""The four-layer record: sessions, trials, events and frames in one SQLite store per file,
crash-safe, verifiable, and exported to CSV with the interchange contract's columns."""

from workcell.record.entries import (
    AnnotationRecord,
    EventRecord,
    SessionInfo,
    SessionRecord,
    StoreCounts,
    StoredMetrics,
    TrialEnd,
    TrialRecord,
    TrialStart,
)
from workcell.record.errors import ExportError, RecordError, StorageError, StoreError
from workcell.record.store import Store

__all__ = [
    "AnnotationRecord",
    "EventRecord",
    "ExportError",
    "RecordError",
    "SessionInfo",
    "SessionRecord",
    "StorageError",
    "Store",
    "StoreCounts",
    "StoreError",
    "StoredMetrics",
    "TrialEnd",
    "TrialRecord",
    "TrialStart",
]
