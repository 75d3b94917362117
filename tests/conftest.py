"""Fixtures shared by the simulation and control tests: real MuJoCo, no mocks."""

from __future__ import annotations

import os

# Offscreen rendering through EGL (Mesa) even when pytest runs outside `make test`; MuJoCo
# reads this on its first import, which is below.
os.environ.setdefault("MUJOCO_GL", "egl")

from collections.abc import Callable
from typing import Any

import mujoco
import numpy as np
import pytest

from workcell.control.command import Command
from workcell.control.simulation import Simulation
from workcell.sim.arena import pickup_range_x
from workcell.sim.boxes import BoxSlot, BoxState
from workcell.sim.config import BoxConfig, FeederConfig, WorldConfig

Quat = tuple[float, float, float, float]
SettledBoxSim = Callable[..., Simulation]

LEFT_TCP_ROTATION = ((1.0, 0.0, 0.0), (0.0, 0.0, -1.0), (0.0, 1.0, 0.0))
"""Left TCP in the base frame: x forward, approach (z) pointing right, toward the box."""
RIGHT_TCP_ROTATION = ((1.0, 0.0, 0.0), (0.0, 0.0, 1.0), (0.0, -1.0, 0.0))
"""Right TCP in the base frame: x forward, approach (z) pointing left, toward the box."""

REST_TOLERANCE = 0.005
"""How far (m) outside the pickup range a resting box's centre may be."""


def matrix_to_quat(rotation: tuple[tuple[float, float, float], ...]) -> Quat:
    """Unit quaternion (w, x, y, z) of a 3x3 rotation matrix."""
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, np.asarray(rotation, dtype=float).ravel())
    w, x, y, z = (float(v) for v in quat)
    return (w, x, y, z)


def _rank(item: pytest.Item) -> int:
    """0: drives a browser, 1: slow, 2: the rest (by its markers)."""
    if item.get_closest_marker("browser") is not None:
        return 0
    return 1 if item.get_closest_marker("slow") is not None else 2


BROWSER_FILES = "tests/web/"
"""Where every test that drives a browser lives (and only such tests): the browser tests
share one lock, so ``make test`` gives all these files to one worker."""


def _file(nodeid: str) -> str:
    return nodeid.split("::", maxsplit=1)[0]


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """The files with the longest tests first, each file's tests together and in their
    order. ``make test`` hands whole files to its two workers in this order (``--dist
    loadfile``, with the browser files as one unit: :func:`pytest_xdist_make_scheduler`):
    the browser tests (which run one at a time: they share one lock) start at once on one
    worker, which takes them all, so the other never waits on the lock; the files with
    slow tests come next and the many short files fill in at the end, so that neither
    worker is left alone with a long file while the other idles."""
    file_rank: dict[str, int] = {}
    for item in items:
        file = _file(item.nodeid)
        rank = _rank(item)
        if (rank == 0) != file.startswith(BROWSER_FILES):
            raise pytest.UsageError(
                f"{item.nodeid}: a test that drives a browser (marked 'browser') belongs in "
                f"{BROWSER_FILES}, and every test there is marked 'browser' "
                "(make test runs those files on one worker)"
            )
        file_rank[file] = min(file_rank.get(file, 2), rank)
    items.sort(key=lambda item: file_rank[_file(item.nodeid)])


def pytest_xdist_make_scheduler(config: pytest.Config, log: Any) -> Any:
    """With ``--dist loadfile``: whole files to each worker as usual, except that all the
    browser files (:data:`BROWSER_FILES`) go to one worker together."""
    if config.getvalue("dist") != "loadfile":
        return None
    from xdist.scheduler import LoadScopeScheduling  # type: ignore[import-untyped]

    class BrowserFilesTogether(LoadScopeScheduling):  # type: ignore[misc]
        def _split_scope(self, nodeid: str) -> str:
            file = _file(nodeid)
            return BROWSER_FILES if file.startswith(BROWSER_FILES) else file

    return BrowserFilesTogether(config, log)


@pytest.fixture(scope="session")
def tcp_quats() -> dict[str, Quat]:
    """Side-grasp TCP orientations ("l", "r") as base-frame wxyz quaternions."""
    return {"l": matrix_to_quat(LEFT_TCP_ROTATION), "r": matrix_to_quat(RIGHT_TCP_ROTATION)}


def at_pickup(config: WorldConfig, x: float) -> bool:
    """True when a box centre at ``x`` lies on the pickup plate."""
    low, high = pickup_range_x(config)
    return low - REST_TOLERANCE <= x <= high + REST_TOLERANCE


def run_until_box_rests(sim: Simulation, slot: BoxSlot, hold_s: float = 1.0) -> None:
    """Step idle commands until ``slot`` has rested on the pickup plate for ``hold_s`` s."""
    config = sim.config
    travel = config.conveyor.length / config.conveyor.speed
    deadline = sim.time + config.feeder.first_release_s + travel + 10.0
    since: float | None = None
    world = sim.world
    while sim.time < deadline:
        sim.step(Command())
        x = world.boxes.position(world.data, slot)[0]
        still = world.boxes.speed(world.data, slot) < 0.005
        if slot.state is BoxState.ACTIVE and at_pickup(config, x) and still:
            since = sim.time if since is None else since
            if sim.time - since >= hold_s:
                return
        else:
            since = None
    pytest.fail(
        f"box {slot.index} did not come to rest on the pickup plate "
        f"(x in {pickup_range_x(config)}) by t = {deadline:.1f} s"
    )


@pytest.fixture(scope="session")
def settled_box_sim() -> SettledBoxSim:
    """Factory: a fresh Simulation whose first box rests against the end stop.

    Call it with a :class:`WorldConfig` (default: assisted grasp, 2 kg box, a pool of one
    box so no second box arrives while the test works).
    """

    def make(config: WorldConfig | None = None) -> Simulation:
        if config is None:
            config = WorldConfig(
                grasp="assisted", box=BoxConfig(mass=2.0), feeder=FeederConfig(pool_size=1)
            )
        sim = Simulation(config)
        run_until_box_rests(sim, sim.world.boxes.slots[0])
        return sim

    return make
