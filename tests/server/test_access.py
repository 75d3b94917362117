"""Token, subprotocol and static files: what gets in and what is refused."""

from __future__ import annotations

import asyncio
import http.client
from pathlib import Path

import pytest
from websockets.asyncio.client import connect
from websockets.exceptions import ConnectionClosedError, InvalidStatus

from tests.server.harness import RunningServer, client, running_server
from workcell.errors import ConfigError
from workcell.protocol import messages as m
from workcell.server.options import ServerOptions

TOKEN = "s3cret-token-for-tests"


def test_non_loopback_host_needs_a_token() -> None:
    with pytest.raises(ConfigError, match="needs a token"):
        ServerOptions(host="0.0.0.0")
    ServerOptions(host="0.0.0.0", token=TOKEN)
    ServerOptions(host="localhost")


def test_token_is_required_for_http_and_websocket(tmp_path: Path) -> None:
    with running_server(tmp_path, token=TOKEN) as server:
        for path in ("/", "/api/defaults", "/api/sessions", "/app.js"):
            status, body = server.get(path)
            assert status == 401 and b"token" in body
        assert server.get("/api/defaults?token=wrong")[0] == 401
        assert server.get("/api/defaults", {"Authorization": "Bearer wrong"})[0] == 401
        assert server.get(f"/api/defaults?token={TOKEN}")[0] == 200
        assert server.get("/api/defaults", {"Authorization": f"Bearer {TOKEN}"})[0] == 200
        # the page's own requests carry the cookie set on the first authorised response
        connection = http.client.HTTPConnection("127.0.0.1", server.port, timeout=10)
        connection.request("GET", f"/api/sessions?token={TOKEN}")
        response = connection.getresponse()
        response.read()
        cookie = response.getheader("set-cookie") or ""
        assert cookie.startswith("workcell_token=") and "HttpOnly" in cookie
        assert server.get("/api/sessions", {"Cookie": cookie.split(";")[0]})[0] == 200

        async def sockets() -> None:
            with pytest.raises(InvalidStatus) as refused:
                async with connect(server.ws, subprotocols=[m.SUBPROTOCOL]):  # type: ignore[list-item]
                    pass
            assert refused.value.response.status_code == 403
            async with client(server, query=f"?token={TOKEN}") as c:
                assert (await c.hello()).role == "operator"

        asyncio.run(sockets())


def test_other_protocol_versions_are_closed_with_a_reason(tmp_path: Path) -> None:
    async def scenario(server: RunningServer) -> None:
        async with connect(server.ws, subprotocols=["workcell.v2"]) as ws:  # type: ignore[list-item]
            first = await ws.recv()
            assert "workcell.v1" in str(first)
            with pytest.raises(ConnectionClosedError) as closed:
                await ws.recv()
        assert closed.value.rcvd is not None
        assert closed.value.rcvd.code == 4000
        assert "protocol mismatch" in closed.value.rcvd.reason
        assert "workcell.v1" in closed.value.rcvd.reason
        async with connect(server.ws) as ws:  # no subprotocol at all
            with pytest.raises(ConnectionClosedError) as closed:
                while True:
                    await ws.recv()
        assert closed.value.rcvd is not None and closed.value.rcvd.code == 4000

    with running_server(tmp_path) as server:
        asyncio.run(scenario(server))


def _raw_get(port: int, path: str) -> int:
    """GET with the path sent exactly as written (no client-side normalisation)."""
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=10)
    connection.putrequest("GET", path, skip_accept_encoding=True)
    connection.endheaders()
    response = connection.getresponse()
    response.read()
    return response.status


def test_static_files_cannot_reach_outside_the_client_folder(tmp_path: Path) -> None:
    dist = tmp_path / "web" / "dist"
    (dist / "assets").mkdir(parents=True)
    (dist / "index.html").write_text("<html>client</html>")
    (dist / "assets" / "app.js").write_text("console.log('hi')")
    (tmp_path / "web" / "secret.txt").write_text("secret")
    (tmp_path / "secret.txt").write_text("secret")
    with running_server(tmp_path, static_dir=dist) as server:
        assert server.get("/") == (200, b"<html>client</html>")
        assert server.get("/assets/app.js")[0] == 200
        for path in (
            "/../secret.txt",
            "/assets/../../secret.txt",
            "/%2e%2e/secret.txt",
            "/%2E%2E/%2E%2E/secret.txt",
            "/assets/%2e%2e%2f%2e%2e%2fsecret.txt",
            "/..%2fsecret.txt",
            "/..%5csecret.txt",
            "/%252e%252e/secret.txt",
            "//etc/passwd",
            "/assets/..%00/secret.txt",
        ):
            assert _raw_get(server.port, path) in (400, 404), path


def test_missing_client_build_says_how_to_build_it(tmp_path: Path) -> None:
    with running_server(tmp_path, static_dir=tmp_path / "nowhere") as server:
        status, body = server.get("/")
        assert status == 503
        assert b"not built" in body and b"set-up" in body
        assert server.get("/app.js")[0] == 404
