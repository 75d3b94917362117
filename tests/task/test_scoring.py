"""Score = box_score x boxes delivered + ceil(remaining seconds), worked out by hand."""

from __future__ import annotations

import pytest

from workcell.task.scoring import trial_score


@pytest.mark.parametrize(
    ("box_score", "boxes", "limit", "elapsed", "expected"),
    [
        (100, 1, 120.0, 76.06, 144),  # 100 + ceil(43.94) = 100 + 44
        (100, 1, 120.0, 100.0, 120),  # whole seconds left: 100 + 20
        (100, 3, 90.0, 89.999, 301),  # a thousandth of a second left still counts: 300 + 1
        (100, 2, 100.0, 100.0, 200),  # timeout with 2 of 3 boxes: 200 + 0
        (100, 0, 120.0, 120.0, 0),  # timeout with nothing delivered
        (100, 2, 100.0, 100.00000000001, 200),  # clock noise past the limit is no negative time
        (100, 1, 120.0, 100.00000000001, 120),  # clock noise does not gain a second: 100 + 20
        (50, 2, 60.0, 30.5, 130),  # other box score: 100 + ceil(29.5) = 100 + 30
    ],
)
def test_score_examples(
    box_score: int, boxes: int, limit: float, elapsed: float, expected: int
) -> None:
    assert trial_score(box_score, boxes, limit, elapsed) == expected
