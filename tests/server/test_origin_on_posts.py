"""Every state-changing HTTP route checks the Origin as the WebSocket does: a page of
another origin (another port of the same host sends the admin's SameSite=Strict cookie
along) cannot stop a participant's session; the server's own page and an
``--allow-origin`` can."""

from __future__ import annotations

import asyncio
import re
from pathlib import Path

from starlette.routing import Route

from tests.server.harness import RunningServer, client, running_server
from tests.server.test_origin_and_host import raw_request
from tests.server.test_study_server import ended, start, study, token_of
from workcell.protocol import messages as m
from workcell.server.app import create_app
from workcell.server.auth import COOKIE
from workcell.server.options import ServerOptions

ALLOWED = "http://localhost:18009"
FOREIGN = (
    "http://localhost:3000",  # another port of the same host: the cookie goes along
    "http://evil.example",
    "null",  # a sandboxed frame or a file: page
    "garbage",
)


def post(server: RunningServer, path: str, origin: str | None) -> tuple[int, str]:
    """POST ``path`` with the admin's cookie, as a browser would, from ``origin``."""
    lines = [
        f"POST {path} HTTP/1.1",
        f"Host: 127.0.0.1:{server.port}",
        f"Cookie: {COOKIE}={server.options.token}",
        "Content-Length: 0",
        "Connection: close",
    ]
    if origin is not None:
        lines.append(f"Origin: {origin}")
    return raw_request(server.port, "\r\n".join(lines))


def state_changing_paths(options: ServerOptions) -> list[str]:
    """Every route of the app that takes more than GET, its parameters filled with p01."""
    app = create_app(options)
    paths = []
    for route in app.routes:
        if isinstance(route, Route) and (route.methods or set()) - {"GET", "HEAD"}:
            paths.append(re.sub(r"\{[^}]+\}", "p01", route.path))
    return paths


def test_every_state_changing_route_refuses_a_foreign_origin(tmp_path: Path) -> None:
    paths = state_changing_paths(ServerOptions(store=tmp_path / "store.sqlite"))
    assert "/api/study/participants/p01/stop" in paths
    with running_server(tmp_path, study=study(), allow_origins=(ALLOWED,)) as server:
        for path in paths:
            for origin in FOREIGN:
                status, answer = post(server, path, origin)
                assert status == 403, (path, origin)
                assert f"Origin {origin!r} may not send POST requests here" in answer
            own: tuple[str | None, ...] = (f"http://127.0.0.1:{server.port}", ALLOWED, None)
            for allowed in own:  # the route itself answers (409: no session runs)
                assert post(server, path, allowed)[0] == 409, (path, allowed)


def test_a_foreign_origin_cannot_stop_a_participants_session(tmp_path: Path) -> None:
    async def scenario(server: RunningServer) -> None:
        path = "/api/study/participants/p02/stop"
        async with client(server, query=f"?token={token_of(server, 'p02')}") as p02:
            await p02.hello("operator")
            started = await start(p02, consent=True)
            assert isinstance(started, m.SessionStarted)
            status, answer = post(server, path, "http://localhost:3000")
            assert status == 403 and "may not send POST requests here" in answer
            await asyncio.sleep(0.5)  # had it been stopped, it would have ended by now
            assert server.seats.conductors["p02"].session is not None
            assert not any(isinstance(x, m.SessionEnded) for x in p02.received)
            status, answer = post(server, path, f"http://127.0.0.1:{server.port}")
            assert status == 200 and '"stopped":"p02"' in answer.replace(" ", "")
            assert (await ended(p02)).reason == "admin_stop"

    with running_server(tmp_path, study=study(time_limit_s=60.0)) as server:
        asyncio.run(scenario(server))
