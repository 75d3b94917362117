"""A Ray address is judged before ray.init is given it: nothing listening, or something
listening that is not Ray, is one clear error within seconds (ray.init would retry the
first for minutes and wait on the second for ever); a real Ray head passes."""

from __future__ import annotations

import socket
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
import ray

from workcell.cli.main import main
from workcell.scale.ray_cluster import LOCAL, REACH_TIMEOUT_S, check_reachable, start_ray


@pytest.fixture
def silent_port() -> Iterator[int]:
    """A TCP port that accepts connections and never says a word."""
    server = socket.create_server(("127.0.0.1", 0))
    accepted: list[socket.socket] = []

    def accept() -> None:
        while True:
            try:
                connection, _ = server.accept()
            except OSError:
                return
            accepted.append(connection)

    threading.Thread(target=accept, daemon=True).start()
    yield server.getsockname()[1]
    server.close()
    for connection in accepted:
        connection.close()


def test_an_address_that_answers_but_not_as_ray_is_one_clear_error(
    silent_port: int, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    address = f"127.0.0.1:{silent_port}"
    store = tmp_path / "store.sqlite"
    started = time.monotonic()
    args = ["collect", "--trials", "1", "--workers", "2", "--store", str(store)]
    assert main([*args, "--ray", address]) == 2
    assert time.monotonic() - started < REACH_TIMEOUT_S + 20  # not ray.init's wait
    errors = [line for line in capsys.readouterr().err.splitlines() if line.startswith("workcell:")]
    assert len(errors) == 1  # one line, after the run's own progress line
    (error,) = errors
    assert error.startswith(f"workcell: error: cannot connect to Ray at '{address}': something ")
    assert "not as Ray does" in error and "6379" in error
    assert not store.exists()


@pytest.mark.slow
def test_a_ray_head_passes_the_check() -> None:

    start_ray(LOCAL, 1)
    try:
        head = ray.get_runtime_context().gcs_address
        check_reachable(head)  # a gRPC server: no error
        check_reachable("auto")  # not host:port: Ray's to judge
    finally:
        ray.shutdown()
