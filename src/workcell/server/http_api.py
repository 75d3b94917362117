"""The read-only JSON API: ``/api/defaults``, ``/api/settings/hints``, ``/api/sessions``,
``/api/trials/{id}/frames`` and ``/api/diagnostics``."""

from __future__ import annotations

import re
import time
from pathlib import Path
from typing import Any

from starlette.requests import Request
from starlette.responses import Response
from starlette.routing import Route

from workcell.protocol.api import SessionList, SessionSummary, TrialSummary
from workcell.protocol.codec import encode
from workcell.record.connection import damage_as_store_error
from workcell.record.entries import AnnotationRecord, TrialRecord
from workcell.record.errors import StoreError
from workcell.record.inclusion import decide
from workcell.record.store import Store
from workcell.record.study_tags import StudyTags
from workcell.server.defaults import session_defaults, session_hints
from workcell.server.diagnostics import diagnostics
from workcell.server.replay import TrialNotFoundError, trial_replay
from workcell.server.seats import Seats

MAX_EVERY = 10_000


def json_response(body: object, status: int = 200) -> Response:
    return Response(encode(body), status_code=status, media_type="application/json")


def problem(status: int, message: str) -> Response:
    return json_response({"error": message}, status)


def whole_number(text: str, high: int) -> int | None:
    """``text`` as a whole number 1 to ``high`` written in ASCII digits, else None (never
    an exception: ``int`` refuses "²" and 5,000 digits with one, and reads "٣" as 3)."""
    if not re.fullmatch(r"[0-9]{1,12}", text):
        return None
    number = int(text)
    return number if 1 <= number <= high else None


def shown(text: str, most: int = 20) -> str:
    """``text`` quoted for a message, cut to its first ``most`` characters."""
    return repr(text) if len(text) <= most else f"{text[:most]!r}... ({len(text)} characters)"


def session_list(path: Path) -> SessionList:
    if not path.exists():
        return SessionList(sessions=())
    with damage_as_store_error(path), Store.open(path, writer=False) as store:
        trials = store.trials()
        reviews: dict[str, list[AnnotationRecord]] = {}
        for annotation in store.annotations():
            reviews.setdefault(annotation.trial_id, []).append(annotation)
        return SessionList(
            sessions=tuple(
                SessionSummary(
                    session_id=s.session_id,
                    mode=s.mode,
                    **StudyTags.of(s.operator_id, s.parameters).as_dict(),
                    created_wall=s.created_wall,
                    ended_wall=s.ended_wall,
                    status=s.status,
                    trials=tuple(
                        TrialSummary(
                            trial_id=t.trial_id,
                            trial_index=t.trial_index,
                            mode=t.mode,
                            round=t.round,
                            level=t.level,
                            required_boxes=t.required_boxes,
                            time_limit_s=t.time_limit_s,
                            outcome=t.outcome,
                            interruption_reason=t.interruption_reason,
                            elapsed_s=t.elapsed_s,
                            boxes_delivered=t.boxes_delivered,
                            score=t.score,
                            n_frames=t.n_frames,
                            quality_flags=t.quality_flags,
                            **_inclusion(t, reviews.get(t.trial_id, [])),
                            started_wall=t.started_wall,
                        )
                        for t in trials
                        if t.session_id == s.session_id
                    ),
                )
                for s in store.sessions()
            )
        )


def _inclusion(trial: TrialRecord, reviews: list[AnnotationRecord]) -> dict[str, Any]:
    """``included`` and ``exclusion_reason`` as every output says them (None while the
    trial runs)."""
    if trial.outcome is None:
        return {"included": None, "exclusion_reason": None}
    inclusion = decide(trial, reviews)
    return {"included": inclusion.included, "exclusion_reason": inclusion.reason}


def routes(seats: Seats) -> list[Route]:
    store_path = seats.options.store

    def defaults(request: Request) -> Response:
        return json_response(session_defaults())

    def hints(request: Request) -> Response:
        return json_response(session_hints())

    def sessions(request: Request) -> Response:
        try:
            return json_response(session_list(store_path))
        except StoreError as error:  # a damaged store: say so instead of a bare 500
            return problem(503, str(error))

    def frames(request: Request) -> Response:
        text = request.query_params.get("every", "1")
        every = whole_number(text, MAX_EVERY)
        if every is None:
            return problem(400, f"every = {shown(text)}: must be a whole number 1 to {MAX_EVERY}")
        if not store_path.exists():
            return problem(404, "the store has no trials yet")
        try:
            with damage_as_store_error(store_path), Store.open(store_path, writer=False) as store:
                reply = trial_replay(store, request.path_params["trial_id"], every)
        except TrialNotFoundError as error:
            return problem(404, str(error))
        except StoreError as error:
            return problem(503, str(error))
        return json_response(reply)

    def diagnostics_route(request: Request) -> Response:
        return json_response(diagnostics(seats, time.process_time()))

    return [
        Route("/api/defaults", defaults),
        Route("/api/settings/hints", hints),
        Route("/api/sessions", sessions),
        Route("/api/trials/{trial_id}/frames", frames),
        Route("/api/diagnostics", diagnostics_route),
    ]
