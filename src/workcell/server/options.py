"""Everything ``workcell serve`` can be told, as one frozen value."""

from __future__ import annotations

import ipaddress
import math
from dataclasses import dataclass
from pathlib import Path

from workcell.errors import ConfigError
from workcell.record.chain import ChainKey
from workcell.record.errors import StoreError
from workcell.server.origin import allowed_origins

DEFAULT_STORE = Path("workcell.sqlite")
DEFAULT_STATIC = Path(__file__).resolve().parents[3] / "web" / "dist"
DEFAULT_CERT_DIR = Path.home() / ".cache" / "workcell" / "tls"
MAX_SESSIONS = 64
"""Most sessions one server runs at once (``--sessions``)."""


def is_loopback(host: str) -> bool:
    """True for 127.0.0.0/8, ::1 and ``localhost``."""
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


@dataclass(frozen=True)
class ServerOptions:
    """How the server runs. ``token`` None means no token is required (loopback only)."""

    store: Path = DEFAULT_STORE
    host: str = "127.0.0.1"
    port: int = 8000
    token: str | None = None
    tls: bool = False
    grace_s: float = 10.0
    """How long a dropped operator may take to reconnect before the trial ends."""
    static_dir: Path = DEFAULT_STATIC
    cert_dir: Path = DEFAULT_CERT_DIR
    state_hz: float = 60.0
    """Most State messages per second to each client."""
    max_messages_per_s: float = 240.0
    """Sustained message rate a client may send; beyond it messages are refused."""
    burst: int = 60
    """Messages a client may send at once above the sustained rate."""
    max_catch_up_s: float = 0.25
    """How far the simulation may fall behind the wall clock before it drops time."""
    allow_origins: tuple[str, ...] = ()
    """Origins (``scheme://host[:port]``) whose pages may open the WebSocket besides the
    server's own, and whose host names the Host check accepts."""
    key_file: Path | None = None
    """Sign the store's hash chain with the secret in this file (``--key``)."""
    max_sessions: int = 1
    """Sessions at once, each with its own operator and simulation (``--sessions``); with
    more than one, each session records into a shard merged into the store at its end."""
    ray: str | None = None
    """Run every session in a Ray actor (``--ray``): "local" starts Ray on this machine,
    anything else is the address of a cluster to connect to; None: in local processes."""
    ws_compression: bool = False
    """Compress WebSocket messages (permessage-deflate, ``--ws-compression``) when a client
    offers it: less bandwidth for a client on a slow link, for CPU on both ends of every
    message. Off: a State is about 1.7 KB, about 1 Mbit/s per driving client at 72 a
    second; compressed, about a ninth of that."""
    admission: bool = True
    """Start a session only while the machine has headroom for it (else it waits in line);
    False (``--no-admission``): every start at once, whatever the load (benchmarks that
    measure an overloaded machine)."""
    admit_cores: float | None = None
    """The cores the sessions may use together, for admission by measured headroom
    (:mod:`workcell.server.admission`, ``--admit-cores``); None: this machine's."""
    admit_min_real_time_factor: float = 0.98
    """The least recent real-time factor of every running session for one more to start."""
    header_timeout_s: float = 10.0
    """How long a connection may take to send a request's headers (from connecting, or
    from the end of the previous response) before it is closed."""

    def __post_init__(self) -> None:
        problems = []
        if not 0 <= self.port <= 65535:
            problems.append(f"--port = {self.port}: must be 0 to 65535")
        if not is_loopback(self.host) and not self.token:
            problems.append(
                f"--host = {self.host}: a non-loopback host needs a token (--token T, or "
                "let `workcell serve` generate one)"
            )
        if self.token is not None and not (8 <= len(self.token) <= 256):
            problems.append("--token: must be 8 to 256 characters")
        if not 1 <= self.max_sessions <= MAX_SESSIONS:
            problems.append(f"--sessions = {self.max_sessions}: must be 1 to {MAX_SESSIONS}")
        if self.ray is not None and not self.ray:
            problems.append("--ray = '': give 'local' or a Ray cluster's address (HOST:PORT)")
        elif self.ray is not None and self.max_sessions < 2:
            problems.append(
                f"--ray = {self.ray}: each session in a Ray actor records into a shard of "
                "its own, which needs several seats; give --sessions 2 or more"
            )
        if not (math.isfinite(self.grace_s) and 0 <= self.grace_s <= 3600):
            problems.append(f"--grace = {self.grace_s}: must be 0 to 3600 s")
        if not (math.isfinite(self.state_hz) and 1 <= self.state_hz <= 240):
            problems.append(f"state_hz = {self.state_hz}: must be 1 to 240")
        if not (math.isfinite(self.max_messages_per_s) and self.max_messages_per_s > 0):
            problems.append(f"max_messages_per_s = {self.max_messages_per_s}: must be > 0")
        if not (math.isfinite(self.header_timeout_s) and 0 < self.header_timeout_s <= 3600):
            problems.append(f"header_timeout_s = {self.header_timeout_s}: must be 0 to 3600 s")
        if self.admit_cores is not None and not (
            math.isfinite(self.admit_cores) and 0 < self.admit_cores <= 4096
        ):
            problems.append(f"--admit-cores = {self.admit_cores}: must be > 0 and at most 4096")
        if not (
            math.isfinite(self.admit_min_real_time_factor)
            and 0 <= self.admit_min_real_time_factor <= 2
        ):
            problems.append(
                f"admit_min_real_time_factor = {self.admit_min_real_time_factor}: must be 0 to 2"
            )
        try:
            allowed_origins(self.allow_origins)
        except ConfigError as error:
            problems += error.problems
        if self.key_file is not None:
            try:
                ChainKey.from_file(self.key_file)
            except StoreError as error:
                problems.append(f"--key: {error}")
        if problems:
            raise ConfigError(problems)
