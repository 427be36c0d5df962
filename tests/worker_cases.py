"""Case functions for worker-process tests (importable by spawned workers: ``tests/`` is on their PYTHONPATH).

``alive(pid)`` tells whether a process exists and is not a zombie (Linux ``/proc``).

``announce_and_block(folder)`` writes the worker's pid as an empty file ``folder/<pid>`` (the test reads it as
"this case is running in that process") and then blocks until ``folder/release`` exists (or 600 s pass).

``LAUNCHER`` is the source of a parent process that starts a child running ``{code}`` and then sleeps (the test
kills it to see what becomes of the child); ``poll(cond, timeout)`` waits for an event.
"""
from __future__ import annotations

import os
import time
from pathlib import Path


LAUNCHER = """
    import subprocess, sys, time
    subprocess.Popen([sys.executable, "-c", {code!r}])
    time.sleep(600)
"""


def poll(cond, timeout: float):
    """``cond()`` once it is true (checked every 50 ms), or None after ``timeout`` [s] (a wait for an event, not a
    timing assumption)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        got = cond()
        if got:
            return got
        time.sleep(0.05)
    return None


def announce_and_block(folder: str) -> int:
    d = Path(folder)
    (d / f"{os.getpid()}.tmp").write_text("")
    os.replace(d / f"{os.getpid()}.tmp", d / str(os.getpid()))  # appears whole
    deadline = time.monotonic() + 600
    while not (d / "release").exists() and time.monotonic() < deadline:
        time.sleep(0.05)  # (a wait for an event, not a timing assumption)
    return os.getpid()


def announce_then_run_case(case):
    """``chainid.gap.benchmark.grid.run_case`` after announcing the worker (a file ``<pid>`` in the folder named
    by the environment variable CHAINID_TEST_ANNOUNCE).  The test sets it as ``grid.run_case`` in the parent; the
    workers are spawned (a fresh import), so ``grid.run_case`` here is the real one."""
    from chainid.gap.benchmark.grid import run_case

    d = Path(os.environ["CHAINID_TEST_ANNOUNCE"])
    if not (d / str(os.getpid())).exists():
        (d / f"{os.getpid()}.tmp").write_text("")
        os.replace(d / f"{os.getpid()}.tmp", d / str(os.getpid()))
    return run_case(case)


def alive(pid: int) -> bool:
    """Whether process ``pid`` exists and is not a zombie (its state in ``/proc/<pid>/stat``)."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"
