"""Where a seat's session settings come from: the operator's ``start_session`` or, in a
study, the participant's plan; either the settings or one answer to the client saying why
the session does not start."""

from __future__ import annotations

from typing import Protocol

from workcell.errors import ConfigError
from workcell.protocol import messages as m
from workcell.server.client import Client
from workcell.server.field_problems import field_problems
from workcell.server.study_desk import Refusal
from workcell.session.config import SessionConfig
from workcell.session.toml_io import from_mapping
from workcell.tasks.registry import built_in_task


class SessionPlanner(Protocol):
    """Where a seat's session settings come from when the operator does not choose them (a
    study participant's plan): the settings, or why the session does not start."""

    async def plan(self, start: m.StartSession) -> SessionConfig | Refusal: ...


async def session_settings(
    planner: SessionPlanner | None, client: Client, start: m.StartSession
) -> SessionConfig | None:
    """The session's settings: the operator's, or the planner's (None: ``client`` has
    been told why not)."""
    if planner is not None:
        planned = await planner.plan(start)
        if isinstance(planned, Refusal):
            client.refuse(planned.code, planned.message)
            return None
        return planned
    try:
        config = from_mapping(SessionConfig, start.settings)
        built_in_task(config.task.kind)
    except ConfigError as error:
        client.send(m.ConfigRejected(problems=field_problems(error)))
        return None
    return config
