"""How uvicorn runs the app: HTTP/1.1 by h11 with a deadline for each request's headers.

uvicorn closes a connection that stays idle after a response (``timeout_keep_alive``), but
that timer is cancelled by any byte that arrives and is never armed before the first
request: a client that connects and sends half a request line, or one header byte every
few seconds, holds its connection (and a file descriptor) for ever. Here every connection
must send a complete request head within :attr:`ServerOptions.header_timeout_s
<workcell.server.options.ServerOptions.header_timeout_s>` of connecting or of the end of
the previous response, however it trickles; then it is closed. Request heads are also
limited to :data:`MAX_HEADER_BYTES`, however they arrive (larger is a 400): h11's own
``max_incomplete_event_size`` only counts a head still incomplete after a read, so a head
that arrives whole in one read (up to 256 KiB) would pass it.
"""

from __future__ import annotations

import asyncio
import re
from typing import Any

import h11
import uvicorn
from uvicorn.protocols.http.h11_impl import H11Protocol

from workcell.server.options import ServerOptions

MAX_HEADER_BYTES = 16 * 1024
"""The largest request head (request line and headers) a client may send."""
KEEP_ALIVE_S = 5.0
"""How long an idle connection is kept after a response (uvicorn's default)."""
WS_MAX_BYTES = 1024 * 1024
"""WebSocket frames above this close the connection (1009); above 64 KiB they get an
Error reply."""
_HEAD_END = re.compile(rb"\n\r?\n")
"""The blank line that ends a request head (h11 accepts bare newlines too)."""


class HeaderDeadlineH11(H11Protocol):
    """uvicorn's h11 protocol with a deadline for each request head (see the module)."""

    header_timeout_s = 10.0

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._deadline: asyncio.TimerHandle | None = None
        self._armed_for: object = None
        """The request scope current when the deadline was armed: a new one means a new
        request head has arrived."""

    def connection_made(self, transport: asyncio.Transport) -> None:  # type: ignore[override]
        super().connection_made(transport)
        self._arm()

    def data_received(self, data: bytes) -> None:
        if self._head_too_large(data):
            self._refuse_head()
            return
        super().data_received(data)
        if self._deadline is not None and self.scope is not self._armed_for:
            self._disarm()

    def on_response_complete(self) -> None:
        scope = self.scope
        super().on_response_complete()
        if self.scope is scope:  # no pipelined request was waiting: wait for the next
            self._arm()

    def connection_lost(self, exc: Exception | None) -> None:
        self._disarm()
        super().connection_lost(exc)

    def _head_too_large(self, data: bytes) -> bool:
        """Whether the request head being received, with ``data``, exceeds the limit."""
        if self.conn.their_state not in (h11.IDLE, h11.DONE):
            return False  # a body, or a protocol switch: the head has been read
        pending, _ = self.conn.trailing_data
        received = pending + data
        end = _HEAD_END.search(received)
        return (end.end() if end else len(received)) > MAX_HEADER_BYTES

    def _refuse_head(self) -> None:
        if self.conn.our_state is h11.IDLE:
            self.send_400_response(f"Request head larger than {MAX_HEADER_BYTES} bytes.")
        else:  # a response to an earlier request is under way: no room for a 400
            self.transport.close()

    def _arm(self) -> None:
        self._disarm()
        if self.transport.is_closing():
            return
        self._armed_for = self.scope
        self._deadline = self.loop.call_later(self.header_timeout_s, self._expired)

    def _disarm(self) -> None:
        if self._deadline is not None:
            self._deadline.cancel()
            self._deadline = None

    def _expired(self) -> None:
        self._deadline = None
        if not self.transport.is_closing():
            self.transport.close()


EVENT_LOOP = "uvloop"
"""The server's asyncio event loop: uvloop (libuv), which uvicorn's standard install also
picks. Against the standard library's loop (and with the State's JSON by orjson) a live
session's input-to-State latency halved up to 8 sessions, its CPU 3-10 % less
(``bench/README.md``, issue 38)."""


def protocol_for(options: ServerOptions) -> type[HeaderDeadlineH11]:
    """The protocol class with ``options``' header deadline."""
    return type(
        "HeaderDeadlineH11",
        (HeaderDeadlineH11,),
        {"header_timeout_s": options.header_timeout_s},
    )


def uvicorn_config(app: Any, options: ServerOptions, **overrides: Any) -> uvicorn.Config:
    """The uvicorn configuration ``workcell serve`` runs ``app`` with (``overrides``:
    more :class:`uvicorn.Config` arguments, such as the TLS files)."""
    settings: dict[str, Any] = {
        "host": options.host,
        "port": options.port,
        "http": protocol_for(options),
        "h11_max_incomplete_event_size": MAX_HEADER_BYTES,
        "timeout_keep_alive": KEEP_ALIVE_S,
        "ws_max_size": WS_MAX_BYTES,
        "log_level": "warning",
        "timeout_graceful_shutdown": 5,
        "ws_per_message_deflate": options.ws_compression,
        "loop": EVENT_LOOP,
    }
    return uvicorn.Config(app, **(settings | overrides))
