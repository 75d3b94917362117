"""The ASGI application: pages, JSON API and the WebSocket, behind the Host and Origin
checks (:mod:`workcell.server.origin`) and the token check (a study's invites among the
tokens: :mod:`workcell.server.auth`)."""

from __future__ import annotations

import contextlib
from collections.abc import AsyncIterator

from starlette.applications import Starlette
from starlette.middleware import Middleware
from starlette.routing import Mount, Route, WebSocketRoute
from starlette.websockets import WebSocket

from workcell.server.auth import ADMIN, Principal, TokenAuth
from workcell.server.downloads import download_routes
from workcell.server.http_api import routes
from workcell.server.options import ServerOptions, is_loopback
from workcell.server.origin import OriginGuard, allowed_origins
from workcell.server.seats import Seats
from workcell.server.static import ClientFiles, index_route
from workcell.server.study_api import study_routes
from workcell.server.websocket import serve_client


def accepted_tokens(options: ServerOptions, seats: Seats) -> dict[str, Principal] | None:
    """The tokens the server accepts and who holds each (None: no token needed)."""
    if options.token is None and seats.desk is None:
        return None
    tokens = seats.desk.tokens() if seats.desk is not None else {}
    return tokens | ({options.token: ADMIN} if options.token else {})


def create_app(options: ServerOptions, seats: Seats | None = None) -> Starlette:
    """The app; its lifespan ends the running sessions (``application_quit``) on shutdown."""
    seats = seats or Seats(options)

    async def ws(websocket: WebSocket) -> None:
        await serve_client(websocket, seats)

    @contextlib.asynccontextmanager
    async def lifespan(app: Starlette) -> AsyncIterator[None]:
        yield
        await seats.shutdown()
        seats.close_clients()

    app = Starlette(
        routes=[
            Route("/", index_route(options.static_dir)),
            *routes(seats),
            *study_routes(seats),
            *download_routes(seats),
            WebSocketRoute("/ws", ws),
            Mount("/", ClientFiles(options.static_dir)),
        ],
        middleware=[
            Middleware(
                OriginGuard,
                check_host=is_loopback(options.host),
                bound_host=options.host,
                allowed=allowed_origins(options.allow_origins),
            ),
            Middleware(TokenAuth, tokens=accepted_tokens(options, seats), secure=options.tls),
        ],
        lifespan=lifespan,
    )
    app.state.seats = seats
    return app
