"""How a collection is split over workers: each worker is its own session and shard."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np


@dataclass(frozen=True)
class WorkerPlan:
    worker: int
    seed: int
    trials: int | None
    """Trials for this worker; None when the mode decides (practice, challenge) or when
    collection runs until stopped."""
    shard: Path


def worker_seed(session_seed: int, worker: int, workers: int) -> int:
    """Independent, reproducible session seeds for the workers of one run."""
    child = np.random.SeedSequence(session_seed).spawn(workers)[worker]
    return int(child.generate_state(1, np.uint64)[0] >> np.uint64(1))


def plan_workers(workers: int, seed: int, trials: int | None, shard_dir: Path) -> list[WorkerPlan]:
    """Split ``trials`` (None: each worker runs its mode to the end) over ``workers``."""
    plans = []
    for k in range(workers):
        share = None if trials is None else trials // workers + (k < trials % workers)
        plans.append(
            WorkerPlan(k, worker_seed(seed, k, workers), share, shard_dir / f"shard-{k:03d}.sqlite")
        )
    return [p for p in plans if p.trials is None or p.trials > 0]
