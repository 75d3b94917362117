"""The process helpers the fault tests rely on, against real processes: a killed process
whose threads end one by one is dead only once the last has, and a thread that ends while
the helper looks is neither an error nor a sign that the whole process is."""

from __future__ import annotations

import os
import signal
import subprocess
import sys

from tests.record.processes import wait_until_dead

THREADS = """
import threading, time
for _ in range(200):
    threading.Thread(target=time.sleep, args=(60,), daemon=True).start()
print("ready", flush=True)
time.sleep(60)
"""
"""A child with 200 threads: after SIGKILL they end one by one, while the helper reads."""

CHURN = """
import threading, time
end = time.monotonic() + 1.0
while time.monotonic() < end:
    threads = [threading.Thread(target=lambda: None) for _ in range(8)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
"""
"""A child that starts and ends threads without pause for 1 s, then exits."""

KILLS = 10


def _reapable(pid: int) -> bool:
    """``waitpid`` reports ``pid`` now (every thread of it has exited); reaps it."""
    return os.waitpid(pid, os.WNOHANG) != (0, 0)


def test_wait_until_dead_sees_a_killed_many_threaded_child_through_its_threads_ending() -> None:
    for _ in range(KILLS):
        child = subprocess.Popen([sys.executable, "-c", THREADS], stdout=subprocess.PIPE)
        try:
            assert child.stdout is not None and child.stdout.readline() == b"ready\n"
            os.kill(child.pid, signal.SIGKILL)
            wait_until_dead(child.pid)
            assert _reapable(child.pid), "returned while a thread of the child was alive"
        finally:
            child.kill()
            child.wait()


def test_wait_until_dead_waits_for_a_child_whose_threads_come_and_go() -> None:
    child = subprocess.Popen([sys.executable, "-c", CHURN])
    try:
        wait_until_dead(child.pid)
        assert _reapable(child.pid), "returned while the child was still running"
    finally:
        child.kill()
        child.wait()
