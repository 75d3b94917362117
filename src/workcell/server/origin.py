"""Host and Origin checks: what a browser can be made to send is refused (pure ASGI).

Two attacks reach a server on 127.0.0.1 through the user's own browser, and the checks
follow what Jupyter and similar local servers do against them:

- **DNS rebinding**: a page of ``evil.example`` has its name re-resolved to 127.0.0.1 and
  reads this server as its own origin. Its requests carry ``Host: evil.example:PORT``.
  On loopback (no token) every HTTP and WebSocket request must name a host this server
  answers for: ``localhost``, a loopback address (``127.0.0.1``, ``[::1]``, ...), the host
  it was bound to, or the host of an ``--allow-origin``; any port (a port forward, such as
  ``adb reverse`` or ``ssh -L``, changes it). Otherwise HTTP 403.
- **Cross-site WebSocket**: any page may open ``ws://127.0.0.1:PORT/ws`` (browsers apply no
  same-origin policy to WebSockets) and would become the operator. A browser always sends
  the page's ``Origin``; the handshake is refused (HTTP 403, before the socket is accepted)
  unless that origin is the server's own (its scheme and ``host:port`` are those the
  request was sent to) or one given with ``--allow-origin``. Clients that are not browsers
  send no Origin and are let through (they could forge any header anyway).
- **Cross-site requests**: any page may send a POST (a form, ``fetch`` without CORS) to
  the server, with its cookie when the page is on another port of the same host
  (SameSite=Strict counts ports as the same site). Every HTTP request that can change
  something (any method but GET, HEAD and OPTIONS) has its Origin checked as the
  WebSocket's handshake is.

With a token (a non-loopback ``--host``) the Host is the machine's LAN name or address,
which cannot be listed in advance: the token protects HTTP, and the Origin check still
protects the WebSocket and the state-changing requests (the token cookie would be sent
along by a page of another port of the same host).
"""

from __future__ import annotations

import ipaddress
import re
import urllib.parse
from dataclasses import dataclass

from starlette.types import ASGIApp, Receive, Scope, Send

from workcell.errors import ConfigError

_HOST = re.compile(r"^(?P<name>\[[0-9a-fA-F:.]+\]|[^\s:\[\]/@]+)(?::(?P<port>\d{1,5}))?$")
_DEFAULT_PORTS = {"http": 80, "https": 443}
SAFE_METHODS = frozenset({"GET", "HEAD", "OPTIONS"})
"""HTTP methods that change nothing here: every other one has its Origin checked."""


@dataclass(frozen=True)
class Origin:
    """A web origin: scheme, host name (lower case, IPv6 without brackets) and port."""

    scheme: str
    host: str
    port: int

    @classmethod
    def parse(cls, text: str) -> Origin | None:
        """The origin of ``scheme://host[:port]`` (nothing after it), else None."""
        try:
            parts = urllib.parse.urlsplit(text.strip())
            port = parts.port
        except ValueError:
            return None
        scheme = parts.scheme.lower()
        if scheme not in _DEFAULT_PORTS or not parts.hostname or parts.username is not None:
            return None
        if parts.path not in ("", "/") or parts.query or parts.fragment:
            return None
        return cls(scheme, parts.hostname.lower(), port or _DEFAULT_PORTS[scheme])


def allowed_origins(values: tuple[str, ...]) -> tuple[Origin, ...]:
    """The ``--allow-origin`` values as origins; a ConfigError naming each bad one."""
    origins = [Origin.parse(value) for value in values]
    problems = [
        f"--allow-origin = {value!r}: must be an origin, scheme://host[:port] (http or "
        "https, no path), e.g. http://localhost:5173"
        for value, origin in zip(values, origins, strict=True)
        if origin is None
    ]
    if problems:
        raise ConfigError(problems)
    return tuple(o for o in origins if o is not None)


def split_host(header: str) -> tuple[str, int | None] | None:
    """A Host header's name (lower case, IPv6 without brackets) and port, else None."""
    match = _HOST.match(header.strip())
    if match is None:
        return None
    name = match["name"].lower().strip("[]")
    port = int(match["port"]) if match["port"] else None
    return name, port


def is_loopback_name(name: str) -> bool:
    if name == "localhost":
        return True
    try:
        return ipaddress.ip_address(name).is_loopback
    except ValueError:
        return False


class OriginGuard:
    """Refuses requests with a foreign Host (``check_host``), and WebSockets and
    state-changing requests from a foreign Origin; see the module docstring."""

    def __init__(
        self, app: ASGIApp, *, check_host: bool, bound_host: str, allowed: tuple[Origin, ...]
    ) -> None:
        self.app = app
        self.check_host = check_host
        self.allowed = frozenset(allowed)
        self.host_names = frozenset({bound_host.lower().strip("[]"), *(o.host for o in allowed)})

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] not in ("http", "websocket"):
            await self.app(scope, receive, send)
            return
        headers = {k.decode("latin-1").lower(): v.decode("latin-1") for k, v in scope["headers"]}
        host = headers.get("host", "")
        if self.check_host and not self.host_allowed(host):
            await _refuse(scope, send, f"Host {host[:80]!r} is not a name this server answers for")
            return
        origin = headers.get("origin")
        if origin is not None and self.acts(scope):
            secure = scope.get("scheme") in ("https", "wss")
            if not self.origin_allowed(origin, host, secure=secure):
                what = "open this socket"
                if scope["type"] == "http":
                    what = f"send {str(scope.get('method'))[:20]} requests here"
                await _refuse(scope, send, f"Origin {origin[:80]!r} may not {what}")
                return
        await self.app(scope, receive, send)

    @staticmethod
    def acts(scope: Scope) -> bool:
        """The request can change something: a WebSocket, or HTTP beyond GET, HEAD and
        OPTIONS (what a page of another origin could send with the user's cookie)."""
        return scope["type"] == "websocket" or scope.get("method") not in SAFE_METHODS

    def host_allowed(self, header: str) -> bool:
        parsed = split_host(header)
        return parsed is not None and (is_loopback_name(parsed[0]) or parsed[0] in self.host_names)

    def origin_allowed(self, header: str, host: str, *, secure: bool) -> bool:
        origin = Origin.parse(header)
        if origin is None:  # "null" (a sandboxed or file: page), or garbage
            return False
        if origin in self.allowed:
            return True
        target = split_host(host)
        scheme = "https" if secure else "http"
        if target is None or origin.scheme != scheme:
            return False
        name, port = target
        return (origin.host, origin.port) == (name, port or _DEFAULT_PORTS[scheme])


async def _refuse(scope: Scope, send: Send, why: str) -> None:
    """HTTP 403; a WebSocket handshake is refused before it is accepted (also 403)."""
    if scope["type"] == "websocket":
        await send({"type": "websocket.close", "code": 4403, "reason": why[:120]})
        return
    body = f"403 Forbidden: {why}.\n".encode()
    await send(
        {
            "type": "http.response.start",
            "status": 403,
            "headers": [
                (b"content-type", b"text/plain; charset=utf-8"),
                (b"content-length", str(len(body)).encode()),
            ],
        }
    )
    await send({"type": "http.response.body", "body": body})
