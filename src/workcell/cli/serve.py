"""``workcell serve``: the web app (setup, teleoperation, sessions, replay) on uvicorn."""

from __future__ import annotations

import argparse
import secrets
import signal
import socket
import time
from collections import Counter
from pathlib import Path
from types import FrameType
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import uvicorn

    from workcell.cli.command import Subparsers
    from workcell.server.options import ServerOptions
    from workcell.server.seats import Seats
    from workcell.server.study_desk import StudyDesk

EXIT_INTERRUPTED = 128 + signal.SIGINT
EXIT_TERMINATED = 128 + signal.SIGTERM


def register(subparsers: Subparsers) -> None:
    parser = subparsers.add_parser(
        "serve",
        help="serve the web app: setup, teleoperation (VR or desktop), sessions, replay",
        description=(
            "Run the simulation in real time and serve the web client and its WebSocket. "
            "Binds 127.0.0.1 unless --host says otherwise; a non-loopback host needs a token "
            "(generated and printed unless --token is given). A headset on the LAN needs "
            "--tls (a self-signed certificate is generated) for WebXR."
        ),
    )
    parser.add_argument(
        "--store",
        type=Path,
        default=Path("workcell.sqlite"),
        metavar="PATH",
        help="SQLite store to record into (default: %(default)s; created if absent)",
    )
    parser.add_argument(
        "--host", default="127.0.0.1", help="address to bind (default: %(default)s)"
    )
    parser.add_argument("--port", type=int, default=8000, help="port (default: %(default)s)")
    parser.add_argument("--tls", action="store_true", help="HTTPS/WSS, self-signed certificate")
    parser.add_argument("--token", metavar="T", help="access token every request must carry")
    parser.add_argument(
        "--grace",
        type=float,
        default=10.0,
        metavar="S",
        help="seconds a dropped operator has to reconnect (default: %(default)s)",
    )
    parser.add_argument(
        "--admit-cores",
        type=float,
        metavar="N",
        help="cores the sessions may use together: one more session starts only while the "
        "running ones measurably fit N cores and keep real time (default: this machine's)",
    )
    parser.add_argument(
        "--no-admission",
        dest="admission",
        action="store_false",
        help="start every session at once, whatever the load (for benchmarks that measure "
        "an overloaded machine; by default a start waits while the machine has no headroom)",
    )
    parser.add_argument(
        "--allow-origin",
        action="append",
        default=[],
        metavar="ORIGIN",
        help="also let pages of ORIGIN (scheme://host[:port]) open the WebSocket, and accept "
        "its host name in the Host header (repeatable; default: only the server's own pages)",
    )
    parser.add_argument(
        "--key",
        type=Path,
        metavar="FILE",
        help="sign the store's hash chain with the secret in FILE (see 'workcell verify --key')",
    )
    parser.add_argument(
        "--sessions",
        type=int,
        default=1,
        metavar="N",
        help="sessions at once, each with its own operator, simulation and spectators; beyond "
        "N operators watch, told the server is full (default: %(default)s)",
    )
    parser.add_argument(
        "--ray",
        metavar="ADDRESS",
        help="run every session in a Ray actor instead of a local process: 'local' starts "
        "Ray on this machine, HOST:PORT (or ray://HOST:PORT, auto) connects to a running "
        "cluster, whose nodes need workcell installed; needs --sessions 2 or more",
    )
    parser.add_argument(
        "--study",
        type=Path,
        metavar="FILE",
        help="run the study in FILE (see 'workcell study --defaults'): one invite link per "
        "participant, who runs their plan's sessions in turn, and an admin page",
    )
    parser.add_argument(
        "--ws-compression",
        action="store_true",
        help="compress WebSocket messages when the client offers it (permessage-deflate): "
        "less bandwidth for operators on slow links, more CPU per message on both ends "
        "(default: off; uncompressed, a driving operator's States are about 1 Mbit/s, "
        "compressed about a ninth of that)",
    )
    parser.add_argument("--static", type=Path, metavar="DIR", help="built web client folder")
    parser.set_defaults(func=run)


def study_desk_from(args: argparse.Namespace) -> StudyDesk | None:
    """The study ``--study`` names, with its invites (created beside the store)."""
    if args.study is None:
        return None
    from workcell.server.study_desk import StudyDesk  # noqa: PLC0415
    from workcell.study.config import load_study  # noqa: PLC0415
    from workcell.study.invites import invites_path, load_or_create  # noqa: PLC0415

    study = load_study(args.study)
    return StudyDesk(study, load_or_create(invites_path(args.store, study), study), args.store)


def options_from(
    args: argparse.Namespace, desk: StudyDesk | None = None
) -> tuple[ServerOptions, bool]:
    """The server options of ``args`` and whether the token was generated here (a study's
    admin token is the server's token unless ``--token`` is given)."""
    from workcell.server.options import DEFAULT_STATIC, ServerOptions, is_loopback  # noqa: PLC0415

    token: str | None = args.token or (desk.invites.admin if desk else None)
    generated = token is None and not is_loopback(args.host)
    if generated:
        token = secrets.token_urlsafe(18)
    options = ServerOptions(
        store=args.store,
        host=args.host,
        port=args.port,
        token=token,
        tls=args.tls,
        grace_s=args.grace,
        static_dir=args.static or DEFAULT_STATIC,
        allow_origins=tuple(args.allow_origin),
        key_file=args.key,
        max_sessions=args.sessions,
        ray=args.ray,
        ws_compression=args.ws_compression,
        admit_cores=args.admit_cores,
        admission=args.admission,
    )
    return options, generated


def run(args: argparse.Namespace) -> int:
    desk = study_desk_from(args)
    options, generated = options_from(args, desk)
    from workcell.server.listening import listening_socket  # noqa: PLC0415

    listener = listening_socket(options.host, options.port)  # before any link is printed
    try:
        return _run(args, options, generated, desk, listener)
    finally:
        listener.close()


def _run(
    args: argparse.Namespace,
    options: ServerOptions,
    generated: bool,
    desk: StudyDesk | None,
    listener: socket.socket,
) -> int:
    from workcell.record.connection import check_intact  # noqa: PLC0415
    from workcell.server.app import create_app  # noqa: PLC0415
    from workcell.server.http_config import uvicorn_config  # noqa: PLC0415
    from workcell.server.seats import Seats  # noqa: PLC0415
    from workcell.server.session_process import SessionProcess  # noqa: PLC0415
    from workcell.server.tls import lan_address, self_signed  # noqa: PLC0415

    ssl: dict[str, str] = {}
    if options.tls:
        cert = self_signed(options.cert_dir, options.host)
        ssl = {"ssl_certfile": str(cert.cert_file), "ssl_keyfile": str(cert.key_file)}
        print(f"TLS certificate {cert.cert_file}\n  SHA-256 fingerprint {cert.fingerprint}")
    ray = None
    if options.ray is not None:  # before anything is merged: a Ray not reached ends here
        from workcell.server.session_actor import RaySessions  # noqa: PLC0415

        ray = RaySessions.connect(options.ray, options.max_sessions)
    try:
        if options.store.exists():  # never record into a damaged file
            check_intact(options.store)
        seats = Seats(options, desk, ray or SessionProcess)
        for line in seats.merge_leftovers():
            print(line)
        config = uvicorn_config(create_app(options, seats), options, **ssl)
        server = quit_first_server(config, seats)
        shown = options.host if options.host not in ("0.0.0.0", "::") else lan_address() or "HOST"
        scheme = "https" if options.tls else "http"
        query = f"/?token={options.token}" if options.token else "/"
        if generated:
            print("generated an access token (pass --token to choose one)")
        base = f"{scheme}://{shown}:{listener.getsockname()[1]}"
        if desk is not None:  # the admin's page: the study's sessions start from invites
            print_invites(desk, base, args.store)
            query = admin_query(desk)
        print(f"workcell serve: open {base}{query}", flush=True)
        at_once = ""
        if options.max_sessions > 1:
            at_once = f"; up to {options.max_sessions} sessions at once"
            at_once += f", each in a Ray actor ({ray.where})" if ray else ""
        print(f"recording into {options.store}{at_once}; Ctrl+C stops (running trials end "
              "interrupted)")  # fmt: skip
        return _serve(server, seats, listener)
    finally:  # after the sessions' ends: their actors are done with
        if ray is not None:
            ray.close()


def _serve(server: uvicorn.Server, seats: Seats, listener: socket.socket) -> int:
    """Run until a signal; the exit status. However uvicorn ended, the running trials end,
    their stores are closed and what this run recorded is printed."""
    began = time.time()
    # uvicorn handles SIGINT and SIGTERM (a graceful shutdown), then re-raises the signal
    # to the handler that was there before: Python's for SIGINT (KeyboardInterrupt), this
    # one for SIGTERM, so that both end here with the shells' status (130, 143).
    previous = signal.signal(signal.SIGTERM, _raise_terminated)
    try:
        server.run(sockets=[listener])
    except KeyboardInterrupt:
        return EXIT_INTERRUPTED
    except _TerminatedError:
        return EXIT_TERMINATED
    finally:
        signal.signal(signal.SIGTERM, previous)
        seats.quit()
        seats.finish(30.0)
        print(recorded_text(seats.options.store, began), flush=True)
    return 0


def recorded_text(store: Path, since: float) -> str:
    """What the store holds from sessions created since ``since``: sessions, trials and
    their outcomes, in one line."""
    from workcell.record.errors import StoreError  # noqa: PLC0415
    from workcell.record.store import Store  # noqa: PLC0415

    if not store.exists():
        return f"workcell serve: stopped; nothing recorded ({store} was not created)"
    try:
        with Store.open(store, writer=False) as reader:
            sessions = {s.session_id for s in reader.sessions() if s.created_wall >= since}
            outcomes = [t.outcome or "open" for t in reader.trials() if t.session_id in sessions]
    except StoreError as error:
        return f"workcell serve: stopped; what was recorded could not be read: {error}"
    counts = Counter(outcomes)
    each = ", ".join(f"{n} {outcome}" for outcome, n in sorted(counts.items()))
    return (
        f"workcell serve: stopped; recorded {_count(len(sessions), 'session')}, "
        f"{_count(len(outcomes), 'trial')}{f' ({each})' if each else ''} into {store}"
    )


def _count(n: int, noun: str) -> str:
    return f"{n} {noun}{'' if n == 1 else 's'}"


def admin_query(desk: StudyDesk) -> str:
    """The admin page's address (after the host) on a study server."""
    return f"/?token={desk.invites.admin}&role=spectator#/admin"


def print_invites(desk: StudyDesk, base: str, store: Path) -> None:
    from workcell.study.invites import invites_path, minute_utc  # noqa: PLC0415

    study = desk.study
    print(
        f"study {study.name}: {study.participants} participants, "
        f"{len(next(iter(desk.plans.values())))} sessions each; "
        f"invites kept in {invites_path(store, study)}"
    )
    if desk.invites.dropped:
        print(
            f"  invites dropped: {', '.join(desk.invites.dropped)} (not among the study's "
            f"{study.participants} participants: their links open nothing)"
        )
    print(f"  admin page  {base}{admin_query(desk)}")
    now = time.time()
    for participant, token in desk.invites.participants.items():
        expires = desk.invites.expires(participant, study.invite_days)
        until = ""
        if expires is not None:
            when = minute_utc(expires)
            until = f"  (expired {when})" if now >= expires else f"  (valid until {when})"
        print(f"  {participant:<10}  {base}/?token={token}{until}")


class _TerminatedError(Exception):
    """SIGTERM arrived (raised once uvicorn has shut down)."""


def _raise_terminated(number: int, frame: FrameType | None) -> None:
    raise _TerminatedError


def quit_first_server(config: uvicorn.Config, seats: Seats) -> uvicorn.Server:
    """uvicorn's Server, told about a shutdown signal before it closes the connections, so
    an operator dropped during shutdown is an ``application_quit``, not a lost client."""
    import uvicorn  # noqa: PLC0415

    class QuitFirst(uvicorn.Server):
        def handle_exit(self, sig: int, frame: FrameType | None) -> None:
            seats.quit()
            super().handle_exit(sig, frame)

        async def shutdown(self, sockets: list[socket.socket] | None = None) -> None:
            await seats.shutdown()  # clients hear SessionEnded before they are closed
            await super().shutdown(sockets)

    return QuitFirst(config)
