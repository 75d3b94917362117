"""Downloads from the Sessions page: ``GET /api/export/csv.zip`` (the store's CSV export,
as ``workcell export --format csv`` writes it, manifest included, zipped) and ``GET
/api/export/trials.csv?session=ID&session=ID...`` (the audit's trials.csv, as ``workcell
audit`` writes it, of the sessions named; none named: every session's trials).

Both read the store the server records into, in a worker thread. Like every ``/api/``
path they need the server's token or a study's admin token when the server has one (a
participant's invite is refused: :mod:`workcell.server.auth`), so a server reachable from
the network hands its records only to its admin.
"""

from __future__ import annotations

import asyncio
import shutil
import tempfile
import zipfile
from pathlib import Path

from starlette.background import BackgroundTask
from starlette.requests import Request
from starlette.responses import FileResponse, Response
from starlette.routing import Route

from workcell.errors import WorkcellError
from workcell.record.connection import damage_as_store_error
from workcell.record.errors import StoreError
from workcell.server.http_api import problem, shown
from workcell.server.seats import Seats

CSV_ZIP = "workcell-csv-export.zip"
TRIALS_CSV = "trials.csv"
MAX_SESSIONS_ASKED = 1000


class UnknownSessionError(WorkcellError):
    """A download names a session the store does not hold."""


def download_routes(seats: Seats) -> list[Route]:
    store_path = seats.options.store

    async def csv_zip(request: Request) -> Response:
        if not store_path.exists():
            return problem(404, "the store has no sessions yet: nothing to export")
        work = Path(tempfile.mkdtemp(prefix="workcell-download-"))
        try:
            archive = await asyncio.to_thread(zipped_csv_export, store_path, work)
        except (StoreError, WorkcellError) as error:
            shutil.rmtree(work, ignore_errors=True)
            return problem(503, str(error))
        return FileResponse(
            archive,
            media_type="application/zip",
            filename=CSV_ZIP,
            background=BackgroundTask(shutil.rmtree, work, ignore_errors=True),
        )

    async def trials_csv(request: Request) -> Response:
        asked = tuple(request.query_params.getlist("session"))
        if len(asked) > MAX_SESSIONS_ASKED:
            return problem(400, f"session: at most {MAX_SESSIONS_ASKED} sessions at once")
        if not store_path.exists():
            return problem(404, "the store has no sessions yet: nothing to export")
        work = Path(tempfile.mkdtemp(prefix="workcell-download-"))
        try:
            path = await asyncio.to_thread(audited_trials_csv, store_path, asked, work)
        except UnknownSessionError as error:
            shutil.rmtree(work, ignore_errors=True)
            return problem(404, str(error))
        except (StoreError, WorkcellError) as error:
            shutil.rmtree(work, ignore_errors=True)
            return problem(503, str(error))
        return FileResponse(
            path,
            media_type="text/csv",
            filename=TRIALS_CSV,
            background=BackgroundTask(shutil.rmtree, work, ignore_errors=True),
        )

    return [
        Route("/api/export/csv.zip", csv_zip),
        Route("/api/export/trials.csv", trials_csv),
    ]


def zipped_csv_export(store: Path, work: Path) -> Path:
    """The store's CSV export (``workcell export --format csv``) zipped in ``work``."""
    from workcell.record.export_csv import export_csv  # noqa: PLC0415

    out = work / "export"
    with damage_as_store_error(store):
        export_csv(store, out)
    archive = work / CSV_ZIP
    with zipfile.ZipFile(archive, "w", zipfile.ZIP_DEFLATED) as packed:
        for file in sorted(out.iterdir()):
            packed.write(file, arcname=file.name)
    return archive


def audited_trials_csv(store: Path, sessions: tuple[str, ...], work: Path) -> Path:
    """The audit's trials.csv of the trials of ``sessions`` (none: all), audited against
    the whole store (a trial's slowness is judged among every trial, as ``workcell
    audit`` does), written in ``work``."""
    from workcell.audit.run import run_audit  # noqa: PLC0415
    from workcell.audit.store_source import StoreSource  # noqa: PLC0415
    from workcell.audit.trials_csv import write_trials_csv  # noqa: PLC0415

    with damage_as_store_error(store):
        source = StoreSource(store)
        try:
            known = {s.session_id for s in source.sessions()}
            missing = [s for s in sessions if s not in known]
            if missing:
                raise UnknownSessionError(
                    f"session = {shown(missing[0], 40)}: not in the store; the Sessions page "
                    "lists the recorded ones"
                )
            result = run_audit(source, workers=1)
        finally:
            source.close()
    wanted = set(sessions)
    trials = [t for t in result.trials if not wanted or t.row.session_id in wanted]
    path = work / TRIALS_CSV
    write_trials_csv(path, trials)
    return path
