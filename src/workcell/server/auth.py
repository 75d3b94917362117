"""Token authentication of every HTTP and WebSocket request (pure ASGI middleware).

The token may come as ``?token=``, as ``Authorization: Bearer``, or as the cookie this
middleware sets on any response to a request that carried a valid token (so the page's
own scripts, styles and API calls are let in). Without a valid token: HTTP 401, and a
WebSocket handshake is refused (HTTP 403) before it is accepted.

Each token names who holds it (a :class:`Principal`): the server's token and a study's
admin token open everything; a study participant's invite opens the page, their own
session and their own progress, nothing else (HTTP 403 for the rest), and only until it
expires (then HTTP 401 saying so; a connection made before stays). The principal rides
along in the request's scope (:func:`principal_of`).
"""

from __future__ import annotations

import secrets
import time
import urllib.parse
from collections.abc import Mapping
from dataclasses import dataclass
from http.cookies import SimpleCookie

from starlette.types import ASGIApp, Message, Receive, Scope, Send

from workcell.study.invites import minute_utc

COOKIE = "workcell_token"
SCOPE_KEY = "workcell.principal"
PARTICIPANT_API = ("/api/defaults", "/api/settings/hints", "/api/study/me")
"""The API paths a participant's invite opens (besides the page, its files and ``/ws``)."""


@dataclass(frozen=True)
class Principal:
    """Who a request comes from: ``participant`` None is the server's operator or a study's
    admin (everything allowed); otherwise the study participant whose invite it carries."""

    participant: str | None = None
    expires: float | None = None
    """When the token stops opening anything (Unix seconds; None: never)."""

    @property
    def is_admin(self) -> bool:
        return self.participant is None

    def expired(self, now: float) -> bool:
        return self.expires is not None and now >= self.expires


ADMIN = Principal()


def principal_of(scope: Scope) -> Principal:
    """Who sent the request (the admin when the server needs no token)."""
    found = scope.get(SCOPE_KEY)
    return found if isinstance(found, Principal) else ADMIN


def participant_may(path: str) -> bool:
    """Whether a participant's invite opens ``path``."""
    return not path.startswith("/api/") or path in PARTICIPANT_API


def _supplied(scope: Scope) -> tuple[str | None, bool]:
    """The token the request carries and whether it came explicitly (query or header)."""
    query = urllib.parse.parse_qs(scope.get("query_string", b"").decode("latin-1"))
    if query.get("token"):
        return query["token"][0], True
    headers = {k.decode("latin-1").lower(): v.decode("latin-1") for k, v in scope["headers"]}
    authorization = headers.get("authorization", "")
    if authorization.lower().startswith("bearer "):
        return authorization[7:].strip(), True
    cookie = SimpleCookie()
    try:
        cookie.load(headers.get("cookie", ""))
    except Exception:  # a malformed cookie header is no token
        return None, False
    morsel = cookie.get(COOKIE)
    return (morsel.value if morsel else None), False


class TokenAuth:
    """``tokens`` maps each accepted token to its holder; None lets everyone in (a
    loopback server without a token)."""

    def __init__(self, app: ASGIApp, tokens: Mapping[str, Principal] | None, secure: bool) -> None:
        self.app = app
        self.tokens = dict(tokens) if tokens is not None else None
        self.secure = secure

    def holder(self, supplied: str | None) -> Principal | None:
        """The principal ``supplied`` names (None: not a valid token)."""
        if self.tokens is None:
            return ADMIN
        if supplied is None:
            return None
        found = None
        for token, principal in self.tokens.items():  # compare with every token alike
            if secrets.compare_digest(supplied.encode(), token.encode()):
                found = principal
        return found

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] not in ("http", "websocket") or self.tokens is None:
            await self.app(scope, receive, send)
            return
        supplied, explicit = _supplied(scope)
        principal = self.holder(supplied)
        if principal is None:
            await self._refuse(scope, send)
            return
        if principal.expired(time.time()):
            await self._expired(scope, send, principal)
            return
        if not principal.is_admin and not participant_may(scope.get("path", "")):
            await self._forbid(scope, send)
            return
        scope[SCOPE_KEY] = principal
        if scope["type"] == "http" and explicit and supplied is not None:
            send = self._with_cookie(send, supplied)
        await self.app(scope, receive, send)

    def _with_cookie(self, send: Send, token: str) -> Send:
        flags = "; HttpOnly; SameSite=Strict; Path=/" + ("; Secure" if self.secure else "")
        value = f"{COOKIE}={token}{flags}".encode("latin-1")

        async def sending(message: Message) -> None:
            if message["type"] == "http.response.start":
                message = {**message, "headers": [*message["headers"], (b"set-cookie", value)]}
            await send(message)

        return sending

    async def _refuse(self, scope: Scope, send: Send) -> None:
        body = (
            b"401 Unauthorized: this server needs its access token. Open the URL that "
            b"`workcell serve` printed (it ends with ?token=...).\n"
        )
        await _answer(scope, send, 401, body, ws_code=4401, ws_reason="token required")

    async def _expired(self, scope: Scope, send: Send, principal: Principal) -> None:
        assert principal.expires is not None
        when = minute_utc(principal.expires)
        body = (
            f"401 Unauthorized: the invite of {principal.participant} expired on {when}; ask "
            "the study's admin for a new link.\n"
        ).encode()
        await _answer(scope, send, 401, body, ws_code=4401, ws_reason="invite expired")

    async def _forbid(self, scope: Scope, send: Send) -> None:
        body = (
            b"403 Forbidden: a participant's invite opens only the page and their own "
            b"session; this needs the study's admin link.\n"
        )
        await _answer(scope, send, 403, body, ws_code=4403, ws_reason="admin token required")


async def _answer(
    scope: Scope, send: Send, status: int, body: bytes, *, ws_code: int, ws_reason: str
) -> None:
    if scope["type"] == "websocket":
        await send({"type": "websocket.close", "code": ws_code, "reason": ws_reason})
        return
    headers = [
        (b"content-type", b"text/plain; charset=utf-8"),
        (b"content-length", str(len(body)).encode()),
    ]
    if status == 401:
        headers.append((b"www-authenticate", b"Bearer"))
    await send({"type": "http.response.start", "status": status, "headers": headers})
    await send({"type": "http.response.body", "body": body})
