"""Row ids: random 32-hex-digit strings, unique across stores so stores can be merged."""

from __future__ import annotations

import uuid


def new_id() -> str:
    """A fresh id: the hex digits of a random (version 4) UUID."""
    return uuid.uuid4().hex
