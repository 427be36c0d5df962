"""On Linux the kernel itself ends a worker whose parent dies (``prctl(PR_SET_PDEATHSIG, SIGKILL)``, set by
:func:`chainid.infra.parallel.die_with_parent`): with the watchdog thread switched off, a child that armed it is
gone soon after its parent is SIGKILLed, and a child that did not arm it outlives the parent (the control, so
the test can fail).
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

CHILD = """
    import os, time
    from chainid.infra import parallel
    parallel._watchdog = lambda parent, interval: None  # the kernel's signal alone
    if {arm}:
        parallel.die_with_parent(interval=0.05)
    with open({pidfile!r}, "w") as f:
        f.write(str(os.getpid()))
    time.sleep(600)
"""


def _wait_for(cond, timeout: float) -> bool:
    return bool(poll(cond, timeout))


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="PR_SET_PDEATHSIG is Linux's")
@pytest.mark.parametrize("arm", [True, False])
def test_the_kernel_ends_an_armed_child_when_its_parent_is_killed(arm, tmp_path):
    pidfile = tmp_path / "child.pid"
    code = textwrap.dedent(CHILD.format(arm=arm, pidfile=str(pidfile)))
    launcher = subprocess.Popen([sys.executable, "-c", textwrap.dedent(LAUNCHER.format(code=code))], env=ENV,
                                start_new_session=True)
    child = None
    try:
        assert _wait_for(lambda: pidfile.exists() and pidfile.read_text().strip(), 120), "the child never started"
        child = int(pidfile.read_text())
        launcher.kill()
        launcher.wait(30)
        gone = _wait_for(lambda: not alive(child), 10)
        assert gone is arm
    finally:
        if launcher.poll() is None:
            launcher.kill()
        if child is not None and alive(child):
            os.kill(child, signal.SIGKILL)


class _LibcWithout:
    """A C library without ``prctl`` (a libc that does not export it: the attribute lookup fails)."""

    def __getattr__(self, name):
        raise AttributeError(name)


class _LibcFailing:
    """A C library whose ``prctl`` refuses the request (returns -1, as the kernel does for a bad option)."""

    @staticmethod
    def prctl(*args):
        return -1


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="the prctl route is Linux's")
@pytest.mark.parametrize("libc, why", [(_LibcWithout(), "no prctl symbol"), (None, "no C library to load"),
                                       (_LibcFailing(), "prctl refused")])
def test_without_a_working_prctl_the_signal_is_not_armed_and_nothing_raises(libc, why, monkeypatch):
    """The watchdog thread is then the only guard (``_parent_death_signal`` returns False); a libc without the
    symbol or a CDLL that cannot load is an expected platform, not an error."""
    import ctypes

    from chainid.infra import parallel

    def cdll(*a, **k):
        if libc is None:
            raise OSError("cannot load the C library")
        return libc

    monkeypatch.setattr(ctypes, "CDLL", cdll)
    assert parallel._parent_death_signal() is False, why
