"""Content checksums: sha256 over a canonical serialization of rows, and of trees of rows.

A row's canonical form (version 1) is, in the table's grouped column order (text, then
real, then integer columns, each group in table order):

- the prefix ``b"workcell/<table>/v1\\0"``, so a row cannot pass for another table's;
- each text value as its UTF-8 length (uint32, little-endian) and bytes, NULL as
  ``ff ff ff ff``;
- each real value as IEEE-754 float64, little-endian; NULL and NaN (which SQLite stores as
  NULL) as the single quiet NaN ``7ff8000000000000``; -0.0 as +0.0 (SQLite keeps no sign
  on zero);
- each integer value as int64, little-endian (NULL as 0), then one byte per integer
  column: 1 where the value is NULL, 0 otherwise;
- a table's appended columns (real columns a later schema version added, see
  :class:`~workcell.record.schema.TableLayout`) are left out of the real values above and
  follow at the end, only where the row holds one of them: the marker
  ``b"\0appended\0"``, then their values as reals. A row that holds none of them (every
  row written before they existed) has the form it had before.

This is exact for every value SQLite stores, so a checksum recomputed from a row read back
equals the one computed before the write. Aggregates hash the hex checksums of children in
a fixed order, so a trial's aggregate changes when any of its frames or events does.
"""

from __future__ import annotations

import hashlib
from collections.abc import Iterable, Sequence

import numpy as np
from numpy.typing import NDArray

NULL_TEXT = b"\xff\xff\xff\xff"
APPENDED = b"\0appended\0"
"""Marks the start of a row's appended columns in its canonical form."""


def canonical_reals(real: NDArray[np.float64]) -> NDArray[np.float64]:
    """A little-endian copy with every NaN the canonical NaN and -0.0 as +0.0."""
    out = np.asarray(real, dtype="<f8") + 0.0
    out[np.isnan(out)] = np.nan
    return out


def row_checksums(
    table: str,
    text: Sequence[Sequence[str | None]],
    real: NDArray[np.float64],
    integer: NDArray[np.int64],
    integer_null: NDArray[np.bool_],
    *,
    appended: int = 0,
) -> list[str]:
    """Hex sha256 of each row's canonical form (see the module docstring).

    ``real`` is (n, n_real) with NaN for NULL, its last ``appended`` columns the table's
    appended ones; ``integer`` (n, n_integer) with anything where ``integer_null`` is True.
    """
    n = len(text)
    reals = canonical_reals(real).reshape(n, -1) if n else real
    tails: list[bytes | None] = [None] * n
    if appended and n:
        tail = reals[:, reals.shape[1] - appended :]
        held: NDArray[np.bool_] = np.any(~np.isnan(tail), axis=1)
        present = [bool(v) for v in held]
        tails = [APPENDED + tail[i].tobytes() if present[i] else None for i in range(n)]
        reals = np.ascontiguousarray(reals[:, : reals.shape[1] - appended])
    ints = np.where(integer_null, 0, integer).astype("<i8").reshape(n, -1) if n else integer
    nulls = np.asarray(integer_null, dtype=np.uint8).reshape(n, -1) if n else integer_null
    real_bytes, int_bytes, null_bytes = reals.tobytes(), ints.tobytes(), nulls.tobytes()
    real_stride = 8 * (reals.shape[1] if n else 0)
    int_stride = 8 * (ints.shape[1] if n else 0)
    null_stride = nulls.shape[1] if n else 0
    base = hashlib.sha256(f"workcell/{table}/v1\0".encode())
    out: list[str] = []
    for i, values in enumerate(text):
        h = base.copy()
        for value in values:
            if value is None:
                h.update(NULL_TEXT)
            else:
                encoded = value.encode()
                h.update(len(encoded).to_bytes(4, "little"))
                h.update(encoded)
        h.update(real_bytes[i * real_stride : (i + 1) * real_stride])
        h.update(int_bytes[i * int_stride : (i + 1) * int_stride])
        h.update(null_bytes[i * null_stride : (i + 1) * null_stride])
        appended_bytes = tails[i]
        if appended_bytes is not None:
            h.update(appended_bytes)
        out.append(h.hexdigest())
    return out


def aggregate_checksum(kind: str, groups: Iterable[Iterable[str]]) -> str:
    """Hex sha256 over groups of child checksums (each group in its fixed order).

    A trial's aggregate is over (its frames by frame_index, its events by seq); a session's
    over (its trials by trial_index, its session-level events by seq).
    """
    h = hashlib.sha256(f"workcell/{kind}/v1\0".encode())
    for group in groups:
        h.update(b"[")
        for checksum in group:
            h.update(checksum.encode())
            h.update(b"\n")
        h.update(b"]")
    return h.hexdigest()
