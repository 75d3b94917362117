"""The built web client (``web/dist``), or a page saying how to build it.

Files are served by Starlette's StaticFiles, which resolves every path inside its folder
and refuses anything outside it (``..``, encoded or not).
"""

from __future__ import annotations

import html
from collections.abc import Awaitable, Callable
from pathlib import Path

from starlette.requests import Request
from starlette.responses import FileResponse, HTMLResponse, Response
from starlette.staticfiles import StaticFiles
from starlette.types import Receive, Scope, Send

MISSING_PAGE = """<!doctype html>
<html lang="en"><head><meta charset="utf-8"><title>Workcell: web client not built</title>
</head><body style="font-family: sans-serif; max-width: 40em; margin: 3em auto">
<h1>The web client is not built</h1>
<p>The server is running, but <code>{folder}</code> does not exist. Build the client
with the set-up command (see the README), then reload this page.</p>
<p>The JSON API works already: <a href="/api/defaults{query}">/api/defaults</a>,
<a href="/api/sessions{query}">/api/sessions</a>.</p>
</body></html>
"""


class ClientFiles:
    """StaticFiles over ``folder`` that answers 404 (not an error) while it is missing."""

    def __init__(self, folder: Path) -> None:
        self.folder = folder
        self._files = StaticFiles(directory=folder, html=True, check_dir=False)

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if not self.folder.is_dir():
            await Response("not found", status_code=404)(scope, receive, send)
            return
        await self._files(scope, receive, send)


def index_route(folder: Path) -> Callable[[Request], Awaitable[Response]]:
    async def index(request: Request) -> Response:
        page = folder / "index.html"
        if page.is_file():
            return FileResponse(page, headers={"cache-control": "no-cache"})
        token = request.query_params.get("token")
        query = f"?token={html.escape(token)}" if token else ""
        return HTMLResponse(
            MISSING_PAGE.format(folder=html.escape(str(folder)), query=query), status_code=503
        )

    return index
