"""A reviewer's decision on a trial, as the row the store keeps (raw rows are never
rewritten: an exclusion or an inclusion is one more row, saying who, when and why)."""

from __future__ import annotations

import time
from typing import Any

from workcell.record.columns import ANNOTATION_KINDS
from workcell.record.errors import RecordError
from workcell.record.ids import new_id


def annotation_row(trial_id: str, kind: str, reason: str, by: str) -> dict[str, Any]:
    """The annotations row of a decision made now, with a new id; a kind other than
    :data:`ANNOTATION_KINDS`, or an empty reason or reviewer, is a RecordError."""
    if kind not in ANNOTATION_KINDS:
        raise RecordError(f"annotation kind {kind!r}: must be one of {ANNOTATION_KINDS}")
    for name, value in (("reason", reason), ("by", by)):
        if not value:
            raise RecordError(f"annotation {name}: must be a non-empty text")
    return {
        "annotation_id": new_id(),
        "trial_id": trial_id,
        "kind": kind,
        "reason": reason,
        "by": by,
        "at_wall": time.time(),
    }
