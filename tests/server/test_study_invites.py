"""A study's invites are those of the current study file, and can expire: a participant
the study no longer holds, or whose invite is past the study's ``invite_days``, opens
nothing (HTTP 401 saying why, the WebSocket refused), and ``workcell serve`` says so at
startup instead of printing their link."""

from __future__ import annotations

import dataclasses
import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

from tests.server.harness import running_server
from tests.server.test_origin_and_host import ws_handshake
from tests.server.test_study_server import get_as, study
from workcell.study.invites import SECONDS_PER_DAY, invites_path, load_or_create, minute_utc
from workcell.study.template import TEMPLATE


def test_a_removed_participants_invite_opens_nothing(tmp_path: Path) -> None:
    store = tmp_path / "store.sqlite"
    three = study(participants=3)
    before = load_or_create(invites_path(store, three), three)
    with running_server(tmp_path, study=study(participants=2)) as server:
        port = server.port
        removed = before.participants["p03"]
        status, body = get_as(server, "/api/study/me", removed)
        assert status == 401 and "needs its access token" in body  # before: 500 (KeyError)
        assert ws_handshake(port, f"127.0.0.1:{port}", None, f"?token={removed}") == 403
        for kept in ("p01", "p02"):  # the others' links are unchanged and still work
            status, me = get_as(server, "/api/study/me", before.participants[kept])
            assert (status, me["participant"]) == (200, kept)
    held = json.loads(invites_path(store, three).read_text("utf-8"))
    assert sorted(held["participants"]) == sorted(held["issued"]) == ["p01", "p02"]
    grown = load_or_create(invites_path(store, three), three)  # the study grows again
    assert grown.participants["p03"] != removed and grown.dropped == ()


def _issued_days_ago(store: Path, participant: str, days: float) -> None:
    """Say in the study's invites file that ``participant``'s invite is ``days`` old."""
    path = invites_path(store, study())
    held = json.loads(path.read_text("utf-8"))
    then = time.gmtime(time.time() - days * SECONDS_PER_DAY)
    held["issued"][participant] = time.strftime("%Y-%m-%dT%H:%M:%SZ", then)
    path.write_text(json.dumps(held), "utf-8")


def test_an_expired_invite_is_refused_saying_so(tmp_path: Path) -> None:
    store = tmp_path / "store.sqlite"
    pilot = dataclasses.replace(study(), invite_days=2.0)
    invites = load_or_create(invites_path(store, pilot), pilot)
    _issued_days_ago(store, "p01", 3.0)
    with running_server(tmp_path, study=pilot) as server:
        port = server.port
        expired = invites.participants["p01"]
        expires = load_or_create(invites_path(store, pilot), pilot).expires("p01", 2.0)
        assert expires is not None
        for path in ("/", "/api/study/me"):
            status, body = get_as(server, path, expired)
            assert (status, body) == (
                401,
                f"401 Unauthorized: the invite of p01 expired on {minute_utc(expires)}; ask "
                "the study's admin for a new link.\n",
            )
        assert ws_handshake(port, f"127.0.0.1:{port}", None, f"?token={expired}") == 403
        assert get_as(server, "/api/study/me", invites.participants["p02"])[0] == 200
        assert server.options.token is not None  # the admin's link does not expire
        assert get_as(server, "/api/study", server.options.token)[0] == 200


def test_serve_says_which_invites_it_dropped_and_which_expired(tmp_path: Path) -> None:
    store = tmp_path / "store.sqlite"
    three = dataclasses.replace(study(participants=3), invite_days=2.0)
    invites = load_or_create(invites_path(store, three), three)
    _issued_days_ago(store, "p01", 3.0)
    study_file = tmp_path / "pilot.toml"
    pilot = TEMPLATE.replace('name = "study"', 'name = "pilot"')
    pilot = pilot.replace("participants = 12", "participants = 2")
    study_file.write_text(pilot.replace("invite_days = 0", "invite_days = 2"), "utf-8")
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = int(s.getsockname()[1])
    serve = [sys.executable, "-m", "workcell", "serve", "--store", str(store)]
    process = subprocess.Popen(
        [*serve, "--port", str(port), "--study", str(study_file)],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        env={**os.environ, "MUJOCO_GL": "egl"},
    )
    try:
        assert process.stdout is not None
        lines = [process.stdout.readline() for _ in range(6)]
    finally:
        process.send_signal(signal.SIGTERM)
        process.communicate(timeout=30)
    assert lines[1] == (
        "  invites dropped: p03 (not among the study's 2 participants: their links open nothing)\n"
    ), lines
    assert lines[3].startswith(f"  p01         http://127.0.0.1:{port}/?token=")
    assert lines[3].rstrip().endswith(" UTC)") and "  (expired " in lines[3]
    assert f"?token={invites.participants['p02']}  (valid until " in lines[4]
    assert "p03" not in "".join(lines[2:])
