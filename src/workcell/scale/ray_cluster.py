"""Ray, started on this machine or reached at a cluster's address: what ``workcell collect
--ray`` and ``workcell serve --ray`` share. Ray itself is imported only here, when asked for.
"""

from __future__ import annotations

import os
import socket

from workcell.errors import WorkcellError

LOCAL = "local"
"""The address that starts Ray on this machine instead of connecting to a cluster."""
REACH_TIMEOUT_S = 5.0
"""How long a cluster's address may take to accept a connection before it counts as down."""


class RayError(WorkcellError):
    """Ray could not be reached or a task could not run."""


def start_ray(address: str, num_cpus: int) -> None:
    """Start Ray here with ``num_cpus`` CPUs (``address`` "local"), or connect this process
    to the cluster at ``address``; RayError naming the address when neither works."""
    import ray  # noqa: PLC0415

    if address != LOCAL:
        check_reachable(address)
    try:
        if address == LOCAL:
            ray.init(num_cpus=num_cpus, include_dashboard=False, log_to_driver=False)
        else:
            ray.init(address=address, log_to_driver=False)
    except Exception as error:  # ray raises ConnectionError, RuntimeError, ValueError ...
        raise RayError(f"cannot connect to Ray at {address!r}: {error}") from None


def check_reachable(address: str) -> None:
    """Fail at once when nothing listens at a ``host:port`` (or ``ray://host:port``)
    address, or something does that is not a gRPC server (Ray's head and client servers
    are): ray.init would retry the first for minutes and wait on the second for ever.
    Other forms ("auto") are Ray's to judge."""
    host, colon, port = address.removeprefix("ray://").rpartition(":")
    if not colon or not port.isdigit():
        return
    host = host.strip("[]")  # an IPv6 address
    try:
        socket.create_connection((host, int(port)), timeout=REACH_TIMEOUT_S).close()
    except OSError as error:
        raise RayError(
            f"cannot connect to Ray at {address!r}: nothing answers at {host}:{port} "
            f"({error.strerror or error}); is the cluster up (ray start --head)?"
        ) from None
    if os.environ.get("RAY_USE_TLS", "0") not in ("", "0"):
        return  # a TLS cluster: the handshake needs Ray's certificates; ray.init checks
    if not _speaks_grpc(host, int(port)):
        raise RayError(
            f"cannot connect to Ray at {address!r}: something answers at {host}:{port} "
            f"but not as Ray does (no gRPC handshake within {REACH_TIMEOUT_S:g} s); give "
            "the head's address as `ray start --head` printed it (port 6379 by default)"
        )


def _speaks_grpc(host: str, port: int) -> bool:
    """Whether the server at ``host:port`` completes a gRPC (HTTP/2) handshake in time."""
    import grpc  # noqa: PLC0415 - Ray's own dependency, imported only when Ray is asked for

    target = f"[{host}]:{port}" if ":" in host else f"{host}:{port}"
    channel = grpc.insecure_channel(target)
    try:
        grpc.channel_ready_future(channel).result(timeout=REACH_TIMEOUT_S)
    except grpc.FutureTimeoutError:
        return False
    finally:
        channel.close()
    return True
