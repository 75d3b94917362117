"""Half-sent requests are not held open: every connection must deliver a complete request
head within the header deadline, however it trickles (raw sockets, a real server)."""

from __future__ import annotations

import asyncio
import socket
import time
from pathlib import Path

from tests.server.harness import client, running_server
from workcell.protocol import messages as m
from workcell.server.options import ServerOptions

DEADLINE_S = 0.5
SLACK_S = 3.0
"""How long past the deadline a connection may take to be closed on a loaded machine."""


def closed_by_server(sock: socket.socket, within_s: float) -> bool:
    """True when the server closes ``sock`` (reads reach the end) within ``within_s``."""
    sock.settimeout(within_s)
    end = time.monotonic() + within_s
    try:
        while time.monotonic() < end:
            if sock.recv(4096) == b"":
                return True
    except TimeoutError:
        return False
    except ConnectionResetError:
        return True
    return False


def read_response(sock: socket.socket) -> bytes:
    """One whole response (its head and its Content-Length body); returns the head."""
    data = b""
    while b"\r\n\r\n" not in data:
        chunk = sock.recv(4096)
        assert chunk, "the server closed the connection"
        data += chunk
    head, body = data.split(b"\r\n\r\n", 1)
    length = next(
        int(line.split(b":")[1])
        for line in head.split(b"\r\n")
        if line.lower().startswith(b"content-length")
    )
    while len(body) < length:
        body += sock.recv(65536)
    return head


def test_half_sent_requests_are_closed_after_the_header_deadline(tmp_path: Path) -> None:
    with running_server(tmp_path, header_timeout_s=DEADLINE_S) as server:
        silent, partial = [], []
        for _ in range(20):
            silent.append(socket.create_connection(("127.0.0.1", server.port)))
            sock = socket.create_connection(("127.0.0.1", server.port))
            sock.sendall(b"GET /api/defaults HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow")
            partial.append(sock)
        started = time.monotonic()
        try:
            for sock in silent + partial:
                assert closed_by_server(sock, DEADLINE_S + SLACK_S)
            assert time.monotonic() - started < DEADLINE_S + SLACK_S
        finally:
            for sock in silent + partial:
                sock.close()
        # the server answers others all along
        assert server.get("/api/defaults")[0] == 200


def test_a_trickling_client_is_closed_although_it_keeps_sending(tmp_path: Path) -> None:
    with running_server(tmp_path, header_timeout_s=DEADLINE_S) as server:
        head = b"GET /api/defaults HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Padding: " + b"a" * 200
        with socket.create_connection(("127.0.0.1", server.port)) as sock:
            started = time.monotonic()
            closed_after = None
            for byte in head:
                try:
                    sock.sendall(bytes([byte]))
                except OSError:
                    closed_after = time.monotonic() - started
                    break
                if closed_by_server(sock, 0.05):
                    closed_after = time.monotonic() - started
                    break
            assert closed_after is not None, "the trickling connection was held open"
            assert DEADLINE_S * 0.9 <= closed_after < DEADLINE_S + SLACK_S


def test_an_idle_keep_alive_connection_and_a_body_trickle_are_closed(tmp_path: Path) -> None:
    with running_server(tmp_path, header_timeout_s=DEADLINE_S) as server:
        with socket.create_connection(("127.0.0.1", server.port)) as sock:
            sock.sendall(b"GET /api/defaults HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n")
            assert sock.recv(64).startswith(b"HTTP/1.1 200")
            assert closed_by_server(sock, DEADLINE_S + SLACK_S)
        with socket.create_connection(("127.0.0.1", server.port)) as sock:
            sock.sendall(
                b"GET /api/defaults HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: 100000\r\n\r\n"
            )
            assert sock.recv(64).startswith(b"HTTP/1.1 200")  # answered; the body trickles
            started = time.monotonic()
            closed = False
            while time.monotonic() - started < DEADLINE_S + SLACK_S and not closed:
                try:
                    sock.sendall(b"x")
                except OSError:
                    break
                closed = closed_by_server(sock, 0.05)
            assert time.monotonic() - started < DEADLINE_S + SLACK_S


def test_requests_and_websockets_within_the_deadline_are_served(tmp_path: Path) -> None:
    with running_server(tmp_path, header_timeout_s=DEADLINE_S) as server:
        with socket.create_connection(("127.0.0.1", server.port)) as sock:
            for part in (b"GET /api/defaults HTTP/1.1\r\n", b"Host: 127.0.0.1\r\n", b"\r\n"):
                sock.sendall(part)
                time.sleep(DEADLINE_S / 5)
            assert read_response(sock).startswith(b"HTTP/1.1 200")
            sock.sendall(b"GET /api/sessions HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n")  # kept alive
            assert read_response(sock).startswith(b"HTTP/1.1 200")

        async def quiet_websocket() -> None:
            async with client(server) as c:
                await c.hello("spectator")
                await asyncio.sleep(DEADLINE_S * 3)  # an open socket has no header deadline
                await c.send(m.Ping(t_client=1.0))
                await c.wait_for(lambda x: isinstance(x, m.Pong))

        asyncio.run(quiet_websocket())


def test_the_default_header_deadline() -> None:
    assert ServerOptions().header_timeout_s == 10.0
