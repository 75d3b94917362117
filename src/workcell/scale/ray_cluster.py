"""Ray, started on this machine or reached at a cluster's address: what ``workcell collect
--ray`` and ``workcell serve --ray`` share. Ray itself is imported only here, when asked for.
"""

from __future__ import annotations

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
        _check_reachable(address)
    try:
        if address == LOCAL:
            ray.init(num_cpus=num_cpus, include_dashboard=False, log_to_driver=False)
        else:
            ray.init(address=address, log_to_driver=False)
    except Exception as error:  # ray raises ConnectionError, RuntimeError, ValueError ...
        raise RayError(f"cannot connect to Ray at {address!r}: {error}") from None


def _check_reachable(address: str) -> None:
    """Fail at once when nothing listens at a ``host:port`` (or ``ray://host:port``)
    address: ray.init would retry it for minutes. Other forms ("auto") are Ray's to judge."""
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
