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
- a table's appended columns (text and real columns later schema versions added, see
  :class:`~workcell.record.layout.TableLayout`) are left out of the values above and
  follow at the end, version by version (oldest first), each version's only where the row
  holds one of its columns: the version's marker (``b"\0appended\0"`` for version 3, the
  first to append, ``b"\0appended v<N>\0"`` for a later version N), then its text values
  as above, then its real values as above. A row that holds none of a version's columns
  (every row written before they existed) has the form it had before.

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
"""Marks the start of a row's columns appended by schema version 3 in its canonical form."""
FIRST_APPENDING_VERSION = 3


def appended_marker(version: int) -> bytes:
    """Marks the start of a row's columns appended by schema ``version``."""
    return APPENDED if version == FIRST_APPENDING_VERSION else f"\0appended v{version}\0".encode()


AppendedCounts = Sequence[tuple[int, int, int]]
"""Per schema version that appended columns, oldest first: (version, text columns, real
columns)."""


def _text_bytes(values: Iterable[str | None]) -> bytes:
    out = bytearray()
    for value in values:
        if value is None:
            out += NULL_TEXT
        else:
            encoded = value.encode()
            out += len(encoded).to_bytes(4, "little")
            out += encoded
    return bytes(out)


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
    appended: AppendedCounts = (),
) -> list[str]:
    """Hex sha256 of each row's canonical form (see the module docstring).

    ``text`` per row and ``real`` (n, n_real) with NaN for NULL end with the table's
    appended columns, ``appended`` saying how many of each kind each version added;
    ``integer`` (n, n_integer) with anything where ``integer_null`` is True.
    """
    n = len(text)
    reals = canonical_reals(real).reshape(n, -1) if n else real
    tails: list[bytes] = [b""] * n
    n_text = sum(t for _, t, _ in appended)
    n_real = sum(r for _, _, r in appended)
    if (n_text or n_real) and n:
        tails = _appended_tails(text, reals, appended, n_text, n_real)
        reals = np.ascontiguousarray(reals[:, : reals.shape[1] - n_real])
        if n_text:
            text = [values[: len(values) - n_text] for values in text]
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
        h.update(tails[i])
        out.append(h.hexdigest())
    return out


def _appended_tails(
    text: Sequence[Sequence[str | None]],
    reals: NDArray[np.float64],
    appended: AppendedCounts,
    n_text: int,
    n_real: int,
) -> list[bytes]:
    """Each row's appended columns in canonical form (``b""`` where it holds none)."""
    n = len(text)
    tails = [b""] * n
    text_at, real_at = -n_text, reals.shape[1] - n_real
    for version, texts, count in appended:
        marker = appended_marker(version)
        block = reals[:, real_at : real_at + count]
        held: list[bool] = np.any(~np.isnan(block), axis=1).tolist()
        if texts:
            for i, row in enumerate(text):
                values = row[len(row) + text_at : len(row) + text_at + texts]
                if held[i] or any(v is not None for v in values):
                    tails[i] += marker + _text_bytes(values) + block[i].tobytes()
        else:
            for i in range(n):
                if held[i]:
                    tails[i] += marker + block[i].tobytes()
        text_at += texts
        real_at += count
    return tails


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
