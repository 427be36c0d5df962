"""Parallel execution at its limits: a bounded worker count, a scheduler address that is not a dask scheduler
fails in one line within ~10 s, Ctrl-C prints no worker traceback, SIGTERM leaves no pool process alive.

The signal tests run a child Python in its own session and signal it as a terminal (SIGINT to the whole
process group) or a process manager (SIGTERM to the process) would; every child is bounded by a timeout.  The
signal is sent on events, not after a delay: once every case announced that it runs (``worker_cases``) and the
parent no longer ignores SIGINT (/proc/PID/status), so the tests do not depend on the machine's load.
"""
from __future__ import annotations

import contextlib
import http.server
import os
import signal
import socket
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import pytest

from chainid.infra import parallel
from chainid.infra.parallel import MAX_WORKERS, run_cases, worker_count
from fake_servers import greeting_listener
from worker_cases import alive
from repo_paths import REPO as ROOT

ENV = dict(os.environ, PYTHONPATH=str(ROOT), MPLBACKEND="Agg")


def _capped_if_over(n: int):
    """The warning that n workers are capped, expected where n is over this machine's cap."""
    return pytest.warns(RuntimeWarning, match=f"n_workers = {n} is more than .*capped at {MAX_WORKERS}") \
        if n > MAX_WORKERS else contextlib.nullcontext()


def test_worker_count_is_capped_at_cases_and_maximum():
    assert MAX_WORKERS == min(64, 4 * (os.cpu_count() or 1))
    with _capped_if_over(12):  # 12 is over the cap on fewer than 3 cores, and the cap is said
        assert worker_count(12, 2) == 2
    assert worker_count(None, 1) == 1
    assert worker_count(None, 10_000) == min(os.cpu_count() or 1, MAX_WORKERS)
    with pytest.warns(RuntimeWarning, match=f"capped at {MAX_WORKERS}"):
        assert worker_count(100_000, 10**6) == MAX_WORKERS


@pytest.mark.slow
def test_process_pool_starts_no_more_workers_than_cases(monkeypatch):
    import concurrent.futures as cf

    seen = []

    class Recording(cf.ProcessPoolExecutor):
        def __init__(self, max_workers=None, **kw):
            seen.append(max_workers)
            super().__init__(max_workers=max_workers, **kw)

    monkeypatch.setattr(cf, "ProcessPoolExecutor", Recording)
    with pytest.warns(RuntimeWarning):
        assert run_cases(abs, [-1, -2], scheduler="processes", n_workers=100_000, progress=False) == [1, 2]
    with _capped_if_over(12):
        assert run_cases(abs, [-3, -4], scheduler="processes", n_workers=12, progress=False) == [3, 4]
    assert seen == [2, 2]


@pytest.mark.parametrize("n", [0, -1])
def test_cli_workers_below_one_is_refused(capsys, n):
    from chainid.cli import main

    assert main(["benchmark-gap", "--small", "--workers", str(n)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"chainid benchmark-gap: error: --workers = {n} is invalid: valid range >= 1 "
                   f"(more than {MAX_WORKERS} are capped)"]


# -- a scheduler address answered by something else -----------------------------------------------------

class _Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *a):  # no request lines on stderr
        pass


@pytest.fixture
def http_server():
    srv = http.server.ThreadingHTTPServer(("127.0.0.1", 0), _Quiet)
    th = threading.Thread(target=srv.serve_forever, kwargs={"poll_interval": 0.1}, daemon=True)
    th.start()
    yield f"tcp://127.0.0.1:{srv.server_address[1]}"
    srv.shutdown()
    srv.server_close()


@pytest.fixture
def http400_listener():
    """A TCP listener that greets every connection with an HTTP 400 and closes it (as a proxy does)."""
    answer = b"HTTP/1.1 400 Bad Request\r\nContent-Length: 0\r\nConnection: close\r\n\r\n"
    with greeting_listener(lambda: answer) as address:
        yield address


@pytest.mark.slow
@pytest.mark.parametrize("server, why", [("http_server", "sent no dask handshake within 5 s"),
                                         ("http400_listener", "answered 'HTTP/1.1'..., not a dask handshake")])
def test_scheduler_address_that_is_not_dask_fails_fast(request, server, why):
    address = request.getfixturevalue(server)
    t0 = time.monotonic()
    with pytest.raises(ValueError, match="scheduler = .* is invalid: the server there") as ei:
        run_cases(abs, [1, 2], scheduler=address, progress=False)
    assert time.monotonic() - t0 < 10.0
    assert why in str(ei.value) and "\n" not in str(ei.value)
    # the command: one line, exit 2, within the same bound (a child, so a regression cannot hang the suite)
    t0 = time.monotonic()
    p = subprocess.run([sys.executable, "-c", "import sys; from chainid.cli import main; sys.exit(main())",
                        "benchmark-gap", "--small", "--scheduler", address, "--no-progress"],
                       capture_output=True, text=True, timeout=60, env=ENV)
    assert time.monotonic() - t0 < 15.0
    assert p.returncode == 2
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and why in lines[0], p.stderr


def test_refused_connection_is_one_line():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()  # nothing listens there now
    with pytest.raises(ValueError, match="no dask scheduler answers at that address"):
        parallel.probe_scheduler(f"127.0.0.1:{port}")


# -- signals ----------------------------------------------------------------------------------------------

def _descendants(pid: int) -> list[int]:
    """Process ids below ``pid`` (from /proc)."""
    kids: dict[int, list[int]] = {}
    for d in os.listdir("/proc"):
        if d.isdigit():
            try:
                fields = Path(f"/proc/{d}/stat").read_text().rsplit(")", 1)[1].split()
            except OSError:
                continue
            kids.setdefault(int(fields[1]), []).append(int(d))
    out, todo = [], [pid]
    while todo:
        for c in kids.get(todo.pop(), []):
            out.append(c)
            todo.append(c)
    return out




def _sigint_ignored_by(pid: int) -> bool:
    """Whether ``pid`` ignores SIGINT now (the SigIgn mask of /proc/PID/status, bit 1 = signal 2)."""
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("SigIgn:"):
            return bool(int(line.split()[1], 16) & (1 << (signal.SIGINT - 1)))
    return False


def _start(code: str, folder: Path, n_cases: int) -> tuple[subprocess.Popen, list[int]]:
    """Start ``code`` in its own session and wait (events, no delay) until ``n_cases`` cases announced that they
    run (``worker_cases``: a file per worker pid in ``folder``) and the parent handles SIGINT again (it left
    the window in which it ignores SIGINT while it starts the workers).  Bounded by 240 s."""
    env = dict(ENV, PYTHONPATH=os.pathsep.join([str(ROOT), str(ROOT / "tests")]), CHAINID_TEST_ANNOUNCE=str(folder))
    # a terminal's program starts with SIGINT at its default, whatever the test runner inherited (a runner started
    # in the background by a non-interactive shell ignores SIGINT, and a child would inherit that)
    p = subprocess.Popen([sys.executable, "-c", textwrap.dedent(code)], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, env=env, start_new_session=True,
                         preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    deadline = time.monotonic() + 240
    while time.monotonic() < deadline:
        if p.poll() is not None:
            pytest.fail(f"child ended early: {p.communicate()}")
        running = [f for f in folder.iterdir() if f.name.isdigit()]
        if len(running) >= n_cases and not _sigint_ignored_by(p.pid):
            return p, _descendants(p.pid)
        time.sleep(0.05)  # polling for the events above, not waiting for something to happen in time
    os.killpg(p.pid, signal.SIGKILL)
    pytest.fail("the cases did not start within 240 s")


SLEEPERS = """
    import sys
    from chainid.infra.parallel import run_cases
    from worker_cases import announce_and_block
    try:
        run_cases(announce_and_block, [{folder!r}] * 2, scheduler="{sched}", n_workers=2, progress=False)
    except KeyboardInterrupt:
        sys.exit(130)
"""


def _finish(p: subprocess.Popen, kids: list[int], folder: Path) -> tuple[int, str]:
    try:
        _, err = p.communicate(timeout=60)
    except subprocess.TimeoutExpired:  # pragma: no cover - the failure this guards against
        os.killpg(p.pid, signal.SIGKILL)
        pytest.fail("the run did not end within 60 s of the signal")
    finally:
        (folder / "release").write_text("")  # a blocked case that outlived the parent returns now
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline and any(alive(k) for k in kids):
        time.sleep(0.1)
    left = [k for k in kids if alive(k)]
    for k in left:  # do not leave them behind even when the test fails
        os.kill(k, signal.SIGKILL)
    assert not left, f"processes left alive: {left}"
    return p.returncode, err


@pytest.mark.slow
@pytest.mark.parametrize("sched", ["processes", "local"])
def test_sigterm_leaves_no_pool_process(sched, tmp_path):
    p, kids = _start(SLEEPERS.format(sched=sched, folder=str(tmp_path)), tmp_path, 2)
    assert len(kids) >= 2
    p.send_signal(signal.SIGTERM)
    rc, err = _finish(p, kids, tmp_path)
    assert rc == 143
    assert "Traceback" not in err, err


def _ctrl_c(p: subprocess.Popen) -> None:
    """Ctrl-C as the terminal sends it: SIGINT to the whole foreground group, once (the parent handles it: see
    _start)."""
    os.killpg(p.pid, signal.SIGINT)


@pytest.mark.slow
def test_ctrl_c_on_a_dask_local_cluster_no_worker_traceback(tmp_path):
    p, kids = _start(SLEEPERS.format(sched="local", folder=str(tmp_path)), tmp_path, 2)
    _ctrl_c(p)
    rc, err = _finish(p, kids, tmp_path)
    assert rc == 130
    assert "Traceback" not in err and "KeyboardInterrupt" not in err, err


@pytest.mark.slow
def test_ctrl_c_on_benchmark_gap_exits_130_with_one_line(tmp_path):
    code = """
        import sys
        import chainid.gap.benchmark.grid as grid
        import worker_cases
        grid.run_case = worker_cases.announce_then_run_case  # each case announces its worker, then runs
        from chainid.cli import main
        sys.exit(main(["benchmark-gap", "--small", "--scheduler", "processes", "--workers", "2", "--no-progress"]))
    """
    p, kids = _start(code, tmp_path, 2)
    _ctrl_c(p)
    rc, err = _finish(p, kids, tmp_path)
    assert rc == 130
    assert err.strip().splitlines() == ["chainid benchmark-gap: interrupted; no partial output was written"], err
