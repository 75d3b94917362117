"""The study's HTTP API (``workcell serve --study``): ``GET /api/study/me`` for a
participant (204, no content, for a page that is not a participant's, or on a server
without a study: every page asks), and for the admin ``GET /api/study`` (every
participant, live) and ``POST /api/study/participants/{id}/stop`` (end their running session;
an optional JSON body ``{"reason": "..."}`` gives the admin's words, recorded in the
``stop_requested`` event and shown to the participant)."""

from __future__ import annotations

import asyncio
import json

from starlette.requests import Request
from starlette.responses import Response
from starlette.routing import Route

from workcell.protocol.api import ParticipantRow, ParticipantState, StudyOverview
from workcell.protocol.codec import LONE_SURROGATE, has_utf8_form
from workcell.server.admission import behind_real_time
from workcell.server.auth import principal_of
from workcell.server.conductor import Conductor
from workcell.server.diagnostics import sim_diagnostics
from workcell.server.http_api import json_response, problem
from workcell.server.seats import Seats
from workcell.server.study_desk import Recorded, StudyDesk
from workcell.task.events import STOP_NOTE_MAX

NO_STUDY = "this server runs no study (workcell serve --study FILE)"


def study_routes(seats: Seats) -> list[Route]:
    def me(request: Request) -> Response:
        desk = seats.desk
        participant = principal_of(request.scope).participant
        if desk is None or participant is None:  # every page asks: not an error
            return Response(status_code=204)
        return json_response(desk.status(participant))

    async def overview(request: Request) -> Response:
        desk = seats.desk
        if desk is None:
            return problem(404, NO_STUDY)
        recorded = await asyncio.to_thread(desk.recorded)  # the seats are read on the loop
        return json_response(study_overview(seats, desk, recorded))

    async def stop(request: Request) -> Response:
        desk = seats.desk
        if desk is None:
            return problem(404, NO_STUDY)
        participant = request.path_params["participant"]
        if participant not in desk.plans:
            return problem(404, f"participant {participant[:40]!r}: not one of the study's")
        note = await _stop_note(request)
        if not isinstance(note, str):
            return note
        conductor = seats.conductors.get(participant)
        if conductor is None or not conductor.stop_by_admin(note):
            return problem(409, f"participant {participant}: no session is running")
        return json_response({"stopped": participant})

    return [
        Route("/api/study/me", me),
        Route("/api/study", overview),
        Route("/api/study/participants/{participant}/stop", stop, methods=["POST"]),
    ]


async def _stop_note(request: Request) -> str | Response:
    """The admin's reason for a stop (none: ""), or the 400 saying what was wrong."""
    body = await request.body()
    if not body.strip():
        return ""
    allowed = f'a JSON object {{"reason": text of at most {STOP_NOTE_MAX} characters}}'
    try:
        data = json.loads(body)
    except (ValueError, UnicodeDecodeError, RecursionError):  # RecursionError: nested too deep
        return problem(400, f"stop: the body is not JSON; give {allowed}")
    reason = data.get("reason", "") if isinstance(data, dict) else None
    if not isinstance(reason, str) or len(reason) > STOP_NOTE_MAX or set(data) - {"reason"}:
        return problem(400, f"stop: body {body[:80]!r}: give {allowed}")
    if not has_utf8_form(reason):  # the store writes UTF-8
        return problem(400, f"stop: {LONE_SURROGATE}")
    return reason.strip()


def study_overview(seats: Seats, desk: StudyDesk, recorded: Recorded) -> StudyOverview:
    """Every participant as the admin page shows them, from the seats (read on the event
    loop, which changes them) and what the store holds."""
    rows = tuple(
        _row(desk, participant, seats.conductors.get(participant), recorded)
        for participant in desk.plans
    )
    factors = [row.real_time_factor for row in rows if row.real_time_factor is not None]
    return StudyOverview(
        study=desk.study.name,
        running=seats.running,
        max_sessions=seats.options.max_sessions,
        participants=rows,
        behind=behind_real_time(factors),
        waiting=seats.line.waiting,
    )


def _row(
    desk: StudyDesk, participant: str, seat: Conductor | None, recorded: Recorded
) -> ParticipantRow:
    session = seat.session if seat is not None else None
    remaining = desk.remaining(participant, recorded)
    operator = seat.operator if seat is not None else None
    running_id = session.session_id if session is not None else None
    theirs = {
        s.session_id
        for s in recorded.sessions
        if s.operator_id == participant and s.session_id != running_id
    }
    outcomes = [t.outcome for t in recorded.trials if t.session_id in theirs and t.outcome]
    outcomes += session.outcomes if session is not None else ()
    state: ParticipantState
    if session is not None:
        state, condition = "running", session.config.condition
    elif not remaining:
        state, condition = "finished", None
    else:
        state = "waiting" if operator is not None else "offline"
        condition = remaining[0].condition
    sim = sim_diagnostics(seat) if seat is not None else None
    plan = desk.plans[participant]
    return ParticipantRow(
        participant=participant,
        invite=f"/?token={desk.invites.participants[participant]}",
        state=state,
        done=len(plan) - len(remaining),
        total=len(plan),
        condition=condition,
        session_id=running_id,
        rtt_ms=operator.stats.rtt_ms if operator is not None else None,
        real_time_factor=sim.real_time_factor if sim is not None else None,
        trials=len(outcomes),
        successes=sum(outcome == "success" for outcome in outcomes),
    )
