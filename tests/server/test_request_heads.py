"""Request heads are limited to MAX_HEADER_BYTES however they arrive: in one write, in
pieces, or followed by a body (raw sockets, a real server)."""

from __future__ import annotations

import socket
from pathlib import Path

import pytest

from tests.server.harness import running_server
from workcell.server.http_config import MAX_HEADER_BYTES


def request_head(size: int) -> bytes:
    """A GET of /api/defaults whose head (request line to blank line) is ``size`` bytes."""
    start = b"GET /api/defaults HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Padding: "
    end = b"\r\n\r\n"
    return start + b"a" * (size - len(start) - len(end)) + end


def status_of(port: int, pieces: list[bytes]) -> bytes:
    """The status line the server answers ``pieces`` (sent one after another) with."""
    with socket.create_connection(("127.0.0.1", port)) as sock:
        sock.settimeout(10)
        try:
            for piece in pieces:
                sock.sendall(piece)
        except OSError:  # the server may close while the rest is being sent
            pass
        data = b""
        while b"\r\n" not in data:
            chunk = sock.recv(4096)
            if not chunk:
                break
            data += chunk
        return data.split(b"\r\n", 1)[0]


@pytest.mark.parametrize("size", [MAX_HEADER_BYTES + 1, 64 * 1024, 128 * 1024, 200 * 1024])
def test_a_head_over_the_limit_in_one_write_gets_400(tmp_path: Path, size: int) -> None:
    with running_server(tmp_path) as server:
        assert status_of(server.port, [request_head(size)]) == b"HTTP/1.1 400 Bad Request"
        assert server.get("/api/defaults")[0] == 200


def test_a_head_over_the_limit_in_pieces_gets_400(tmp_path: Path) -> None:
    head = request_head(MAX_HEADER_BYTES + 100)
    pieces = [head[i : i + 1000] for i in range(0, len(head), 1000)]
    with running_server(tmp_path) as server:
        assert status_of(server.port, pieces) == b"HTTP/1.1 400 Bad Request"


def test_a_head_at_the_limit_is_served_also_with_a_body_in_the_same_write(
    tmp_path: Path,
) -> None:
    with running_server(tmp_path) as server:
        assert status_of(server.port, [request_head(MAX_HEADER_BYTES)]) == b"HTTP/1.1 200 OK"
        body = b"x" * (4 * MAX_HEADER_BYTES)
        head = b"GET /api/defaults HTTP/1.1\r\nHost: 127.0.0.1\r\n"
        head += b"Content-Length: %d\r\n\r\n" % len(body)
        assert status_of(server.port, [head + body]) == b"HTTP/1.1 200 OK"
