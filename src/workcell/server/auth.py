"""Token authentication of every HTTP and WebSocket request (pure ASGI middleware).

The token may come as ``?token=``, as ``Authorization: Bearer``, or as the cookie this
middleware sets on any response to a request that carried a valid token (so the page's
own scripts, styles and API calls are let in). Without a valid token: HTTP 401, and a
WebSocket handshake is refused (HTTP 403) before it is accepted.
"""

from __future__ import annotations

import secrets
import urllib.parse
from http.cookies import SimpleCookie

from starlette.types import ASGIApp, Message, Receive, Scope, Send

COOKIE = "workcell_token"


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
    def __init__(self, app: ASGIApp, token: str | None, secure: bool) -> None:
        self.app = app
        self.token = token
        self.secure = secure

    def valid(self, supplied: str | None) -> bool:
        return self.token is None or (
            supplied is not None and secrets.compare_digest(supplied.encode(), self.token.encode())
        )

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] not in ("http", "websocket") or self.token is None:
            await self.app(scope, receive, send)
            return
        supplied, explicit = _supplied(scope)
        if not self.valid(supplied):
            await self._refuse(scope, send)
            return
        if scope["type"] == "http" and explicit:
            send = self._with_cookie(send)
        await self.app(scope, receive, send)

    def _with_cookie(self, send: Send) -> Send:
        flags = "; HttpOnly; SameSite=Strict; Path=/" + ("; Secure" if self.secure else "")
        value = f"{COOKIE}={self.token}{flags}".encode("latin-1")

        async def sending(message: Message) -> None:
            if message["type"] == "http.response.start":
                message = {**message, "headers": [*message["headers"], (b"set-cookie", value)]}
            await send(message)

        return sending

    async def _refuse(self, scope: Scope, send: Send) -> None:
        if scope["type"] == "websocket":
            await send({"type": "websocket.close", "code": 4401, "reason": "token required"})
            return
        body = (
            b"401 Unauthorized: this server needs its access token. Open the URL that "
            b"`workcell serve` printed (it ends with ?token=...).\n"
        )
        await send(
            {
                "type": "http.response.start",
                "status": 401,
                "headers": [
                    (b"content-type", b"text/plain; charset=utf-8"),
                    (b"www-authenticate", b"Bearer"),
                    (b"content-length", str(len(body)).encode()),
                ],
            }
        )
        await send({"type": "http.response.body", "body": body})
