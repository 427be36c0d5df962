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
