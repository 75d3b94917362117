"""Attempts as Ray tasks, on a cluster or on Ray started here (``workcell generate --ray``).

The attempts are cut into chunks of :data:`CHUNK` attempts; each chunk is one Ray task that
records its attempts into a shard in its own temporary folder and returns their results and
the shard's bytes (as ``workcell collect --ray`` does, :mod:`workcell.scale.ray_tasks`); the
shards are written here and merged like local ones. The plan goes into Ray's object store
once. Once the caller asks to stop, no further chunk is handed out.
"""

from __future__ import annotations

import tempfile
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from workcell.errors import WorkcellError
from workcell.generate.attempts import AttemptResult, run_attempt
from workcell.generate.errors import GenerateError
from workcell.generate.plan import GenerationPlan
from workcell.scale.ray_cluster import start_ray
from workcell.session.config import SessionConfig

CHUNK = 5
"""Attempts per Ray task: enough to pay for a task's start, few enough to spread."""


@dataclass(frozen=True)
class ChunkResult:
    """What one Ray task hands back."""

    attempts: tuple[AttemptResult, ...]
    shard: bytes
    error: str
    """Why the chunk stopped early ("" when it did not)."""


def _run_chunk(plan: GenerationPlan, config: SessionConfig, attempts: list[int]) -> ChunkResult:
    results: list[AttemptResult] = []
    error = ""
    with tempfile.TemporaryDirectory() as folder:
        shard = Path(folder) / "shard.sqlite"
        try:
            for attempt in attempts:
                result = run_attempt(plan, config, attempt, shard)
                if result is not None:
                    results.append(result)
        except WorkcellError as failure:
            error = str(failure)
        data = shard.read_bytes() if shard.exists() else b""
    return ChunkResult(tuple(results), data, error)


def run_ray(
    address: str,
    plan: GenerationPlan,
    config: SessionConfig,
    attempts: Sequence[int],
    workers: int,
    *,
    shard_dir: Path,
    on_attempt: Callable[[AttemptResult], None],
    should_stop: Callable[[], bool],
) -> list[Path]:
    """Run ``attempts`` as Ray tasks using ``workers`` CPUs at a time (``address``
    ``local``: Ray started here); returns the shards written into ``shard_dir``."""
    import ray  # noqa: PLC0415

    start_ray(address, workers)
    try:
        task = ray.remote(num_cpus=1)(_run_chunk)
        plan_ref = ray.put(plan)
        chunks = [list(attempts[i : i + CHUNK]) for i in range(0, len(attempts), CHUNK)]
        pending: dict[Any, int] = {}
        shards: list[Path] = []
        errors: list[str] = []
        number = 0
        while chunks or pending:
            while chunks and len(pending) < 2 * workers and not should_stop():
                pending[task.remote(plan_ref, config, chunks.pop(0))] = number
                number += 1
            if should_stop():
                chunks.clear()
            if not pending:
                break
            done, _ = ray.wait(list(pending), num_returns=1, timeout=0.5)
            for ref in done:
                index = pending.pop(ref)
                result: ChunkResult = ray.get(ref)
                for attempt in result.attempts:
                    on_attempt(attempt)
                if result.shard:
                    shard = shard_dir / f"shard-{index:04d}.sqlite"
                    shard.write_bytes(result.shard)
                    shards.append(shard)
                if result.error:
                    errors.append(result.error)
        if errors:
            raise GenerateError(f"a Ray task stopped: {errors[0]}")
        return sorted(shards)
    finally:
        ray.shutdown()
