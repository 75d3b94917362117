"""How fast this host is right now: a fixed piece of the workcell's own work, timed in CPU
time on one core, so runs of a benchmark at different hours can be compared.

The same 2-core machine has run the same code a third faster at one hour than at another
(``bench/README.md``, issue 38's runs), more than most changes measured with it; a figure
taken beside a benchmark's says which kind of hour it ran in. Two numbers, because they can
drift apart: MuJoCo's physics of the factory (C) and a loop of plain Python (the
interpreter, where a live session spends most of its time).

    .venv/bin/python -m bench.host_speed
"""

from __future__ import annotations

import time

import mujoco

from workcell.sim.config import WorldConfig
from workcell.sim.scene import build_world_model

PHYSICS_STEPS = 2000
PYTHON_ROUNDS = 200_000


def physics_ms(steps: int = PHYSICS_STEPS, repeats: int = 3) -> float:
    """CPU milliseconds ``steps`` physics steps of the bare factory take (best of
    ``repeats``: the least disturbed)."""
    model = build_world_model(WorldConfig(), None)
    best = float("inf")
    for _ in range(repeats):
        data = mujoco.MjData(model)
        began = time.thread_time()
        for _ in range(steps):
            mujoco.mj_step(model, data)
        best = min(best, time.thread_time() - began)
    return 1000 * best


def python_ms(rounds: int = PYTHON_ROUNDS, repeats: int = 3) -> float:
    """CPU milliseconds of a fixed loop of small-object Python (tuples, floats, a dict)."""
    best = float("inf")
    for _ in range(repeats):
        began = time.thread_time()
        seen: dict[int, float] = {}
        pose: tuple[float, ...] = (0.1, 0.2, 0.3)
        for i in range(rounds):
            pose = tuple(0.5 * p + 0.25 for p in pose)
            seen[i & 1023] = pose[0] + pose[1] * pose[2]
        best = min(best, time.thread_time() - began)
    return 1000 * best


def host_speed_line() -> str:
    """One line naming this hour's speed (lower is faster)."""
    return (
        f"host speed now: {PHYSICS_STEPS} physics steps {physics_ms():.0f} ms, "
        f"{PYTHON_ROUNDS} Python rounds {python_ms():.0f} ms of one core's CPU (lower: faster)"
    )


if __name__ == "__main__":
    print(host_speed_line())
