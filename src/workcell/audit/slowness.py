"""Slow trials: successes far slower than the audited set's typical success.

Definition (version :data:`SLOWNESS_VERSION`): ``slow`` is raised on a successful trial
whose recomputed ``completion_time_s`` is more than ``factor`` times the median
completion time of its reference group: the valid successes (dispositions of the other
rules, reviewers' decisions included) of the same task — the same ``task.kind``, mode and
number of required boxes — in the audited set, when that group holds at least
``min_reference`` trials. A trial counts in its own reference. A trial a person took over
from an autonomous driver (a ``take_over`` event) is neither flagged nor counted in a
reference: its time is the driver's stall plus the correction, not one operator's pace,
and what is learned from it is the corrected stretch alone (``workcell train
--correction-weight``), so an audited export keeps it. The reference is the audited population, not
an absolute pace: a set whose typical success is slow flags none, and a policy evaluated
in the same store as its demonstrations is measured against them.

By default ``slow`` marks a trial without excluding it (the paper's dispositions count it
as valid); ``workcell export --audited`` leaves marked trials out, since a slow
demonstration is one an imitation learner copies: its pauses and detours look, from the
current state, like the right action.

Version 2 lowered the default ``factor`` from 2 to 1.5: in ``bench/learn.py``'s filtering
experiment the keep of version 1 held 2 low-skill successes at 1.7x the median (4 % of its
episodes), and an ACT policy trained on it never released the box, while the same keep
without them succeeded (bench/README.md). A study whose people are expected to vary more
can raise it (``slowness.factor``).

Version 3 made the reference group the same ``task.kind`` as well (with four tasks in one
store, a sort trial, about three times as long as a box transfer, was measured against box
transfer's median) and left corrected trials out (the loop of README's "Correcting a
policy" exported with ``--audited`` lost the rollouts whose correction took longest).
Stores of one task without take-overs are flagged as under version 2.
"""

from __future__ import annotations

from dataclasses import dataclass

from workcell.audit.flags import SLOW, Flag
from workcell.errors import ConfigError
from workcell.settings import declared_problems, setting

SLOWNESS_VERSION = "3"
"""Bumped whenever the definition above changes meaning."""


@dataclass(frozen=True)
class SlownessParams:
    """The ``slow`` detector's parameters (see the definition above)."""

    factor: float = setting(
        1.5, "how many times its group's median a success may take before it is slow",
        unit="1", low=1.0, high=100.0,
    )  # fmt: skip
    min_reference: int = setting(
        5, "the fewest valid successes a task's reference group needs",
        unit="trials", low=1, high=1_000_000,
    )  # fmt: skip
    disqualifying: bool = setting(False, "whether slow excludes a success as low quality")

    def __post_init__(self) -> None:
        problems = declared_problems(self, "slowness")
        if problems:
            raise ConfigError(problems)


def detect_slow(
    time: float | None, median: float, count: int, params: SlownessParams
) -> Flag | None:
    """``slow`` for a success that took ``time`` s against the ``median`` of its reference
    group of ``count`` valid successes; None when it is not slow."""
    if time is None or not time > params.factor * median:
        return None
    detail = (
        f"completed in {time:.1f} s, {time / median:.1f}x the median {median:.1f} s of "
        f"{count} valid successes of this task (limit {params.factor:g}x)"
    )
    return Flag(SLOW, detail, params.disqualifying)
