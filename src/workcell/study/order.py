"""Counterbalanced orders of a study's conditions.

``latin_square``: the balanced Latin square (Williams design). Row ``r`` of ``n``
conditions is ``r, r+1, r-1, r+2, r-2, ...`` (mod ``n``): every condition comes first equally
often and, for an even ``n``, directly follows every other condition equally often; for an
odd ``n`` the rows are followed by their reverses (``2n`` rows), which balances that too.
Participant ``k`` (1-based) takes row ``(k - 1) mod rows``. ``fixed``: everyone runs the
conditions as the file lists them. ``shuffled``: each participant's own random order, from
the study seed.
"""

from __future__ import annotations

from typing import Literal

import numpy as np

Order = Literal["latin_square", "fixed", "shuffled"]


def balanced_latin_square(n: int) -> list[list[int]]:
    """The rows of the balanced Latin square of ``n`` conditions (``2n`` rows when ``n`` is
    odd and greater than 1)."""
    first = [0]
    for step in range(1, n):
        first.append((step + 1) // 2 if step % 2 else n - step // 2)
    rows = [[(c + r) % n for c in first] for r in range(n)]
    if n % 2 and n > 1:
        rows += [list(reversed(row)) for row in rows]
    return rows


def condition_order(order: Order, conditions: int, participant: int, seed: int) -> list[int]:
    """The condition indices participant number ``participant`` (from 1) runs, in order."""
    if order == "fixed":
        return list(range(conditions))
    if order == "shuffled":
        rng = np.random.default_rng([seed, participant])
        return [int(i) for i in rng.permutation(conditions)]
    rows = balanced_latin_square(conditions)
    return rows[(participant - 1) % len(rows)]
