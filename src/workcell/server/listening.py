"""The socket ``workcell serve`` listens on, bound before anything is printed, so that a
port another program holds is one error line (exit 2) and never a link that opens nothing."""

from __future__ import annotations

import errno
import socket

from workcell.errors import WorkcellError

BACKLOG = 2048
"""Connections the kernel queues until the server accepts them (uvicorn's default)."""


class ListenError(WorkcellError):
    """The server cannot listen on the host and port it was given."""


def listening_socket(host: str, port: int) -> socket.socket:
    """A socket bound to ``host:port`` and listening (connections queue until the server
    takes them); ListenError naming the port and what to do when it cannot be."""
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    sock = socket.socket(family, socket.SOCK_STREAM)
    try:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        sock.bind((host, port))
        sock.listen(BACKLOG)
    except OSError as error:
        sock.close()
        raise ListenError(_reason(host, port, error)) from None
    sock.set_inheritable(True)
    return sock


def _reason(host: str, port: int, error: OSError) -> str:
    where = f"{host}:{port}"
    if error.errno == errno.EADDRINUSE:
        return (
            f"--port = {port}: {where} is already in use by another program (another "
            "workcell serve?); stop it or choose a free port with --port"
        )
    if error.errno in (errno.EACCES, errno.EPERM):
        return (
            f"--port = {port}: not allowed to listen on {where} (ports below 1024 need "
            "privileges); choose a port of 1024 or above with --port"
        )
    if error.errno == errno.EADDRNOTAVAIL:
        return (
            f"--host = {host}: not an address of this machine; give one of its addresses, "
            "127.0.0.1 or 0.0.0.0 (every address)"
        )
    return f"--host = {host}, --port = {port}: cannot listen on {where} ({error.strerror})"
