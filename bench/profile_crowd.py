"""Where a live session's time goes (issue 38): ``bench/crowd.py``'s load, profiled.

Runs one ``bench/crowd.py`` measurement per N with the server started through
``bench/session_profile.py`` (cProfile, CPU time of each thread: a paced loop's sleeping
does not count), then prints, summed over the sessions, the share of the session
processes' simulation threads in each part of a control period, and the server's threads.

The parts (cumulative CPU time of the functions named, so a part includes what it calls;
"rest" is what none of them holds: the runner's own bookkeeping, the task's judge, the
pacer):

- physics: MuJoCo's ``mj_step``;
- IK: ``BimanualIK.solve`` (mink's problem and the QP);
- controller: ``RobotController.apply`` less the IK solve (base motion, the IK's
  integration, the arms' obstacle proxy, grippers);
- world checks: ``World.step`` less physics and the recorder's sampling (grasp, feeder,
  events);
- operator: ``TeleopOperator.act`` (the clutch, the sticks, the head);
- State building: ``StateBuilder.build``; encoding: ``codec.encode`` (JSON);
- pipe: ``Connection.send`` (pickling and writing to the server);
- the server's requests: ``_Obedience.idle``, reading and applying the operator's inputs
  (and any other request) while the loop waits for its next period;
- recorder: ``Recorder.sample``, ``_on_event``, ``_judged``, ``check``, ``trial_settled``
  (the frames captured and handed to the writer process).

cProfile adds a cost per Python call, so parts made of many small Python calls look
larger than they are against one long C call (``mj_step``): the shares rank the parts;
the cost itself is ``bench/crowd.py``'s, without the profiler.

Run: ``.venv/bin/python -m bench.profile_crowd [--sessions 1,8] [--seconds 30]``.
"""

from __future__ import annotations

import argparse
import pstats
import tempfile
from collections.abc import Iterable
from pathlib import Path

from bench import crowd
from bench.session_profile import LAUNCH, PROFILE_DIR

Key = tuple[str, int, str]

SESSION_PARTS: dict[str, list[tuple[str, str]]] = {
    "physics (mj_step)": [("~", "mj_step>")],
    "IK solve": [("control/ik.py", "solve")],
    "controller (less IK solve)": [("control/controller.py", "apply")],
    "world checks (less physics, recorder)": [("sim/world.py", "step")],
    "operator (teleop act)": [("teleop/operator.py", "act")],
    "State building": [("server/state_message.py", "build")],
    "encoding (JSON)": [("protocol/codec.py", "encode")],
    "pipe (Connection.send)": [("multiprocessing/connection.py", "send")],
    "server's requests (read while waiting)": [("server/session_child.py", "idle")],
    "recorder (capture, hand-over)": [
        ("recording/recorder.py", name)
        for name in ("sample", "_on_event", "_judged", "check", "trial_settled")
    ],
}
SUBTRACT: dict[str, list[str]] = {
    "controller (less IK solve)": ["IK solve"],
    "world checks (less physics, recorder)": ["physics (mj_step)", "recorder sample"],
}
SERVER_PARTS: dict[str, list[tuple[str, str]]] = {
    "websocket sends (Client.run_sender)": [("server/client.py", "run_sender")],
    "receive + decode input": [("protocol/codec.py", "decode_client")],
    "conductor.input (to the pipe)": [("server/conductor.py", "input")],
    "broadcast_state": [("server/conductor.py", "broadcast_state")],
    "pipe receive (ChildLink.data_received)": [("server/child_link.py", "data_received")],
    "pipe send (ChildLink.send)": [("server/child_link.py", "send")],
}


def _stats(files: Iterable[Path]) -> pstats.Stats | None:
    paths = [str(f) for f in files]
    return pstats.Stats(*paths) if paths else None


def _cumulative(stats: pstats.Stats, matches: list[tuple[str, str]]) -> float:
    table = stats.stats  # type: ignore[attr-defined]
    total = 0.0
    for (filename, _, name), (_, _, _, cumulative, _) in table.items():
        if any(filename.endswith(f) and name.endswith(n) for f, n in matches):
            total += cumulative
    return total


def _total(stats: pstats.Stats) -> float:
    return float(stats.total_tt)  # type: ignore[attr-defined]


def session_table(stats: pstats.Stats) -> dict[str, float]:
    """CPU seconds of each part (see the module's docstring), "rest" and "total"."""
    parts = {name: _cumulative(stats, matches) for name, matches in SESSION_PARTS.items()}
    parts["recorder sample"] = _cumulative(stats, [("recording/recorder.py", "sample")])
    shown = {}
    for name, seconds in parts.items():
        if name == "recorder sample":
            continue
        shown[name] = seconds - sum(parts[other] for other in SUBTRACT.get(name, []))
    total = _total(stats)
    shown["rest (runner, judge, pacer, ...)"] = total - sum(shown.values())
    shown["total"] = total
    return shown


def print_table(title: str, parts: dict[str, float]) -> None:
    total = parts["total"]
    print(f"  {title}: {total:.2f} CPU s")
    for name, seconds in parts.items():
        if name != "total":
            print(f"    {name:42s} {seconds:7.2f} s  {100 * seconds / total:5.1f} %")


def server_table(folder: Path) -> None:
    for thread in ("loop",):
        stats = _stats(folder.glob(f"server-*-{thread}-*.prof"))
        if stats is None:
            continue
        total = _total(stats)
        print(f"  server {thread} threads: {total:.2f} CPU s")
        for name, matches in SERVER_PARTS.items():
            seconds = _cumulative(stats, matches)
            if seconds > 0.005 * total:
                print(f"    {name:42s} {seconds:7.2f} s  {100 * seconds / total:5.1f} %")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sessions", default="1,8", help="values of N")
    parser.add_argument("--seconds", type=float, default=30.0, help="measured window per N")
    parser.add_argument("--keep", type=Path, help="keep the .prof files in this folder")
    parser.add_argument("--top", type=int, default=0, help="also print the top functions")
    args = parser.parse_args()
    for n in (int(v) for v in args.sessions.split(",")):
        with tempfile.TemporaryDirectory() as tmp:
            folder = args.keep / f"n{n}" if args.keep else Path(tmp)
            folder.mkdir(parents=True, exist_ok=True)
            figures = crowd.measure(
                n, args.seconds, {}, "expert", None, launch=LAUNCH, env={PROFILE_DIR: str(folder)}
            )
            print(
                f"N = {n}: held {figures.held}/{n}, min RTF {figures.min_rtf:.3f}, "
                f"p50/p99 {figures.p50_ms:.1f}/{figures.p99_ms:.1f} ms, "
                f"cores {figures.cores:.2f} (profiled), load {figures.load:.1f}"
            )
            stats = _stats(folder.glob("session-*-sim-*.prof"))
            if stats is None:
                print("  no session profile written")
                continue
            print_table(f"session simulation threads ({n})", session_table(stats))
            server_table(folder)
            if args.top:
                stats.sort_stats("tottime").print_stats(args.top)


if __name__ == "__main__":
    main()
