"""The web client end to end: the real server (``python -m workcell serve``) on a free port,
Debian's chromium driven by playwright-core from the TypeScript scripts in
``web/tests/e2e/`` (compiled once per run with ``npm run build:e2e`` into
``web/build/e2e/``, then run with node), and an IWER-emulated Meta Quest 3. Each script
prints ``RESULT {json}``; these tests then read the store the server recorded into.

Needs node, ``/usr/bin/chromium`` (``make browser-setup``) and the built client with its
node modules (``make web-setup``). Without them the tests skip, unless
``WORKCELL_BROWSER_TESTS=require`` (CI), where they fail. Browser tests take a lock so
that only one runs at a time (each runs a simulation server and a software-rendered
browser; two at once on two cores would starve both). Screenshots and logs are kept
under ``web/test-artifacts/`` (or ``$WORKCELL_ARTIFACTS``); each test prints its folder.
"""

from __future__ import annotations

import contextlib
import fcntl
import hashlib
import json
import math
import os
import shutil
import signal
import socket
import sqlite3
import subprocess
import sys
import tempfile
import time
import urllib.request
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

from workcell.study.config import load_study
from workcell.study.invites import invites_path, load_or_create
from workcell.study.plan import participant_plan

REPO = Path(__file__).resolve().parents[2]
WEB = REPO / "web"
E2E = WEB / "build" / "e2e" / "tests" / "e2e"
"""Where ``npm run build:e2e`` puts the compiled scripts of ``web/tests/e2e/``."""
CHROMIUM = Path(os.environ.get("WORKCELL_CHROMIUM", "/usr/bin/chromium"))
REQUIRED = os.environ.get("WORKCELL_BROWSER_TESTS") == "require"
SCRIPT_TIMEOUT_S = 900.0
"""Only for a script that hangs: each fails by itself when the page stops changing (its waits
are on conditions, a delivery ends with its trial, whose limit is simulated time), however
slowly a busy machine runs it."""
SERVER_START_TIMEOUT_S = 90.0

pytestmark = [pytest.mark.slow, pytest.mark.browser]


def _missing() -> str | None:
    """Why the browser tests cannot run here, or None."""
    if shutil.which("node") is None:
        return "node is not installed"
    if not CHROMIUM.exists():
        return f"{CHROMIUM} is missing (make browser-setup)"
    if not (WEB / "node_modules" / "playwright-core").is_dir():
        return "web/node_modules is missing (make web-setup)"
    if not (WEB / "dist" / "index.html").is_file():
        return "web/dist is not built (make web-setup)"
    return None


@pytest.fixture(scope="module", autouse=True)
def browser_available() -> None:
    reason = _missing()
    if reason is not None:
        if REQUIRED:
            pytest.fail(f"browser tests required (WORKCELL_BROWSER_TESTS=require): {reason}")
        pytest.skip(reason)


@contextlib.contextmanager
def _locked(name: str) -> Iterator[None]:
    path = Path(tempfile.gettempdir()) / name
    with path.open("w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)


@pytest.fixture
def one_browser_at_a_time() -> Iterator[None]:
    with _locked("workcell-browser-tests.lock"):
        yield


@pytest.fixture(scope="module", autouse=True)
def scripts_compiled(browser_available: None) -> None:
    """The end-to-end scripts compiled from their TypeScript (strict) as they are now."""
    with _locked("workcell-e2e-build.lock"):
        completed = subprocess.run(
            ["npm", "run", "--silent", "build:e2e"],
            cwd=WEB,
            capture_output=True,
            text=True,
            timeout=300,
            check=False,
        )
    assert completed.returncode == 0, (
        f"npm run build:e2e failed:\n{completed.stdout}{completed.stderr}"
    )


@dataclass
class Server:
    url: str
    store: Path
    log: Path


def _free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return int(sock.getsockname()[1])


@contextlib.contextmanager
def serving(tmp_path: Path, *extra: str, token: str | None = None) -> Iterator[Server]:
    """``python -m workcell serve EXTRA...`` recording into a fresh store, stopped with
    SIGINT (``token``: the one it needs, to see that it answers)."""
    port = _free_port()
    store = tmp_path / "store.sqlite"
    log = tmp_path / "server.log"
    env = {**os.environ, "MUJOCO_GL": os.environ.get("MUJOCO_GL", "egl")}
    command = [
        sys.executable,
        "-m",
        "workcell",
        "serve",
        "--port",
        str(port),
        "--store",
        str(store),
        *extra,
    ]
    with log.open("w") as out:
        process = subprocess.Popen(command, stdout=out, stderr=subprocess.STDOUT, env=env)
    url = f"http://127.0.0.1:{port}"
    try:
        deadline = time.monotonic() + SERVER_START_TIMEOUT_S
        while True:
            if process.poll() is not None:
                pytest.fail(f"workcell serve exited with {process.returncode}:\n{log.read_text()}")
            with (
                contextlib.suppress(OSError),
                urllib.request.urlopen(
                    f"{url}/api/defaults" + (f"?token={token}" if token else ""), timeout=2
                ) as reply,
            ):
                if reply.status == 200:
                    break
            if time.monotonic() > deadline:
                pytest.fail(f"workcell serve did not answer in time:\n{log.read_text()}")
            time.sleep(0.2)
        yield Server(url=url, store=store, log=log)
    finally:
        if process.poll() is None:
            process.send_signal(signal.SIGINT)
            try:
                process.wait(timeout=20)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()


@pytest.fixture
def server(tmp_path: Path, one_browser_at_a_time: None) -> Iterator[Server]:
    with serving(tmp_path) as running:
        yield running


def _artifacts(name: str) -> Path:
    root = Path(os.environ.get("WORKCELL_ARTIFACTS", WEB / "test-artifacts"))
    return root / name


def run_script(name: str, server: Server, *extra: str) -> dict[str, Any]:
    """Run the compiled ``web/tests/e2e/<name>.ts`` against ``server`` (more arguments: ``extra``);
    its RESULT line as a dict."""
    artifacts = _artifacts(name)
    if artifacts.exists():
        shutil.rmtree(artifacts)
    env = {**os.environ, "WORKCELL_ARTIFACTS": str(artifacts.parent)}
    started = time.monotonic()
    completed = subprocess.run(
        ["node", str(E2E / f"{name}.js"), server.url, *extra],
        capture_output=True,
        text=True,
        timeout=SCRIPT_TIMEOUT_S,
        env=env,
        cwd=WEB,
        check=False,
    )
    took = time.monotonic() - started
    output = completed.stdout + completed.stderr
    print(f"{name}: {took:.1f} s, artifacts in {artifacts}\n{output}")
    assert completed.returncode == 0, (
        f"{name}.ts failed (exit {completed.returncode}); artifacts in {artifacts}\n"
        f"{output}\n--- server log ---\n{server.log.read_text()[-4000:]}"
    )
    lines = [line for line in completed.stdout.splitlines() if line.startswith("RESULT ")]
    assert lines, f"{name}.ts printed no RESULT line\n{output}"
    result: dict[str, Any] = json.loads(lines[-1].removeprefix("RESULT "))
    return result


def _rows(store: Path, sql: str, *params: object) -> list[sqlite3.Row]:
    with contextlib.closing(sqlite3.connect(f"file:{store}?mode=ro", uri=True)) as db:
        db.row_factory = sqlite3.Row
        return list(db.execute(sql, params))


def check_successful_trial(store: Path, session_id: str, operator_id: str) -> list[sqlite3.Row]:
    """The session's one trial succeeded; returns its frames in order."""
    (session,) = _rows(store, "SELECT * FROM sessions WHERE session_id = ?", session_id)
    assert session["operator_id"] == operator_id
    assert session["mode"] == "practice"
    assert json.loads(session["parameters_json"])["task"]["kind"] == "box_transfer"
    (trial,) = _rows(store, "SELECT * FROM trials WHERE session_id = ?", session_id)
    assert trial["outcome"] == "success", dict(trial)
    assert trial["boxes_delivered"] == 1
    assert trial["score"] > 100
    frames = _rows(
        store, "SELECT * FROM frames WHERE trial_id = ? ORDER BY frame_index", trial["trial_id"]
    )
    assert len(frames) == trial["n_frames"] > 20
    return frames


def check_frame_reports(store: Path, session_id: str, presenting: bool) -> None:
    """The operator's page reported how it drew, recorded with the trial: frame intervals
    and draw calls, presenting to a headset or not."""
    rows = _rows(
        store,
        "SELECT payload_json FROM events WHERE session_id = ? AND kind = 'client_frames'",
        session_id,
    )
    reports = [json.loads(row["payload_json"]) for row in rows]
    assert reports, "the page never reported its frame times"
    for report in reports:
        assert report["frames"] > 0 and report["draw_calls"] > 0 and report["triangles"] > 0
        assert 0 < report["frame_ms_p50"] <= report["frame_ms_p95"] <= report["frame_ms_max"]
    assert any(report["presenting"] is presenting for report in reports)


def check_operator_inputs(frames: list[sqlite3.Row]) -> None:
    """The frames carry the operator's raw device state: both controller poses, grips held,
    triggers closed, and the base driven away from its start."""
    with_poses = [f for f in frames if f["ctrl_l_x"] is not None and f["ctrl_r_x"] is not None]
    assert len(with_poses) > len(frames) // 2, "controller poses missing from the frames"
    assert all(f["headset_qw"] is not None for f in with_poses)
    # ...and beside the raw poses the filtered ones the arms and the view acted on
    assert all(
        f[f"{pose}_filtered_{axis}"] is not None
        for f in with_poses
        for pose in ("ctrl_l", "ctrl_r", "headset")
        for axis in ("x", "qw")
    )
    lagging = [f for f in with_poses if abs(f["ctrl_l_filtered_y"] - f["ctrl_l_y"]) > 1e-4]
    assert lagging, "the filtered left controller never differs from the raw one"
    gripped = [f for f in frames if f["grip_l"] > 0.5 and f["grip_r"] > 0.5]
    assert len(gripped) > 10, "no frames with both grips held"
    assert any(f["trigger_l"] > 0.5 and f["trigger_r"] > 0.5 for f in frames)
    assert any(f["follow_l"] and f["follow_r"] for f in frames)
    assert any(abs(f["stick_l_y"] or 0.0) > 0.2 for f in frames), "the left stick never moved"
    first = frames[0]
    moved = max(
        math.hypot(f["base_x"] - first["base_x"], f["base_y"] - first["base_y"]) for f in frames
    )
    assert moved > 0.5, f"the base moved only {moved:.2f} m"
    # While a grip is held the controller moves (the arm follows the hand).
    spread = max(f["ctrl_l_y"] for f in gripped) - min(f["ctrl_l_y"] for f in gripped)
    assert spread > 0.05, f"the left controller hardly moved while gripped ({spread:.3f} m)"


def test_vr_delivery_with_emulated_quest(server: Server) -> None:
    result = run_script("xr_delivery", server)
    assert result["outcome"] == "success"
    assert result["base_moved_m"] > 0.2
    frames = check_successful_trial(server.store, result["session_id"], "e2e-xr")
    check_operator_inputs(frames)
    check_frame_reports(server.store, result["session_id"], presenting=True)
    assert result["hud_off_axis_deg"] > 45  # the HUD never sits in front of the work area
    assert result["vignette_peak"] > 0.3  # driving in first person narrowed the view


def test_desktop_delivery_with_keyboard_and_mouse(server: Server) -> None:
    result = run_script("desktop_delivery", server)
    assert result["outcome"] == "success"
    assert result["source"] == "desktop"
    assert {"w", "g", "h", "f", "j", "z"} <= set(result["keys_used"])
    frames = check_successful_trial(server.store, result["session_id"], "e2e-desktop")
    check_operator_inputs(frames)
    check_frame_reports(server.store, result["session_id"], presenting=False)


def test_reconnect_sessions_page_and_replay(server: Server) -> None:
    result = run_script("sessions_replay", server)
    (trial,) = _rows(
        server.store, "SELECT * FROM trials WHERE session_id = ?", result["session_id"]
    )
    assert trial["outcome"] == "interrupted"
    assert trial["interruption_reason"] == "operator_stop"
    assert result["replay_frames"] > 10


def test_toolbar_stays_on_top_after_leaving_vr(server: Server) -> None:
    result = run_script("xr_exit_toolbar", server)
    assert all(control["ok"] for control in result["toolbar_after_vr"])
    assert result["reason"] == "operator_stop"  # "Stop session" was clicked with the pointer
    (trial,) = _rows(
        server.store, "SELECT * FROM trials WHERE session_id = ?", result["session_id"]
    )
    assert (trial["outcome"], trial["interruption_reason"]) == ("interrupted", "operator_stop")


def test_in_vr_menu_recenters_switches_view_restarts_and_stops(server: Server) -> None:
    """The in-VR menu (X, thumbstick, A) in the emulated Quest: every choice is recorded as
    an event of the trial it was made in, and the restart began a new trial."""
    result = run_script("xr_menu", server)
    assert result["reason"] == "operator_stop"
    assert abs(result["recenter_yaw"] - math.pi / 3) < 0.02
    first, second = _rows(
        server.store,
        "SELECT * FROM trials WHERE session_id = ? ORDER BY trial_index",
        result["session_id"],
    )
    assert (first["outcome"], first["interruption_reason"]) == ("interrupted", "operator_restart")
    assert (second["outcome"], second["interruption_reason"]) == ("interrupted", "operator_stop")
    events = _rows(
        server.store,
        "SELECT trial_id, payload_json FROM events WHERE session_id = ? AND kind = ? ORDER BY seq",
        result["session_id"],
        "operator_action",
    )
    recorded = [(e["trial_id"], json.loads(e["payload_json"])) for e in events]
    assert [(t, p["action"], p["source"]) for t, p in recorded] == [
        (first["trial_id"], "recenter_view", "xr_menu"),
        (first["trial_id"], "view_third", "xr_menu"),
        (first["trial_id"], "restart_trial", "xr_menu"),
        (second["trial_id"], "turn_snap", "xr_menu"),
        (second["trial_id"], "snap_right", "xr_button"),
    ]
    assert result["snap_turned"] == pytest.approx(-math.pi / 6, abs=0.05)  # one flick right


def test_hand_tracking_grabs_moves_and_pinches_in_the_emulated_quest(server: Server) -> None:
    """Hands instead of controllers: a grab engages the arm, which follows the wrist; a
    pinch closes the gripper. The frames record the hand as they record a controller."""
    result = run_script("xr_hands", server)
    assert result["moved"] > 0.08
    (trial,) = _rows(
        server.store, "SELECT * FROM trials WHERE session_id = ?", result["session_id"]
    )
    frames = _rows(
        server.store,
        "SELECT * FROM frames WHERE trial_id = ? ORDER BY frame_index",
        trial["trial_id"],
    )
    grabbed = [f for f in frames if f["grip_l"] > 0.9 and f["follow_l"]]
    assert grabbed, "no frame with the left hand grabbing and the arm following"
    first = grabbed[0]
    travel = max(
        math.dist([f[f"target_l_{a}"] for a in "xyz"], [first[f"target_l_{a}"] for a in "xyz"])
        for f in grabbed
    )
    assert travel > 0.08, f"the grabbed arm's target moved {travel:.3f} m"
    assert any(f["trigger_l"] > 0.9 and not f["follow_l"] for f in frames), "no pinch recorded"
    assert all(f["ctrl_l_x"] is not None for f in grabbed)  # the wrist pose, recorded raw
    assert all(f["ctrl_l_filtered_x"] is not None for f in grabbed)  # and as filtered


STUDY = """name = "pilot"
participants = 2
instructions = "Move the box to the green zone."
consent = "I agree that my teleoperation is recorded."
[session]
task = { countdown_s = 0.0, time_limit_s = 3.0 }
[[conditions]]
name = "assisted"
settings = { "world.grasp" = "assisted" }
[[conditions]]
name = "physical"
settings = { "world.grasp" = "physical" }
[[steps]]
mode = "practice"
"""


def test_a_study_participant_consents_and_runs_their_plan_and_the_admin_sees_it(
    tmp_path: Path, one_browser_at_a_time: None
) -> None:
    """``workcell serve --study``: the participant's invite page asks consent once and runs
    the plan's session; the admin page lists the participants live."""
    study_file = tmp_path / "pilot.toml"
    study_file.write_text(STUDY, encoding="utf-8")
    study = load_study(study_file)
    invites = load_or_create(invites_path(tmp_path / "store.sqlite", study), study)
    study_server = ("--study", str(study_file), "--sessions", "2")
    with serving(tmp_path, *study_server, token=invites.admin) as server:
        result = run_script("study", server, invites.participants["p01"], invites.admin)
    (session,) = _rows(server.store, "SELECT * FROM sessions")
    parameters = json.loads(session["parameters_json"])
    assert session["session_id"] == result["session_id"] and session["operator_id"] == "p01"
    assert parameters["condition"] == participant_plan(study, "p01")[0].condition
    assert parameters["consent"] == hashlib.sha256(study.consent.encode()).hexdigest()
    assert session["status"] == "completed"


def test_a_page_of_another_origin_cannot_drive(tmp_path: Path, one_browser_at_a_time: None) -> None:
    """A page of another local origin opens the WebSocket in Chromium: refused before it
    can say hello; an origin given with --allow-origin is let in."""
    port = _free_port()
    with serving(tmp_path, "--allow-origin", f"http://127.0.0.1:{port}") as running:
        result = run_script("cross_origin", running, str(port))
        foreign, allowed = result["foreign"], result["allowed"]
        assert not foreign["opened"] and foreign["messages"] == []
        assert foreign["close_code"] == 1006  # the handshake was refused
        assert foreign["api"].startswith("refused")  # and the API is not readable from it
        assert allowed["opened"] and allowed["messages"][0] == "welcome"
        with urllib.request.urlopen(f"{running.url}/api/diagnostics", timeout=5) as reply:
            assert json.loads(reply.read())["sim"] is None  # no session was started
    assert not running.store.exists()  # nothing was recorded
