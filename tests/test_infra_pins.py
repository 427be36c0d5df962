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


def test_progress_bar_throttles_to_ten_draws_a_second(monkeypatch):
    """The bar draws at start, then at most every 0.1 s, and always at the end (fake clock).
    Bug caught: the throttle's 'and' made 'or' (no draw at all until the end)."""
    import io

    from chainid.infra import parallel

    now = [100.0]
    monkeypatch.setattr(parallel.time, "monotonic", lambda: now[0])
    out = io.StringIO()
    bar = parallel._Bar(4, "x", True, stream=out)
    assert out.getvalue().count("\r") == 1 and "0/4" in out.getvalue()
    now[0] = 100.05
    bar.update()  # 0.05 s after the last draw: skipped
    assert out.getvalue().count("\r") == 1
    now[0] = 100.2
    bar.update()  # 0.2 s: drawn
    assert out.getvalue().count("\r") == 2 and out.getvalue().endswith("2/4 0.2s")
    now[0] = 100.21
    bar.update(2)  # the end: always drawn
    assert out.getvalue().count("\r") == 3 and "4/4" in out.getvalue()


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
