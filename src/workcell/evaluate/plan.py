"""What an evaluation runs: which worlds, how many rollouts in each, on which seeds.

Every world's rollouts are the trials ``0 .. N-1`` of a collection session whose seed is
the evaluation's ``--seed``, so rollout ``i`` starts from
:func:`~workcell.task.runner.trial_seed` ``(seed, i)`` in every world and for every
operator: two policies evaluated with one seed meet the same worlds, and D0's rollout ``i``
and D2's draw from the same seed within their own ranges. Split over workers, a world's
rollouts are contiguous runs of those indices (``task.first_trial``), so the seeds do not
depend on the number of workers.
"""

from __future__ import annotations

from dataclasses import dataclass

from workcell.errors import ConfigError
from workcell.tasks.worlds import WORLDS, WorldName

MAX_ROLLOUTS = 100_000
"""The most rollouts per world (``task.trials``'s own limit)."""


@dataclass(frozen=True)
class Share:
    """Rollouts ``first .. end - 1`` of one world, run as one session."""

    world: WorldName
    first: int
    end: int

    @property
    def rollouts(self) -> int:
        return self.end - self.first


@dataclass(frozen=True)
class EvaluationPlan:
    worlds: tuple[WorldName, ...]
    rollouts: int
    """Rollouts per world."""
    seed: int

    def shares(self, world: WorldName, workers: int) -> list[Share]:
        """``world``'s rollouts in up to ``workers`` contiguous runs (none empty)."""
        size, extra = divmod(self.rollouts, workers)
        out, first = [], 0
        for k in range(workers):
            end = first + size + (k < extra)
            if end > first:
                out.append(Share(world, first, end))
            first = end
        return out


def parse_worlds(text: str) -> tuple[WorldName, ...]:
    """``D0,D1,D2`` as world names, in the order given; one clear error otherwise."""
    names = [part.strip() for part in text.split(",")]
    allowed = f"a comma-separated list of {', '.join(WORLDS)} (e.g. D0,D1,D2)"
    unknown = [name for name in names if name not in WORLDS]
    if unknown:
        raise ConfigError([f"--world {text!r}: unknown world {unknown[0]!r}; give {allowed}"])
    if len(set(names)) != len(names):
        repeated = next(name for name in names if names.count(name) > 1)
        raise ConfigError([f"--world {text!r}: {repeated} is named twice; give {allowed}"])
    worlds: tuple[WorldName, ...] = tuple(w for name in names for w in WORLDS if w == name)
    return worlds


def rollout_problems(rollouts: int) -> list[str]:
    if 1 <= rollouts <= MAX_ROLLOUTS:
        return []
    return [f"--rollouts = {rollouts}: must be a whole number from 1 to {MAX_ROLLOUTS} per world"]
