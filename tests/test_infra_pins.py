"""Pins of chainid.infra (issue 20 §5): file modes under the user's umask, file names for awkward ids, and which
parallel back end actually ran.  Each test fails under the single-point bug its docstring names."""
from __future__ import annotations

import os
import re
import stat

import pytest

from chainid.infra import fileio
from chainid.infra.parallel import dask_available, run_cases


@pytest.mark.parametrize("umask,expected", [(0o022, 0o644), (0o077, 0o600), (0o002, 0o664)])
def test_atomic_write_mode_follows_umask(tmp_path, umask, expected):
    """A written file gets 0o666 & ~umask, as open() would give it (mkstemp alone gives 0o600).
    Bugs caught: the chmod dropped, the umask ignored (0o666) or applied twice/inverted."""
    old = os.umask(umask)
    try:
        p = fileio.atomic_write_text(tmp_path / "out.txt", "x\n")
        fileio.write_json({"a": 1}, str(tmp_path / "out.json"))
    finally:
        os.umask(old)
    assert stat.S_IMODE(os.stat(p).st_mode) == expected
    assert stat.S_IMODE(os.stat(tmp_path / "out.json").st_mode) == expected
    assert os.umask(old) == old  # the helper leaves the process umask as it was
    os.umask(old)


@pytest.mark.parametrize("name", [".", "..", ".hidden", "...", ".a.b"])
def test_safe_filename_never_hidden_or_a_directory(name):
    """Ids that start with a dot give a visible name that is neither '.' nor '..', with a hash suffix
    (distinct ids stay distinct).  Bugs caught: the leading-dot rule dropped, lstrip removed, hash not added."""
    out = fileio.safe_filename(name)
    assert not out.startswith(".") and out not in (".", "..")
    assert re.fullmatch(r"[A-Za-z0-9_.-]+-[0-9a-f]{8}", out), out


def test_safe_filename_dot_ids_distinct():
    ids = [".", "..", ".hidden", "hidden", "id"]
    names = {fileio.safe_filename(i) for i in ids}
    assert len(names) == len(ids)
    assert fileio.safe_filename("hidden") == "hidden"  # a safe id is kept as it is


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


def test_processes_run_in_other_processes_without_dask():
    """scheduler='processes' runs in a process pool, not in this process and not on dask.
    Bugs caught: dispatch to serial or to dask."""
    out = run_cases(_where, range(4), scheduler="processes", n_workers=2, progress=False)
    pids = {p for p, _ in out}
    assert os.getpid() not in pids and not any(d for _, d in out)
    assert 1 <= len(pids) <= 2


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


def test_commit_without_hard_links_still_refuses_to_overwrite(tmp_path, monkeypatch):
    """On a file system without hard links (os.link raises EPERM) the no-clobber commit falls back to a checked
    rename: a new target is written, an existing one is refused and kept, and no temporary file is left.
    Bug caught: the existence check inverted."""
    import errno

    def no_link(*a, **k):
        raise OSError(errno.EPERM, "Operation not permitted")

    monkeypatch.setattr(fileio.os, "link", no_link)
    p = fileio.atomic_write_text(tmp_path / "a.txt", "new\n")
    assert p.read_text() == "new\n"
    q = tmp_path / "b.txt"
    with pytest.raises(fileio.OutputError, match="already exists"):
        with fileio.atomic_open(q) as fh:
            fh.write("ours\n")
            q.write_text("appeared meanwhile\n")  # another process wrote the target while we were writing
    assert q.read_text() == "appeared meanwhile\n" and sorted(os.listdir(tmp_path)) == ["a.txt", "b.txt"]


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
