"""A parent killed outright (SIGKILL: no clean-up runs) leaves no worker behind: the process pool's and the dask
LocalCluster's workers end with it (Linux PR_SET_PDEATHSIG, and the watchdog thread on every system).

Each case announces the pid of the worker running it (a file named by the pid) and blocks; the test waits for
the announcements (events, not delays), SIGKILLs the parent and waits, bounded, for the workers to be gone.
"""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from worker_cases import LAUNCHER, alive, poll

ROOT = Path(__file__).resolve().parents[2]
ENV = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT), str(ROOT / "tests")]), MPLBACKEND="Agg")

PARENT = """
    import sys
    from chainid.infra.parallel import run_cases
    from worker_cases import announce_and_block
    run_cases(announce_and_block, [{folder!r}] * 2, scheduler={sched!r}, n_workers=2, progress=False)
"""


def _wait_for(cond, timeout: float, what: str):
    got = poll(cond, timeout)
    if not got:
        pytest.fail(f"not within {timeout:g} s: {what}")
    return got


def _pids(folder: Path) -> list[int]:
    return sorted(int(p.name) for p in folder.iterdir() if p.name.isdigit())


@pytest.mark.skipif(not Path("/proc").is_dir(), reason="needs /proc to see the processes")
@pytest.mark.parametrize("sched", ["processes", "local"])
def test_sigkilled_parent_leaves_no_worker(sched, tmp_path):
    if sched == "local":
        pytest.importorskip("distributed")
    p = subprocess.Popen([sys.executable, "-c", textwrap.dedent(PARENT.format(folder=str(tmp_path), sched=sched))],
                         env=ENV, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, start_new_session=True)
    try:
        workers = _wait_for(lambda: (len(_pids(tmp_path)) >= 2 or p.poll() is not None) and _pids(tmp_path), 240,
                            "both cases running")
        assert p.poll() is None, p.stderr.read().decode() if p.stderr else ""
        assert len(workers) == 2 and p.pid not in workers
        p.kill()  # SIGKILL: the parent runs no clean-up at all
        p.wait(30)
        _wait_for(lambda: not any(alive(w) for w in workers), 30, f"workers {workers} gone")
    finally:
        (tmp_path / "release").write_text("")  # a worker that outlived the test would end now
        if p.poll() is None:
            p.kill()
        for w in _pids(tmp_path):
            if alive(w):
                os.kill(w, signal.SIGKILL)


WATCHED = """
    import os, sys, time
    from chainid.infra import parallel
    parent = os.getppid()
    if {no_prctl}:
        parallel._parent_death_signal = lambda: False  # the watchdog alone (as on a system without prctl)
    parallel.die_with_parent(interval=0.05)
    open({flag!r}, "w").close()
    time.sleep(600)
"""


@pytest.mark.skipif(not Path("/proc").is_dir(), reason="needs /proc to see the processes")
@pytest.mark.parametrize("no_prctl", [False, True])
def test_die_with_parent_ends_the_child_when_the_parent_is_killed(no_prctl, tmp_path):
    flag = tmp_path / "armed"
    code = textwrap.dedent(WATCHED.format(no_prctl=no_prctl, flag=str(flag)))
    launcher = subprocess.Popen([sys.executable, "-c", textwrap.dedent(LAUNCHER.format(code=code))], env=ENV,
                                start_new_session=True)
    child = None
    try:
        _wait_for(flag.exists, 120, "the child armed its watch")
        kids = [int(d) for d in os.listdir("/proc") if d.isdigit() and _ppid(int(d)) == launcher.pid]
        assert len(kids) == 1
        child = kids[0]
        launcher.kill()
        launcher.wait(30)
        _wait_for(lambda: not alive(child), 10, "the child ended")
    finally:
        if launcher.poll() is None:
            launcher.kill()
        if child is not None and alive(child):
            os.kill(child, signal.SIGKILL)


def _ppid(pid: int) -> int:
    try:
        return int(Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[1])
    except (OSError, IndexError, ValueError):
        return -1
