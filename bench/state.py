"""What one State message costs a session (issue 16): building it and writing its JSON.

A live session sends a State after each control period that acted on a new input (72 Hz
from a headset) and at ``state_hz`` otherwise, so its cost is paid up to 100 times a second
per session. Measured in one run on the default world: building the State from the world
(the dynamic bodies' poses, the HUD, the arm targets), and writing its JSON three ways: the
way ``encode`` did until 2026-12-03 (the whole message converted to lists and dicts first,
then ``json.dumps``), the way it did until 2026-12-07 (``json.dumps`` in one pass,
converting only the dataclasses and enums inside) and the way it does now (``orjson`` in
one pass). All write the same text here; the ratios against the first are the savings.

Run: ``.venv/bin/python -m bench.state [--repeats N]``.
"""

from __future__ import annotations

import argparse
import json
import statistics
import time
from collections.abc import Callable

import mujoco

from workcell.protocol.codec import _json_form, encode, to_json_value
from workcell.protocol.messages import State
from workcell.server.scene import PoseReader
from workcell.session.config import SessionConfig
from workcell.sim.world import World
from workcell.task.hud import Hud, HudPhase

STATES_PER_S = 72.0
"""A headset's input rate: the States a driven session sends per second."""


def _per_call_us(call: Callable[[], object], repeats: int, rounds: int = 7) -> float:
    """Median over ``rounds`` of the mean time per call, in microseconds."""
    times = []
    for _ in range(rounds):
        started = time.perf_counter()
        for _ in range(repeats):
            call()
        times.append((time.perf_counter() - started) / repeats * 1e6)
    return statistics.median(times)


def _converted(message: object) -> str:
    return json.dumps(to_json_value(message), separators=(",", ":"), allow_nan=False)


def _one_pass_json(message: object) -> str:
    return json.dumps(message, separators=(",", ":"), allow_nan=False, default=_json_form)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=2000)
    args = parser.parse_args()
    world = World(SessionConfig().world)
    mujoco.mj_forward(world.model, world.data)
    reader = PoseReader(world.model)
    hud = Hud(
        HudPhase.RUNNING,
        "practice",
        0,
        None,
        None,
        None,
        0,
        1,
        0.0,
        39.79,
        0,
        "box_transfer",
        "lifted",
        40,
        "Carry the box from the conveyor to the delivery table.",
    )

    def build() -> State:
        poses = reader.poses(world.data)
        return State(
            seq=1,
            t_sim=12.345678,
            poses=poses,
            hud=hud,
            input_seq=1,
            tcp_targets=(poses[0], poses[1]),
            following=(True, False),
        )

    state = build()
    assert encode(state) == _converted(state) == _one_pass_json(state)
    built = _per_call_us(build, args.repeats)
    before = _per_call_us(lambda: _converted(state), args.repeats)
    one_pass = _per_call_us(lambda: _one_pass_json(state), args.repeats)
    after = _per_call_us(lambda: encode(state), args.repeats)
    print(f"State of {len(state.poses)} bodies, {len(encode(state))} bytes of JSON")
    print(f"build                          {built:7.1f} us")
    print(f"JSON, converted first          {before:7.1f} us   (baseline)")
    print(f"JSON, json one pass            {one_pass:7.1f} us   {before / one_pass:.2f}x faster")
    print(f"JSON, orjson one pass (encode) {after:7.1f} us   {before / after:.2f}x faster")
    saved = (one_pass - after) * 1e-6 * STATES_PER_S
    print(f"at {STATES_PER_S:g} States/s, orjson against json one pass: {saved:.4f} core saved")


if __name__ == "__main__":
    main()
