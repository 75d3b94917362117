"""The Ray actor a live session runs in (``workcell serve --ray``): the same child a
session's process runs (:func:`~workcell.server.session_child.run_child`), at the end of a
socket the server connects to instead of a fork server's pipe.

:meth:`SessionActorBody.prepare` decides where the session records. When the server's
shard folder is on this node (the same machine, or a filesystem the nodes share: the
server leaves a probe file there for the actor to find), the session records straight into
its shard there, so a killed actor leaves its trial open for the merge to recover, as a
killed process does. Otherwise it records into a temporary folder of its own and
:meth:`SessionActorBody.run` hands the shard's bytes and its media files back when the
session ends. The class is made a Ray actor by
:class:`~workcell.server.session_actor.RaySessions`; nothing here imports Ray.
"""

from __future__ import annotations

import contextlib
import dataclasses
import os
import secrets
import shutil
import socket
import tempfile
import threading
from dataclasses import dataclass
from multiprocessing.connection import Connection, Listener
from pathlib import Path

from workcell.record.media_paths import media_dir_for
from workcell.server.session_child import run_child
from workcell.server.session_relay import SessionArgs

HANG_UP_TIMEOUT_S = 10.0
"""How long the actor waits for the server to read the session's last words."""


@dataclass(frozen=True)
class Placement:
    """Where the actor runs and records, and where the server reaches it."""

    pid: int
    node: str
    """The IP address of the actor's node."""
    address: tuple[str, int]
    in_place: bool
    """The session records into the server's shard itself (else: handed back at its end)."""


@dataclass(frozen=True)
class HandedBack:
    """What the actor's run returns: nothing when it recorded in place; else the shard's
    bytes and its media files (path under the shard's media folder, bytes)."""

    shard: bytes = b""
    media: tuple[tuple[str, bytes], ...] = ()


class SessionActorBody:
    """One session: :meth:`prepare`, then :meth:`run` (once)."""

    def __init__(self) -> None:
        self._listener: Listener | None = None
        self._folder: Path | None = None
        self._store: Path | None = None
        self._in_place = False
        self._key_file: Path | None = None

    def prepare(
        self,
        shard: str,
        *,
        probe: bytes,
        key_file: str | None,
        key: bytes | None,
        loopback: bool,
        authkey: bytes,
    ) -> Placement:
        """Choose where to record (``shard`` where the probe file beside it holds
        ``probe``) and open the socket the server connects to (on 127.0.0.1 when
        ``loopback``, else on this node's address), which it must answer with ``authkey``."""
        import ray  # noqa: PLC0415 - only ever run by Ray, in a worker

        path = Path(shard)
        folder = Path(tempfile.mkdtemp(prefix="workcell-session-"))
        self._folder = folder
        self._in_place = in_place = _holds(probe_path(path), probe)
        self._store = path if in_place else folder / path.name
        if key_file is not None and key is not None:  # the server's key file, or a copy
            self._key_file = Path(key_file)
            if not _holds(self._key_file, key):
                self._key_file = folder / "key"
                self._key_file.touch(0o600)
                self._key_file.write_bytes(key)
        node: str = ray.util.get_node_ip_address()  # type: ignore[no-untyped-call]
        self._listener = Listener(("127.0.0.1" if loopback else node, 0), authkey=authkey)
        address = self._listener.address
        assert isinstance(address, tuple)
        return Placement(os.getpid(), node, (str(address[0]), int(address[1])), in_place)

    def run(self, args: SessionArgs) -> HandedBack:
        """Wait for the server, run the session until it ends, then hand it back."""
        assert self._listener is not None and self._store is not None and self._folder
        with self._listener:
            conn = self._listener.accept()
        args = dataclasses.replace(args, store_path=self._store, key_file=self._key_file)
        try:
            commands = run_child(conn, args)
            _hang_up(conn, commands)
            if self._in_place:
                return HandedBack()
            return HandedBack(
                self._store.read_bytes() if self._store.is_file() else b"",
                _media_files(media_dir_for(self._store)),
            )
        finally:
            shutil.rmtree(self._folder, ignore_errors=True)


def probe_path(shard: Path) -> Path:
    """The file the server leaves beside a shard for its actor to find (named after the
    shard, so a merge's clean-up removes any left behind)."""
    return shard.with_name(shard.name + ".probe")


def new_probe() -> bytes:
    return secrets.token_bytes(16)


def _holds(path: Path, content: bytes) -> bool:
    try:
        return path.read_bytes() == content
    except OSError:
        return False


def _hang_up(conn: Connection, commands: threading.Thread | None) -> None:
    """Close the socket once the server has read everything: say no more (the server then
    reads to the end and closes its side), wait for the thread obeying the server to see
    that, then close. Closing at once could reset the connection under unread data."""
    with contextlib.suppress(OSError):
        sock = socket.socket(fileno=conn.fileno())
        try:
            sock.shutdown(socket.SHUT_WR)
        finally:
            sock.detach()  # the connection still owns the descriptor
    if commands is not None:
        commands.join(HANG_UP_TIMEOUT_S)
    conn.close()


def _media_files(folder: Path) -> tuple[tuple[str, bytes], ...]:
    if not folder.is_dir():
        return ()
    files = sorted(p for p in folder.rglob("*") if p.is_file())
    return tuple((p.relative_to(folder).as_posix(), p.read_bytes()) for p in files)
