"""chainid.infra.parallel: run_cases gives the same results in case order on every back end, errors propagate
cleanly, arguments are checked, the progress bar counts, and the dask scheduler probe (an 8-byte little-endian
length of at most 1 MiB) refuses what is not dask in one line."""
from __future__ import annotations

import multiprocessing
import os
import re
import sys
import time

import pytest

from chainid.infra.parallel import dask_available, probe_scheduler, run_cases

from fake_servers import greeting_listener


def _where(case):
    """Where a case ran: (pid, inside a dask worker)."""
    try:
        from distributed import get_worker

        get_worker()
        in_dask = True
    except Exception:  # noqa: BLE001 - not in a dask worker (or no dask)
        in_dask = False
    return os.getpid(), in_dask


def test_serial_runs_in_this_process():
    """scheduler='serial' runs here.  Bug caught: a pool used instead."""
    out = run_cases(_where, range(3), scheduler="serial", progress=False)
    assert out == [(os.getpid(), False)] * 3


@pytest.mark.slow
def test_processes_run_in_other_processes_without_dask():
    """scheduler='processes' runs in a process pool, not in this process and not on dask.
    Bugs caught: dispatch to serial or to dask."""
    out = run_cases(_where, range(4), scheduler="processes", n_workers=2, progress=False)
    pids = {p for p, _ in out}
    assert os.getpid() not in pids and not any(d for _, d in out)
    assert 1 <= len(pids) <= 2


@pytest.mark.slow
@pytest.mark.skipif(not dask_available(), reason="dask.distributed not installed")
def test_default_runs_on_dask_when_available():
    """scheduler=None (local) with dask installed runs on a dask LocalCluster.
    Bug caught: the default falls back to the process pool (or serial) although dask is there."""
    out = run_cases(_where, range(2), n_workers=1, progress=False)
    assert all(d for _, d in out) and os.getpid() not in {p for p, _ in out}


def test_progress_bar_counts_to_the_total_on_a_terminal_only(monkeypatch):
    """The bar of run_cases is tqdm's (its own 0.1 s throttle replaced the hand-drawn one): on a terminal it
    reaches n/n and closes; no bar without cases, when disabled, or when stderr is not a terminal.
    Bugs caught: a bar drawn into a pipe or log; a bar left open (never reaching its total)."""
    import io
    import sys

    from chainid.infra import parallel

    tty = io.StringIO()
    tty.isatty = lambda: True  # type: ignore[method-assign]
    monkeypatch.setattr(sys, "stderr", tty)
    bar = parallel._Bar(4, "x", True)
    for _ in range(4):
        bar.update()
    bar.close()
    assert "4/4" in tty.getvalue()
    for total, enabled in ((0, True), (4, False)):
        n0 = len(tty.getvalue())
        parallel._Bar(total, "y", enabled).close()
        assert len(tty.getvalue()) == n0
    pipe = io.StringIO()
    pipe.isatty = lambda: False  # type: ignore[method-assign]
    monkeypatch.setattr(sys, "stderr", pipe)
    b = parallel._Bar(4, "z", True)
    b.update(4)
    b.close()
    assert pipe.getvalue() == ""


# --- the scheduler probe's address rules (the documented contract of probe_scheduler) -------------------------
@pytest.mark.parametrize("address", ["tcp://nohost", "tcp://host:", "tcp://:8786", "host:port", "tcp://h:87a6"])
def test_probe_refuses_an_address_without_host_and_numeric_port(address):
    """``tcp://host:port`` or ``host:port`` only: the message names the address, 'expected host:port' and the
    valid values (no connection is tried)."""
    from chainid.infra.parallel import probe_scheduler

    with pytest.raises(ValueError, match=rf"^scheduler = {re.escape(repr(address))} is invalid: expected "
                                         r"host:port; valid values are None, \['local', 'processes', 'serial'\] or "):
        probe_scheduler(address, timeout=0.5)


@pytest.mark.parametrize("address", ["tls://10.255.255.1:8786", "ucx://10.255.255.1:8786", "inproc://x/1/2"])
def test_probe_leaves_other_schemes_alone(address):
    """Other schemes than tcp:// are not probed: no connection, no error, at once."""
    import time

    from chainid.infra.parallel import probe_scheduler

    t0 = time.monotonic()
    assert probe_scheduler(address, timeout=5.0) is None
    assert time.monotonic() - t0 < 1.0


def test_probe_a_server_that_closes_without_a_word_and_an_ipv6_address():
    """A listener that accepts and closes at once: 'closed the connection without a dask handshake', well before
    the timeout.  An IPv6 address in brackets is parsed (the refusal is the connection's, not the format's)."""
    import socket
    import time

    from chainid.infra.parallel import probe_scheduler
    from fake_servers import greeting_listener

    with greeting_listener(lambda: b"") as address:
        t0 = time.monotonic()
        with pytest.raises(ValueError, match="the server there closed the connection without a dask handshake"):
            probe_scheduler(address, timeout=4.0)
        assert time.monotonic() - t0 < 3.0
    s = socket.socket(socket.AF_INET6) if socket.has_ipv6 else None
    if s is None:
        pytest.skip("no IPv6")
    try:
        s.bind(("::1", 0))
    except OSError:
        s.close()
        pytest.skip("no IPv6 loopback")
    port = s.getsockname()[1]
    s.close()
    with pytest.raises(ValueError, match="no dask scheduler answers at that address"):
        probe_scheduler(f"tcp://[::1]:{port}", timeout=1.0)


@pytest.mark.parametrize("kw,message", [
    ({"n_workers": 0}, r"^n_workers = 0 is invalid: valid values are None or an int >= 1 \(capped at {M}\)$"),
    ({"n_workers": True}, r"^n_workers = True is invalid: valid values are None or an int >= 1"),
    ({"n_workers": 2.0}, r"^n_workers = 2.0 is invalid"),
    ({"scheduler": "  "}, r"^scheduler = '  ' is invalid: valid values are None, \['local', 'processes', 'serial'\]"),
    ({"scheduler": 3}, r"^scheduler = 3 is invalid"),
    ({"fn": 3}, r"^fn = 3 is invalid: valid values are callables"),
])
def test_run_cases_refuses_bad_arguments_naming_field_value_and_range(kw, message):
    """Each bad argument is one ValueError naming the field, the value and the valid values (MAX_WORKERS in the
    n_workers message), before any case runs; the checks come before the empty-cases shortcut."""
    from chainid.infra.parallel import MAX_WORKERS

    args = {"fn": abs, **kw}
    fn = args.pop("fn")
    for cases in ([1, -2], []):
        with pytest.raises(ValueError, match=message.replace("{M}", str(MAX_WORKERS))):
            run_cases(fn, cases, progress=False, **args)


def test_run_cases_smallest_valid_arguments():
    """n_workers = 1 is valid (the bound is inclusive); a scheduler name with spaces around it is that name."""
    assert run_cases(abs, [1, -2, 3], scheduler=" serial ", n_workers=1, progress=False) == [1, 2, 3]


@pytest.fixture
def greeter():
    """A TCP listener that greets every connection with the given bytes, then closes it after 0.3 s."""
    payload = {"bytes": b""}
    with greeting_listener(lambda: payload["bytes"], hold_s=0.3) as address:
        yield address, payload


def _le(n: int) -> bytes:
    return n.to_bytes(8, "little")


@pytest.mark.slow
def test_probe_accepts_lengths_up_to_one_mib(greeter):
    address, payload = greeter
    for n in (1, 300, 1 << 20):
        payload["bytes"] = _le(n)
        probe_scheduler(address, timeout=3.0)  # a dask-like greeting: accepted
    for n in (0, (1 << 20) + 1):
        payload["bytes"] = _le(n)
        with pytest.raises(ValueError, match="the server there answered .*not a dask handshake"):
            probe_scheduler(address, timeout=3.0)


@pytest.mark.slow
@pytest.mark.skipif(not dask_available(), reason="needs dask.distributed")
@pytest.mark.parametrize("greeting", [
    _le(1 << 20),  # a valid length, then the connection closes (dask: CommClosedError, an OSError)
    _le(16) + _le(1) + _le(0),  # frames that msgpack cannot unpack (ValueError)
    _le(17) + _le(1) + _le(1) + b"\x01",  # (TypeError inside dask's reader)
    _le(100) + b"\x00" * 100,  # (IndexError inside dask's reader)
    _le(8) + b"\xc1" * 8,  # (struct.error inside dask's reader)
], ids=["closed", "ValueError", "TypeError", "IndexError", "struct.error"])
def test_a_server_that_passes_the_probe_but_is_not_dask_is_one_line(greeter, capsys, greeting):
    address, payload = greeter
    payload["bytes"] = greeting
    probe_scheduler(address, timeout=3.0)
    t0 = time.monotonic()
    with pytest.raises(ValueError) as ei:
        run_cases(abs, [1, -2], scheduler=address, progress=False)
    assert time.monotonic() - t0 < 15.0
    msg = str(ei.value)
    assert msg.startswith(f"scheduler = {address!r} is invalid: no dask scheduler answers at that address (")
    assert "\n" not in msg
    assert "CRITICAL" not in capsys.readouterr().err  # dask's deserialisation traceback is held back


def test_probe_reads_the_whole_eight_byte_length():
    """A dask handshake starts with an 8-byte little-endian length, which the probe accepts in (0, 1 MiB]: seven
    bytes of 16 and, in a second read, an eighth byte 1 make 16 + 2^56, refused (the message shows all 8 bytes).
    Bug caught: the read loop stopping at 7 bytes (the length read as 16: accepted)."""
    import re

    from fake_servers import greeting_listener

    from chainid.infra.parallel import probe_scheduler

    greeting = [(16).to_bytes(7, "little"), b"\x01"]  # the eighth byte 0.1 s after the first seven
    with greeting_listener(lambda: greeting, hold_s=0.3) as address:
        with pytest.raises(ValueError, match=re.escape(
                r"answered '\\x10\\x00\\x00\\x00\\x00\\x00\\x00\\x01'..., not a dask handshake")):
            probe_scheduler(address, timeout=3.0)


def _square_plus(case):
    """A top-level (picklable) function of one case: (a, b) -> a**2 + b."""
    a, b = case
    return a * a + b


def _fail_on_three(case):
    if case == 3:
        raise RuntimeError("case 3 failed")
    return case


CASES = [(i, 10 * i) for i in range(7)]


EXPECTED = [i * i + 10 * i for i in range(7)]  # by hand: 0, 11, 24, 39, 56, 75, 96


def test_serial_in_order():
    assert run_cases(_square_plus, CASES, scheduler="serial", progress=False) == EXPECTED
    assert EXPECTED[:4] == [0, 11, 24, 39]


@pytest.mark.slow
def test_processes_same_as_serial():
    assert run_cases(_square_plus, CASES, scheduler="processes", n_workers=2, progress=False) == EXPECTED
    assert multiprocessing.active_children() == []


@pytest.mark.slow
@pytest.mark.skipif(not dask_available(), reason="dask.distributed not installed")
def test_local_cluster_same_as_serial():
    assert run_cases(_square_plus, CASES, scheduler="local", n_workers=2, progress=False) == EXPECTED
    assert multiprocessing.active_children() == []


@pytest.mark.skipif(not dask_available(), reason="dask.distributed not installed")
def test_existing_cluster_by_address_results_and_errors():
    """An existing scheduler (here an in-process one: fast) is used by address and left running."""
    from distributed import LocalCluster
    with LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None) as cluster:
        addr = cluster.scheduler_address
        assert run_cases(_square_plus, CASES, scheduler=addr, progress=False) == EXPECTED
        with pytest.raises(RuntimeError, match="case 3 failed"):
            run_cases(_fail_on_three, range(6), scheduler=addr, progress=False)
        assert run_cases(_square_plus, CASES[:2], scheduler=addr, progress=False) == EXPECTED[:2]  # still up


def test_empty_cases():
    assert run_cases(_square_plus, [], scheduler="processes") == []


def test_progress_bar_on_stderr(capsys, monkeypatch):
    run_cases(_square_plus, CASES, scheduler="serial", progress=True, desc="sweep")
    assert capsys.readouterr().err == ""  # stderr is not a terminal (issue 19): no bar in pipes and logs
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True, raising=False)
    run_cases(_square_plus, CASES, scheduler="serial", progress=True, desc="sweep")
    err = capsys.readouterr().err
    assert "sweep" in err and "7/7" in err
    run_cases(_square_plus, CASES, scheduler="serial", progress=False, desc="sweep")
    assert capsys.readouterr().err == ""


@pytest.mark.slow
@pytest.mark.parametrize("scheduler", ["serial", "processes"])
def test_case_exception_propagates_and_workers_stop(scheduler):
    with pytest.raises(RuntimeError, match="case 3 failed"):
        run_cases(_fail_on_three, range(6), scheduler=scheduler, n_workers=2, progress=False)
    assert multiprocessing.active_children() == []


@pytest.mark.parametrize("kw, field", [({"n_workers": 0}, "n_workers"), ({"scheduler": ""}, "scheduler"),
                                      ({"n_workers": 1.5}, "n_workers")])
def test_bad_arguments(kw, field):
    with pytest.raises(ValueError, match=field):
        run_cases(_square_plus, CASES, progress=False, **kw)
