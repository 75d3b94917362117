"""Host and Origin checks against forged headers, sent by raw clients over a real socket.

A page of another origin (or a DNS-rebound name) must not reach the API or the WebSocket of
a loopback server; token mode keeps working from a LAN address; ``--allow-origin`` admits
a named origin. The browser's side of it is in ``tests/web`` (a real page of another
origin in Chromium).
"""

from __future__ import annotations

import asyncio
import base64
import contextlib
import os
import socket
from pathlib import Path

import pytest
from websockets.asyncio.client import connect
from websockets.exceptions import InvalidStatus

from tests.server.harness import FAST_SETTINGS, RunningServer, running_server
from workcell.errors import ConfigError
from workcell.protocol import messages as m
from workcell.protocol.codec import encode
from workcell.server.options import ServerOptions

TOKEN = "s3cret-token-for-tests"


def raw_request(port: int, head: str) -> tuple[int, str]:
    """Send ``head`` (a request without its final blank line) on a new socket; the status
    code and the reason text of the answer."""
    with socket.create_connection(("127.0.0.1", port), timeout=10) as sock:
        sock.sendall(head.encode("latin-1") + b"\r\n\r\n")
        answer = b""
        while b"\r\n\r\n" not in answer:
            chunk = sock.recv(4096)
            if not chunk:
                break
            answer += chunk
        if b"\r\n\r\n" in answer and not answer.startswith(b"HTTP/1.1 101"):
            sock.settimeout(2.0)
            with contextlib.suppress(TimeoutError):
                while chunk := sock.recv(4096):  # the body, until the server closes
                    answer += chunk
    status_line = answer.split(b"\r\n", 1)[0].decode("latin-1")
    return int(status_line.split()[1]), answer.decode("latin-1", "replace")


def http_get(port: int, path: str, host: str | None, extra: str = "") -> int:
    lines = [f"GET {path} HTTP/1.1"]
    if host is not None:
        lines.append(f"Host: {host}")
    lines.append("Connection: close")
    if extra:
        lines.append(extra)
    return raw_request(port, "\r\n".join(lines))[0]


def ws_handshake(
    port: int, host: str, origin: str | None, query: str = "", subprotocol: str = m.SUBPROTOCOL
) -> int:
    """A WebSocket opening handshake by hand; 101 when the server accepts it."""
    key = base64.b64encode(os.urandom(16)).decode()
    lines = [
        f"GET /ws{query} HTTP/1.1",
        f"Host: {host}",
        "Upgrade: websocket",
        "Connection: Upgrade",
        f"Sec-WebSocket-Key: {key}",
        "Sec-WebSocket-Version: 13",
        f"Sec-WebSocket-Protocol: {subprotocol}",
    ]
    if origin is not None:
        lines.append(f"Origin: {origin}")
    return raw_request(port, "\r\n".join(lines))[0]


def test_loopback_server_refuses_a_foreign_host(tmp_path: Path) -> None:
    with running_server(tmp_path) as server:
        port = server.port
        for host in (
            f"127.0.0.1:{port}",
            f"localhost:{port}",
            f"LOCALHOST:{port}",
            f"[::1]:{port}",
            "127.0.0.1",
            f"127.0.0.2:{port}",
            "localhost:9000",  # a port forward (adb reverse tcp:9000 tcp:PORT, ssh -L)
        ):
            assert http_get(port, "/api/sessions", host) == 200, host
        for host in (
            f"evil.example:{port}",  # DNS rebinding: evil.example now resolves to 127.0.0.1
            "evil.example",
            f"127.0.0.1.evil.example:{port}",
            f"localhost@evil.example:{port}",
            f"localhost.evil.example:{port}",
            f"0.0.0.0:{port}",
            f"192.168.1.20:{port}",
            "",
        ):
            assert http_get(port, "/api/sessions", host) == 403, host
            assert ws_handshake(port, host, None) == 403, host
        assert http_get(port, "/", None, "") == 400  # HTTP/1.1 without a Host at all
        status, answer = raw_request(port, "GET /api/defaults HTTP/1.0")  # no Host
        assert status == 403 and "is not a name this server answers for" in answer


def test_websocket_from_another_origin_is_refused_before_it_can_act(tmp_path: Path) -> None:
    with running_server(tmp_path) as server:
        port = server.port
        own = f"127.0.0.1:{port}"
        for origin in (
            "http://evil.example",
            "http://localhost:18009",  # another local page (another port is another origin)
            f"http://localhost:{port}",  # another name: another origin
            f"https://127.0.0.1:{port}",  # another scheme
            "null",  # a sandboxed frame or a file: page
            "garbage",
            f"http://127.0.0.1:{port}/path",
        ):
            assert ws_handshake(port, own, origin) == 403, origin
        # DNS rebinding: the page's origin and the Host agree, but the Host is foreign
        assert ws_handshake(port, f"evil.example:{port}", f"http://evil.example:{port}") == 403
        assert ws_handshake(port, own, f"http://{own}") == 101  # the server's own page
        assert ws_handshake(port, own, f"HTTP://{own.upper()}") == 101
        assert ws_handshake(port, own, None) == 101  # not a browser: no Origin
        asyncio.run(_cannot_drive(server, "http://evil.example"))
        assert server.conductor.sessions_started == 0
        assert not server.options.store.exists()  # nothing was recorded


async def _cannot_drive(server: RunningServer, origin: str) -> None:
    """A client forging ``origin`` tries to become operator and start a session."""
    with pytest.raises(InvalidStatus) as refused:
        async with connect(
            server.ws,
            origin=origin,  # type: ignore[arg-type]
            subprotocols=[m.SUBPROTOCOL],  # type: ignore[list-item]
        ) as ws:
            await ws.send(encode(m.Hello(role="operator")))
            await ws.send(encode(m.StartSession(settings=FAST_SETTINGS)))
            await ws.recv()
    assert refused.value.response.status_code == 403


def test_allow_origin_admits_a_named_origin(tmp_path: Path) -> None:
    allowed = "http://localhost:18009"
    with running_server(tmp_path, allow_origins=(allowed, "https://proxy.example")) as server:
        port = server.port
        assert ws_handshake(port, f"127.0.0.1:{port}", allowed) == 101
        assert ws_handshake(port, f"127.0.0.1:{port}", "http://localhost:18010") == 403
        # its host is a name the server answers for (a reverse proxy that keeps the Host)
        assert http_get(port, "/api/defaults", "proxy.example") == 200
        assert http_get(port, "/api/defaults", "other.example") == 403


def test_token_mode_answers_a_lan_address_and_still_checks_the_origin(tmp_path: Path) -> None:
    lan = "192.168.1.20"
    with running_server(tmp_path, host="0.0.0.0", token=TOKEN) as server:
        port = server.port
        query = f"?token={TOKEN}"
        assert http_get(port, f"/api/sessions{query}", f"{lan}:{port}") == 200
        assert http_get(port, "/api/sessions", f"{lan}:{port}") == 401  # the token protects
        assert ws_handshake(port, f"{lan}:{port}", f"http://{lan}:{port}", query) == 101
        assert ws_handshake(port, f"{lan}:{port}", None, query) == 101
        # a page of another port on the same host would send the token cookie along
        cookie_bearer = f"{lan}:{port}"
        assert ws_handshake(port, cookie_bearer, f"http://{lan}:8080", query) == 403
        assert ws_handshake(port, cookie_bearer, "http://evil.example", query) == 403


def test_allow_origin_values_are_checked() -> None:
    with pytest.raises(ConfigError) as refused:
        ServerOptions(allow_origins=("localhost:5173", "http://a.example/x", "ftp://b.example"))
    assert len(refused.value.problems) == 3
    assert all("must be an origin, scheme://host[:port]" in p for p in refused.value.problems)
    ServerOptions(allow_origins=("http://localhost:5173", "https://[::1]:8443"))
