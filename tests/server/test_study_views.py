"""The researcher's views over a real socket (issue 36, points 7 and 8): the admin
watches a participant's live session; a replay names its trial's participant, condition,
study step and outcome, counts the frames the Sessions page counts and carries the event
timeline; the Sessions page's downloads (the store's CSV export zipped, the audit's
trials.csv of chosen sessions, a LeRobot dataset of chosen participants) answer the admin
only."""

from __future__ import annotations

import asyncio
import csv
import io
import json
import zipfile
from pathlib import Path

from tests.server.harness import RunningServer, client, running_server
from tests.server.test_study_server import ended, get_as, start, study, token_of
from workcell.protocol import messages as m
from workcell.protocol.api import SessionList, TrialReplay
from workcell.protocol.validation import build
from workcell.study.plan import participant_plan


def _admin(server: RunningServer) -> str:
    token = server.options.token
    assert token is not None
    return token


async def _run_p01_watched_by_the_admin(server: RunningServer) -> tuple[str, int]:
    """p01 runs their first planned session while the admin watches their seat; the
    session id and how many States the admin saw."""
    async with client(server, query=f"?token={token_of(server, 'p01')}") as p01:
        await p01.hello("operator")
        async with client(server, query=f"?token={_admin(server)}") as admin:
            welcome = await admin.hello("spectator", seat="p01")
            assert (welcome.role, welcome.seat) == ("spectator", "p01")
            started = await start(p01, consent=True)
            assert isinstance(started, m.SessionStarted), started
            await admin.wait_for(lambda x: isinstance(x, m.State))
            assert (await ended(p01)).reason == "completed"
            states = sum(isinstance(x, m.State) for x in admin.received)
        return started.session_id, states


def test_replay_facts_timeline_and_frame_count_and_the_admins_downloads(tmp_path: Path) -> None:
    config = study()
    plan = participant_plan(config, "p01")
    with running_server(tmp_path, study=config) as server:
        session_id, watched = asyncio.run(_run_p01_watched_by_the_admin(server))
        admin = _admin(server)
        status, listing_json = get_as(server, "/api/sessions", admin)
        listing = build(SessionList, listing_json, "sessions")
        assert isinstance(listing, SessionList)
        (session,) = listing.sessions
        (trial,) = session.trials
        assert (session.operator_id, session.condition) == ("p01", plan[0].condition)
        assert session.study_step == 1

        status, body = get_as(server, f"/api/trials/{trial.trial_id}/frames?every=2", admin)
        assert status == 200
        replay = build(TrialReplay, body, "replay")
        assert isinstance(replay, TrialReplay)
        facts = replay.facts
        assert (facts.operator_id, facts.condition, facts.study_step) == (
            "p01",
            plan[0].condition,
            1,
        )
        assert (facts.outcome, facts.boxes_delivered, facts.elapsed_s) == ("timeout", 0, 0.5)
        assert (facts.included, facts.score) == (trial.included, trial.score)
        # the frames the Sessions page counts, though the reply carries every second one
        assert replay.recorded_frames == trial.n_frames
        assert len(replay.poses) == (replay.recorded_frames + 1) // 2
        kinds = [e.kind for e in replay.events]
        assert kinds[0] == "trial_started" and "trial_timed_out" in kinds
        assert "client_frames" not in kinds and "media" not in kinds
        times = [e.t for e in replay.events]
        assert times == sorted(times) and times[-1] == 0.5

        status, text = get_as(server, f"/api/export/trials.csv?session={session_id}", admin)
        assert status == 200
        (row,) = list(csv.DictReader(io.StringIO(text)))
        assert (row["trial_id"], row["operator_id"], row["condition"], row["study_step"]) == (
            trial.trial_id,
            "p01",
            plan[0].condition,
            "1",
        )
        assert row["outcome"] == "timeout"
        status, problem = get_as(server, "/api/export/trials.csv?session=nope", admin)
        assert status == 404 and "session = 'nope': not in the store" in problem["error"]

        status, archive = server.get("/api/export/csv.zip", {"Authorization": f"Bearer {admin}"})
        assert status == 200
        with zipfile.ZipFile(io.BytesIO(archive)) as packed:
            names = set(packed.namelist())
            manifest = json.loads(packed.read("manifest.json"))
            trials_csv = packed.read("trials.csv").decode()
        assert {"sessions.csv", "trials.csv", "frames.csv", "manifest.json"} <= names
        assert manifest["files"]["frames.csv"]["rows"] == trial.n_frames
        assert trial.trial_id in trials_csv

        bearer = {"Authorization": f"Bearer {admin}"}
        status, archive = server.get("/api/export/lerobot.zip?operator=p01", bearer)
        assert status == 200, archive[:300]
        with zipfile.ZipFile(io.BytesIO(archive)) as packed:
            names = set(packed.namelist())
            note = packed.read("workcell_selection.txt").decode()
        assert "meta/info.json" in names and any(n.startswith("data/") for n in names)
        assert any(n.startswith("meta/workcell_provenance") for n in names)
        assert "exported 1 episode," in note and "kept 1 of 1 closed trials" in note
        status, body = server.get("/api/export/lerobot.zip?operator=p02", bearer)
        assert status == 409 and b"none of its 1 closed trials can be exported" in body

        p01 = token_of(server, "p01")
        paths = ("/api/export/csv.zip", "/api/export/lerobot.zip", "/api/export/trials.csv")
        for path in paths:
            status, refused = get_as(server, path, p01)
            assert status == 403 and "admin" in refused, path
    assert watched > 0


def test_downloads_before_anything_is_recorded_say_so(tmp_path: Path) -> None:
    with running_server(tmp_path) as server:
        for path in ("/api/export/csv.zip", "/api/export/trials.csv", "/api/export/lerobot.zip"):
            status, body = server.get(path)
            assert status == 404 and b"the store has no sessions yet" in body, path
