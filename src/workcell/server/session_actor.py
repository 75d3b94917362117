"""Live sessions in Ray actors (``workcell serve --sessions N --ray ADDRESS``): the sessions
of one server spread over a Ray cluster's cores, or over this machine's with ``local``.

A :class:`SessionActor` is a :class:`~workcell.server.session_relay.RelayedSession` whose
child runs in a Ray actor (:class:`~workcell.server.ray_actor.SessionActorBody`, one CPU,
one actor per session) instead of a local process: the same child, the same pipe protocol
over a socket. The actor listens (on 127.0.0.1 for ``local``, else on its node's address)
with a random key for the session, and the server connects: a dead actor then shows as a
refused connection at once, where a server waiting for the actor to call would wait for
the start's whole timeout. When the actor dies (``ray.kill``, its node lost), its session
ends ``error`` with a detail naming how, and the server and other sessions carry on.

Where the actor records: into the session's shard in the server's shard folder when its
node sees that folder (this machine, a shared filesystem), so a killed actor's trial is
recovered ``interrupted`` (``crash_recovered``) by the merge, as a killed process's is;
otherwise into a folder of its own, its shard and media handed back to the server when the
session ends (so a killed actor there loses the session's record). Ray is imported only
when a :class:`RaySessions` is made.
"""

from __future__ import annotations

import logging
import os
import secrets
import threading
from multiprocessing import AuthenticationError
from multiprocessing.connection import Client, Connection
from pathlib import PurePosixPath
from typing import Any

from workcell.closing import Closing
from workcell.errors import WorkcellError
from workcell.record.media_paths import media_dir_for
from workcell.scale.ray_cluster import LOCAL, start_ray
from workcell.server.ray_actor import HandedBack, Placement, SessionActorBody, new_probe, probe_path
from workcell.server.session_listener import SessionListener
from workcell.server.session_relay import (
    KEPT_TO_THE_LAST_FRAMES,
    START_TIMEOUT_S,
    RelayedSession,
    SessionArgs,
)

logger = logging.getLogger(__name__)


class RaySessions(Closing):
    """Makes sessions that run in Ray actors (a :class:`~workcell.server.session_relay.
    SessionFactory`), on the Ray this process is connected to: :meth:`connect` first."""

    def __init__(self, address: str, *, hand_back: bool = False) -> None:
        import ray  # noqa: PLC0415

        self.address = address
        self.hand_back = hand_back
        """Every session records in its actor's own folder and is handed back at its end,
        as on a node without the server's shard folder (tests)."""
        self.actor_class: Any = ray.remote(num_cpus=1)(SessionActorBody)

    @classmethod
    def connect(cls, address: str, sessions: int) -> RaySessions:
        """Start Ray here with a CPU per session (``address`` "local") or connect to the
        cluster at ``address``; :class:`~workcell.scale.ray_cluster.RayError` when neither
        works."""
        start_ray(address, sessions)
        return cls(address)

    @property
    def where(self) -> str:
        return "Ray on this machine" if self.address == LOCAL else f"the Ray at {self.address}"

    def __call__(self, args: SessionArgs, listener: SessionListener) -> SessionActor:
        return SessionActor(args, listener, ray=self)

    def close(self) -> None:
        """Disconnect from Ray (ending any actor still running); stop it if it was started
        here."""
        import ray  # noqa: PLC0415

        ray.shutdown()


class SessionActor(RelayedSession):
    """A session in a Ray actor; start with :meth:`start`, as any relayed session."""

    kind = "Ray actor"

    def __init__(self, args: SessionArgs, listener: SessionListener, *, ray: RaySessions) -> None:
        super().__init__(args, listener)
        self.sessions = ray
        self.actor: Any = None
        """The actor's handle (None before :meth:`start`)."""
        self.placement: Placement | None = None
        """Where the actor runs and records (None before it is up)."""
        self._run: Any = None
        """The actor's run (an ObjectRef of its HandedBack)."""
        self._end: str | None = None
        """How the actor's run ended, once it has."""
        self._reaping = threading.Lock()

    @property
    def pid(self) -> int | None:
        return self.placement.pid if self.placement else None

    def _launch(self) -> Connection:
        import ray  # noqa: PLC0415

        self.actor = self.sessions.actor_class.remote()
        shard, key_file = self.args.store_path, self.args.key_file
        probe = new_probe()
        if not self.sessions.hand_back:
            probe_path(shard).write_bytes(probe)
        authkey = secrets.token_bytes(32)
        try:
            self.placement = ray.get(
                self.actor.prepare.remote(
                    str(shard),
                    probe=probe,
                    key_file=None if key_file is None else str(key_file),
                    key=None if key_file is None else key_file.read_bytes(),
                    loopback=self.sessions.address == LOCAL,
                    authkey=authkey,
                ),
                timeout=START_TIMEOUT_S,
            )
        except ray.exceptions.GetTimeoutError:
            self.kill()
            raise WorkcellError(
                f"the session's Ray actor did not start in {START_TIMEOUT_S:g} s (has "
                f"{self.sessions.where} a CPU free for it?)"
            ) from None
        except ray.exceptions.RayError as error:
            self.kill()
            raise WorkcellError(f"the session's Ray actor did not start ({_why(error)})") from None
        finally:
            probe_path(shard).unlink(missing_ok=True)
        assert self.placement is not None
        self._run = self.actor.run.remote(self.args)
        address = self.placement.address
        try:
            return Client(address, authkey=authkey)
        except (OSError, EOFError, AuthenticationError) as error:
            self.kill()
            raise WorkcellError(
                f"the session's Ray actor on {self.placement.node} could not be reached at "
                f"{address[0]}:{address[1]} ({error})"
            ) from None

    def _reap(self, timeout: float | None) -> None:
        """Wait for the actor's run; keep what it handed back, then let the actor go."""
        if self._run is None:
            return
        import ray  # noqa: PLC0415

        with self._reaping:
            if self._end is not None:
                return
            ready, _ = ray.wait([self._run], timeout=timeout)
            if not ready:
                return
            try:
                handed: HandedBack = ray.get(self._run)
            except ray.exceptions.RayError as error:
                self._end = _why(error)
            else:
                self._end = "its run returned"
                self._keep(handed)
            ray.kill(self.actor)  # its worker and its CPU go back to Ray

    @property
    def running(self) -> bool:
        if self._run is None or self._end is not None:
            return False
        import ray  # noqa: PLC0415

        ready, _ = ray.wait([self._run], timeout=0)
        return not ready

    def kill(self) -> None:
        if self.actor is not None:
            import ray  # noqa: PLC0415

            ray.kill(self.actor)

    def _exit(self) -> str:
        self._reap(0)
        return self._end or "still running"

    def _kept(self) -> str:
        if self.placement is None or self.placement.in_place:
            return KEPT_TO_THE_LAST_FRAMES
        return (
            f"its record was kept on the actor's node ({self.placement.node}) until the "
            "session's end, and is lost"
        )

    def _keep(self, handed: HandedBack) -> None:
        """Write a handed-back shard where the server's merge looks for it: its media
        first, then the shard itself, whole (renamed into place)."""
        if not handed.shard:
            return
        shard = self.args.store_path
        media = media_dir_for(shard)
        for name, data in handed.media:
            relative = PurePosixPath(name)
            if relative.is_absolute() or ".." in relative.parts:
                logger.warning("session %s: media file %r refused", self.session_id, name)
                continue
            target = media.joinpath(*relative.parts)
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(data)
        partial = shard.with_name(shard.name + ".part")
        partial.write_bytes(handed.shard)
        os.replace(partial, shard)


def _why(error: Exception) -> str:
    """Ray's word for why an actor or its call ended, in one line."""
    lines = [line.strip() for line in str(error).splitlines() if line.strip()]
    for line in lines:
        if line.startswith("The actor is dead because "):
            return line.removeprefix("The actor is dead because ").rstrip(".")
    return lines[0] if lines else type(error).__name__
