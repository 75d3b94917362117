"""The browser's frame budget (issue 18): how the teleoperation page draws in headless
Chromium on this machine, measured by the page's own frame meter.

Starts ``workcell serve`` on a free localhost port and runs the compiled end-to-end script
``web/tests/e2e/frame_budget.ts`` against it: one practice session per view (desktop at
low quality, desktop, an emulated Meta Quest 3 in immersive-vr with both eyes), each over
``--windows`` report windows of 5 s while the trial runs. Prints each view's frame interval
percentiles (p50, p95, max), frames per second, WebGL draw calls and triangles per frame,
and the frame times as ratios to the first view, measured in the same run.

This machine renders WebGL in software (SwiftShader/llvmpipe, no GPU): the absolute frame
times are far from a headset's, the ratios and the draw calls carry over. Target (issue
18): at most 30 draw calls per eye.

Run: ``.venv/bin/python bench/frames.py [--windows N]`` after ``make web-setup`` (the web
app and its end-to-end scripts are built first if missing), on an otherwise idle machine.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import signal
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request
from collections.abc import Iterator
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
WEB = ROOT / "web"
SCRIPT = WEB / "build" / "e2e" / "tests" / "e2e" / "frame_budget.js"
MAX_DRAWS_PER_EYE = 30


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@contextlib.contextmanager
def serving(folder: Path) -> Iterator[str]:
    """``workcell serve`` recording into a fresh store in ``folder``; its URL."""
    port = free_port()
    env = {**os.environ, "MUJOCO_GL": os.environ.get("MUJOCO_GL", "egl")}
    command = [sys.executable, "-m", "workcell", "serve", "--port", str(port)]
    command += ["--store", str(folder / "bench.sqlite")]
    with (folder / "server.log").open("w") as log:
        server = subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT, env=env)
    url = f"http://127.0.0.1:{port}"
    try:
        for _ in range(300):
            with (
                contextlib.suppress(OSError),
                urllib.request.urlopen(f"{url}/api/defaults", timeout=2) as reply,
            ):
                if reply.status == 200:
                    break
            time.sleep(0.1)
        yield url
    finally:
        server.send_signal(signal.SIGINT)
        server.wait(30)


def build() -> None:
    """The web app and the end-to-end scripts, as they are now."""
    if not (WEB / "dist" / "index.html").exists():
        subprocess.run(["npm", "run", "--silent", "build"], cwd=WEB, check=True)
    subprocess.run(["npm", "run", "--silent", "build:e2e"], cwd=WEB, check=True)


def report(views: list[dict[str, Any]]) -> None:
    print(f"machine: {os.cpu_count()} cores, load average {os.getloadavg()[0]:.2f}")
    print(
        f"{'view':40s} {'fps':>5s} {'p50 ms':>8s} {'p95 ms':>8s} {'max ms':>8s} "
        f"{'draws':>6s} {'triangles':>10s}  p50, p95 vs the first"
    )
    first: dict[str, float] | None = None
    for view in views:
        reports = view["reports"]
        frames = sum(r["frames"] for r in reports)
        p50 = sum(r["frame_ms_p50"] * r["frames"] for r in reports) / frames
        p95 = max(r["frame_ms_p95"] for r in reports)
        longest = max(r["frame_ms_max"] for r in reports)
        draws = max(r["draw_calls"] for r in reports)
        triangles = max(r["triangles"] for r in reports)
        first = first or {"p50": p50, "p95": p95}
        print(
            f"{view['view']:40s} {1000 / p50:5.1f} {p50:8.1f} {p95:8.1f} {longest:8.1f} "
            f"{draws:6d} {triangles:10d}  {p50 / first['p50']:4.2f}x, {p95 / first['p95']:4.2f}x"
        )
        eyes = 2 if any(r["presenting"] for r in reports) else 1
        verdict = "ok" if draws / eyes <= MAX_DRAWS_PER_EYE else "MISSED"
        print(f"{'':40s} draw calls per eye: {draws / eyes:.0f} (target <= 30: {verdict})")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    parser.add_argument("--windows", type=int, default=2, help="5 s report windows per view")
    args = parser.parse_args()
    build()
    with tempfile.TemporaryDirectory() as folder, serving(Path(folder)) as url:
        completed = subprocess.run(
            ["node", str(SCRIPT), url, str(args.windows)],
            cwd=WEB,
            capture_output=True,
            text=True,
            check=False,
            env={**os.environ, "WORKCELL_ARTIFACTS": folder},
        )
    lines = [line for line in completed.stdout.splitlines() if line.startswith("RESULT ")]
    if completed.returncode != 0 or not lines:
        sys.exit(f"frame_budget.js failed:\n{completed.stdout}{completed.stderr}")
    report(json.loads(lines[-1].removeprefix("RESULT ")))


if __name__ == "__main__":
    main()
