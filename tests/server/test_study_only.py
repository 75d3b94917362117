"""A study server records its participants' planned sessions only: the admin's page (or
any page that is not a participant's) starts nothing, and ``/api/study/me`` answers a page
that is not a participant's without an error."""

from __future__ import annotations

import asyncio
from pathlib import Path

from tests.server.harness import FAST_SETTINGS, RunningServer, client, running_server
from tests.server.test_study_server import get_as, start, study
from workcell.protocol import messages as m


def test_the_admins_start_is_refused_and_records_nothing(tmp_path: Path) -> None:
    async def scenario(server: RunningServer) -> None:
        admin = server.options.token
        assert admin is not None
        async with client(server, query=f"?token={admin}") as page:
            welcome = await page.hello("operator")
            assert welcome.role == "operator"
            refused = await start(page, consent=True, **FAST_SETTINGS)
            assert isinstance(refused, m.Error) and refused.code == "not_allowed"
            assert "study pilot" in refused.message and "invite" in refused.message
            assert "\n" not in refused.message
        assert server.seats.running == 0

    with running_server(tmp_path, study=study()) as server:
        asyncio.run(scenario(server))
    assert not (tmp_path / "store.sqlite").exists()  # nothing was recorded


def test_study_me_answers_pages_that_are_not_a_participants_without_an_error(
    tmp_path: Path,
) -> None:
    for folder in ("free", "study"):
        (tmp_path / folder).mkdir()
    with running_server(tmp_path / "free") as server:  # no study
        assert server.get("/api/study/me") == (204, b"")
    with running_server(tmp_path / "study", study=study()) as server:
        admin = server.options.token
        assert admin is not None
        assert get_as(server, "/api/study/me", admin)[0] == 204
