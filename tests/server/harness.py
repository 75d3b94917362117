"""A real server on a free localhost port (uvicorn in a thread) and a real WebSocket client."""

from __future__ import annotations

import asyncio
import contextlib
import json
import socket
import threading
import time
import urllib.error
import urllib.request
from collections.abc import Callable, Iterator
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import uvicorn
from websockets.asyncio.client import ClientConnection, connect

from workcell.protocol import messages as m
from workcell.protocol.codec import decode_server, encode
from workcell.protocol.scene import Pose
from workcell.server.app import create_app
from workcell.server.conductor import Conductor
from workcell.server.http_config import uvicorn_config
from workcell.server.options import ServerOptions
from workcell.server.seats import Seats
from workcell.server.session_process import SessionProcess
from workcell.server.session_relay import SessionFactory
from workcell.server.study_desk import StudyDesk
from workcell.server.tls import Certificate
from workcell.study.config import StudyConfig
from workcell.study.invites import invites_path, load_or_create

FAST_SETTINGS: dict[str, Any] = {"task": {"countdown_s": 0.0, "time_limit_s": 60.0}}
"""A practice session that starts at once."""


@dataclass
class RunningServer:
    options: ServerOptions
    seats: Seats
    server: uvicorn.Server
    port: int

    @property
    def conductor(self) -> Conductor:
        """The first seat (the only one of a one-session server)."""
        return self.seats.first

    @property
    def http(self) -> str:
        return f"http://127.0.0.1:{self.port}"

    @property
    def ws(self) -> str:
        return f"ws://127.0.0.1:{self.port}/ws"

    def get(
        self, path: str, headers: dict[str, str] | None = None, method: str = "GET"
    ) -> tuple[int, bytes]:
        """Status and body of a request (errors included)."""
        request = urllib.request.Request(self.http + path, headers=headers or {}, method=method)
        try:
            with urllib.request.urlopen(request, timeout=10) as response:
                return int(response.status), bytes(response.read())
        except urllib.error.HTTPError as error:
            return int(error.code), bytes(error.read())

    def get_json(self, path: str) -> Any:
        status, body = self.get(path)
        assert status == 200, (status, body[:300])
        return json.loads(body)


@contextlib.contextmanager
def running_server(
    tmp_path: Path,
    tls: Certificate | None = None,
    study: StudyConfig | None = None,
    launch: SessionFactory = SessionProcess,
    **overrides: Any,
) -> Iterator[RunningServer]:
    """A server on ``tmp_path/store.sqlite`` whose admission lets every start in (unless
    ``admit_cores`` or ``admit_min_real_time_factor`` is given); with ``study``, running
    it as ``workcell serve --study`` does (its invites beside the store, the admin token
    as the server's); its sessions made by ``launch`` (Ray actors: a RaySessions)."""
    options = replace(ServerOptions(store=tmp_path / "store.sqlite", grace_s=1.0), **overrides)
    admitting = {"admit_cores", "admit_min_real_time_factor", "admission"} & set(overrides)
    if not admitting:  # tests of other things start sessions at will
        options = replace(options, admission=False)
    desk = None
    if study is not None:
        invites = load_or_create(invites_path(options.store, study), study)
        desk = StudyDesk(study, invites, options.store)
        options = replace(options, token=options.token or invites.admin)
    seats = Seats(options, desk, launch)
    config = uvicorn_config(
        create_app(options, seats),
        options,
        ssl_certfile=str(tls.cert_file) if tls else None,
        ssl_keyfile=str(tls.key_file) if tls else None,
    )
    server = uvicorn.Server(config)
    sock = socket.socket()
    sock.bind(("127.0.0.1", 0))
    port = int(sock.getsockname()[1])
    thread = threading.Thread(target=server.run, kwargs={"sockets": [sock]}, daemon=True)
    thread.start()
    deadline = time.monotonic() + 10
    while not server.started:
        assert time.monotonic() < deadline, "server did not start"
        time.sleep(0.01)
    try:
        yield RunningServer(options, seats, server, port)
    finally:
        server.should_exit = True
        thread.join(30)
        sock.close()


class Client:
    """A protocol client over a real WebSocket, keeping every message it receives."""

    def __init__(self, connection: ClientConnection) -> None:
        self.connection = connection
        self.received: list[m.ServerMessage] = []
        self.seq = 0

    async def send(self, message: object) -> None:
        await self.connection.send(encode(message))

    async def send_raw(self, data: str | bytes) -> None:
        await self.connection.send(data)

    async def next(self, timeout: float = 5.0) -> m.ServerMessage:
        text = await asyncio.wait_for(self.connection.recv(), timeout)
        message = decode_server(text)
        self.received.append(message)
        return message

    async def wait_for(
        self, predicate: Callable[[m.ServerMessage], bool], timeout: float = 10.0
    ) -> m.ServerMessage:
        deadline = time.monotonic() + timeout
        while True:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise TimeoutError("no matching message")
            message = await self.next(remaining)
            if predicate(message):
                return message

    async def hello(
        self, role: m.Role = "operator", token: str | None = None, seat: str | None = None
    ) -> m.Welcome:
        await self.send(m.Hello(role=role, resume_token=token, seat=seat))
        welcome = await self.wait_for(lambda x: isinstance(x, m.Welcome))
        assert isinstance(welcome, m.Welcome)
        return welcome

    async def input(
        self,
        left: m.ControllerState | None = None,
        right: m.ControllerState | None = None,
        headset: Pose | None = None,
    ) -> int:
        self.seq += 1
        await self.send(
            m.Input(
                seq=self.seq,
                t_client=time.time(),
                source="xr",
                headset=headset,
                left=left or hand(),
                right=right or hand(),
            )
        )
        return self.seq


def hand(
    pose: Pose | None = (0.0, 1.0, -0.3, 1.0, 0.0, 0.0, 0.0),
    grip: float = 0.0,
    trigger: float = 0.0,
    stick: tuple[float, float] = (0.0, 0.0),
) -> m.ControllerState:
    return m.ControllerState(pose=pose, grip=grip, trigger=trigger, stick=stick, buttons=0)


@contextlib.asynccontextmanager
async def client(server: RunningServer, subprotocol: str = m.SUBPROTOCOL, query: str = "") -> Any:
    async with connect(
        server.ws + query,
        subprotocols=[subprotocol],  # type: ignore[list-item]
        open_timeout=10,
        max_queue=None,  # unread messages must not stall the close handshake
    ) as connection:
        yield Client(connection)


def body_index(scene: m.Scene, name: str) -> int:
    return next(b.index for b in scene.bodies if b.name == name)
