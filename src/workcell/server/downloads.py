"""Downloads from the Sessions page: ``GET /api/export/csv.zip`` (the store's CSV export,
as ``workcell export --format csv`` writes it, manifest included, zipped), ``GET
/api/export/trials.csv?session=ID&session=ID...`` (the audit's trials.csv, as ``workcell
audit`` writes it, of the sessions named; none named: every session's trials) and ``GET
/api/export/lerobot.zip?operator=ID...`` (``workcell export --format lerobot
[--operator ID]...``: the included trials of those operators, none named: of everyone, as
a LeRobot dataset without camera images, zipped, with ``workcell_selection.txt`` saying
what it kept and left out).

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
from collections.abc import Callable, Sequence
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
LEROBOT_ZIP = "workcell-lerobot.zip"
SELECTION_FILE = "workcell_selection.txt"
TRIALS_CSV = "trials.csv"
MAX_SESSIONS_ASKED = 1000


class UnknownSessionError(WorkcellError):
    """A download names a session the store does not hold."""


def download_routes(seats: Seats) -> list[Route]:
    store_path = seats.options.store

    async def csv_zip(request: Request) -> Response:
        if not store_path.exists():
            return problem(404, "the store has no sessions yet: nothing to export")
        return await _download(
            lambda work: zipped_csv_export(store_path, work),
            "application/zip",
            CSV_ZIP,
            ((StoreError, 503), (WorkcellError, 503)),
        )

    async def trials_csv(request: Request) -> Response:
        asked = tuple(request.query_params.getlist("session"))
        if len(asked) > MAX_SESSIONS_ASKED:
            return problem(400, f"session: at most {MAX_SESSIONS_ASKED} sessions at once")
        if not store_path.exists():
            return problem(404, "the store has no sessions yet: nothing to export")
        return await _download(
            lambda work: audited_trials_csv(store_path, asked, work),
            "text/csv",
            TRIALS_CSV,
            ((UnknownSessionError, 404), (StoreError, 503), (WorkcellError, 503)),
        )

    async def lerobot_zip(request: Request) -> Response:
        operators = tuple(request.query_params.getlist("operator"))
        if len(operators) > MAX_SESSIONS_ASKED:
            return problem(400, f"operator: at most {MAX_SESSIONS_ASKED} operators at once")
        if not store_path.exists():
            return problem(404, "the store has no sessions yet: nothing to export")
        return await _download(  # nothing to export, a store that fails verify: 409
            lambda work: zipped_lerobot_export(store_path, operators, work),
            "application/zip",
            LEROBOT_ZIP,
            ((StoreError, 503), (WorkcellError, 409)),
        )

    return [
        Route("/api/export/csv.zip", csv_zip),
        Route("/api/export/trials.csv", trials_csv),
        Route("/api/export/lerobot.zip", lerobot_zip),
    ]


async def _download(
    build: Callable[[Path], Path],
    media_type: str,
    filename: str,
    statuses: Sequence[tuple[type[Exception], int]],
) -> Response:
    """The file ``build`` writes into a fresh folder (in a worker thread), sent as
    ``filename`` and removed with its folder once sent; an error of a kind in ``statuses``
    is answered with its status (the first kind that matches), the folder removed."""
    work = Path(tempfile.mkdtemp(prefix="workcell-download-"))
    try:
        path = await asyncio.to_thread(build, work)
    except Exception as error:
        shutil.rmtree(work, ignore_errors=True)
        for kind, status in statuses:
            if isinstance(error, kind):
                return problem(status, str(error))
        raise
    return FileResponse(
        path,
        media_type=media_type,
        filename=filename,
        background=BackgroundTask(shutil.rmtree, work, ignore_errors=True),
    )


def zipped_csv_export(store: Path, work: Path) -> Path:
    """The store's CSV export (``workcell export --format csv``) zipped in ``work``."""
    from workcell.record.export_csv import export_csv  # noqa: PLC0415

    out = work / "export"
    with damage_as_store_error(store):
        export_csv(store, out)
    return _zipped(out, work / CSV_ZIP)


def zipped_lerobot_export(store: Path, operators: tuple[str, ...], work: Path) -> Path:
    """The included trials of ``operators`` (none: everyone's) as a LeRobot dataset
    without camera images, zipped in ``work`` with a note of what was kept and left out."""
    from workcell.export.lerobot_export import export_lerobot  # noqa: PLC0415
    from workcell.export.options import ExportOptions  # noqa: PLC0415

    out = work / "lerobot"
    with damage_as_store_error(store):
        summary = export_lerobot(store, out, ExportOptions(operators=operators))
    episodes = f"{summary.episodes} episode{'' if summary.episodes == 1 else 's'}"
    lines = [f"exported {episodes}, {summary.frames} frames"]
    if summary.selection is not None:
        chosen = summary.selection
        left = ", ".join(f"{n} {reason}" for reason, n in chosen.left_out.items())
        lines.append(
            f"kept {len(chosen.episodes)} of {chosen.closed} closed trials (included trials"
            + (f" of {', '.join(operators)}" if operators else "")
            + f"); left out {sum(chosen.left_out.values())}"
            + (f": {left}" if left else "")
        )
    (out / SELECTION_FILE).write_text("\n".join(lines) + "\n", encoding="utf-8")
    return _zipped(out, work / LEROBOT_ZIP)


def _zipped(folder: Path, archive: Path) -> Path:
    """Every file below ``folder`` in the zip ``archive``, named from ``folder``."""
    with zipfile.ZipFile(archive, "w", zipfile.ZIP_DEFLATED) as packed:
        for file in sorted(p for p in folder.rglob("*") if p.is_file()):
            packed.write(file, arcname=file.relative_to(folder).as_posix())
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
