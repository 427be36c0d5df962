"""The numba cache never crashes a kernel call (chainid.infra.numba_cache), each case in a fresh subprocess.

- a read-only install with an unwritable HOME: falls back to a private folder in the temporary
  directory (one NumbaCacheWarning), then to no disk cache at all;
- a truncated cache file: recompiled and rewritten (one warning), nothing deleted;
- NUMBA_DISABLE_JIT=1: the kernels run as plain Python with the jitted results;
- the fallback folder, the warnings given once, njit_cached's recovering cache.

"Unwritable" is made so that it holds for root too: the package copy is chmod a-w *and* has a regular
file named ``__pycache__`` in each package folder, and HOME lies below a regular file, so that numba's
``os.makedirs`` fails with an OSError whatever the user's rights.  Each subprocess compiles one or two
kernels (a few seconds)."""
from __future__ import annotations

import json
import os
import shutil
import stat
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import chainid
from chainid.model.base import ChainModel

from repo_paths import REPO


# F_k at x = 2.2 mm on the built-in chain (two kernels: coefficients, force_array), compared with this
# process's jitted run of the same kernels (whose values test_kernels checks against closed forms).
SCRIPT = """
import json, sys, warnings
warnings.simplefilter("always")
{pre}
import chainid
from chainid.infra import numba_cache as _numba_cache
from numba.core import config
with warnings.catch_warnings(record=True) as w:
    warnings.simplefilter("always")
    F = chainid.force(2.2)
    {post}
print(json.dumps({{"F": F, "extra": locals().get("extra"), "mode": _numba_cache.cache_mode(), "cache_dir": config.CACHE_DIR,
                  "warnings": [str(m.message) for m in w if m.category.__name__ == "NumbaCacheWarning"]}}))
"""


def _env(**extra: str) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_") and k != "XDG_CACHE_HOME"}
    env["PYTHONDONTWRITEBYTECODE"] = "1"
    env.update(extra)
    return env


def _run(env: dict[str, str], pre: str = "", cwd: Path | None = None, post: str = "pass") -> dict:
    proc = subprocess.run([sys.executable, "-c", SCRIPT.format(pre=pre, post=post)], env=env, cwd=cwd, capture_output=True,
                          text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout.strip().splitlines()[-1])


def _files(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


@pytest.fixture
def readonly_install(tmp_path):
    """A read-only copy of chainid + generated (as PYTHONPATH) and a HOME nobody can create."""
    pkg = tmp_path / "site"
    for name in ("chainid", "generated"):
        shutil.copytree(REPO / name, pkg / name, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    for folder in [p for p in pkg.rglob("*") if p.is_dir()]:
        (folder / "__pycache__").write_text("not a folder\n")
    (tmp_path / "blocker").write_text("a file, so nothing can be created below it\n")
    for p in [pkg, *pkg.rglob("*")]:
        p.chmod(p.stat().st_mode & ~(stat.S_IWUSR | stat.S_IWGRP | stat.S_IWOTH))
    yield pkg, tmp_path / "blocker" / "home"
    for p in [pkg, *pkg.rglob("*")]:
        p.chmod(p.stat().st_mode | stat.S_IWUSR)


@pytest.mark.slow
def test_readonly_install_falls_back_to_a_temp_cache(readonly_install, tmp_path):
    pkg, home = readonly_install
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    before = _files(pkg)
    env = _env(PYTHONPATH=str(pkg), HOME=str(home), TMPDIR=str(tmp))
    # the hand-written numba operators of the gap effects (chainid/model/effects.py) use the same fallback
    post = ("from chainid.model import effects; import numpy as np; "
            "extra = effects.play_operator(np.array([0.0, 1.0, 0.4, -1.0]), 0.25, periodic=False).tolist()")
    first = _run(env, cwd=tmp_path, post=post)
    # play operator, half width 0.25, by hand: starts at x0 = 0, moves only when x leaves y ± 0.25
    assert first["extra"] == pytest.approx([0.0, 0.75, 0.65, -0.75], abs=1e-15)
    assert first["F"] == pytest.approx(chainid.force(2.2), rel=1e-14)
    assert first["mode"] == "temp"
    assert len(first["warnings"]) == 1 and "caching the compiled kernels in" in first["warnings"][0]
    folder = Path(first["cache_dir"])
    assert folder.parent == tmp and folder.name.startswith("chainid-numba-")
    assert any(p.suffix == ".nbi" for p in folder.rglob("*")), "kernels were not cached in the fallback folder"
    assert _files(pkg) == before, "the read-only install was modified"


@pytest.mark.slow
def test_no_writable_folder_at_all_compiles_in_memory(readonly_install, tmp_path):
    pkg, home = readonly_install
    blocked_tmp = str(tmp_path / "blocker" / "tmp")
    out = _run(_env(PYTHONPATH=str(pkg), HOME=str(home)), pre=f"import tempfile; tempfile.tempdir = {blocked_tmp!r}",
               cwd=tmp_path)
    assert out["F"] == pytest.approx(chainid.force(2.2), rel=1e-14)
    assert out["mode"] == "none" and out["cache_dir"] == ""
    assert len(out["warnings"]) == 1 and "compiled in memory" in out["warnings"][0]


@pytest.mark.slow
def test_truncated_cache_files_are_recompiled_and_nothing_deleted(tmp_path):
    cache = tmp_path / "cache"
    env = _env(PYTHONPATH=str(REPO), NUMBA_CACHE_DIR=str(cache))
    clean = _run(env)
    assert clean["mode"] == "default" and clean["warnings"] == []
    (cache / "notes.txt").write_text("the user's file\n")
    data = sorted(cache.rglob("*force_array*.nbc"))
    index = sorted(cache.rglob("*coefficients*.nbi"))
    assert data and index
    truncated = {}
    for p in data + index:
        p.write_bytes(p.read_bytes()[: p.stat().st_size // 2])  # truncated on purpose
        truncated[p] = p.stat().st_size
    names = {p.name for p in cache.rglob("*")}
    broken = _run(env)
    assert broken["F"] == clean["F"] == pytest.approx(chainid.force(2.2), rel=1e-14)
    assert len(broken["warnings"]) == 1 and "unreadable" in broken["warnings"][0]
    assert names <= {p.name for p in cache.rglob("*")}, "a cache file was deleted"
    assert (cache / "notes.txt").read_text() == "the user's file\n"
    for p, size in truncated.items():  # the entries were rewritten whole (numba: temp file + rename)
        assert p.stat().st_size > size, f"{p.name} was not rewritten"


def test_disable_jit_runs_pure_python_with_the_same_results(tmp_path):
    x = np.array([0.0, 1e-5, 1.0, 2.2, 10.0, 1e70, np.inf, np.nan, -1.0])
    script = (
        "import json, warnings, numpy as np, chainid\n"
        "from chainid.model.base import ChainModel\n"
        "from numba.core import config\n"
        "warnings.simplefilter('error')\n"  # no RuntimeWarning from numpy scalars on the Python path
        "x = np.array([0.0, 1e-5, 1.0, 2.2, 10.0, 1e70, np.inf, np.nan, -1.0])\n"
        "m = ChainModel(contact_exponent=0.8)\n"
        "r = [chainid.force(x), chainid.stiffness(x), chainid.displacement(np.abs(x)),\n"
        "     chainid.force(x, variant='inner_bend_shear'), m.force(x), m.stiffness(x)]\n"
        "print(json.dumps({'jit_disabled': bool(config.DISABLE_JIT), 'r': [v.tolist() for v in r]}))\n"
    )
    env = _env(PYTHONPATH=str(REPO), NUMBA_DISABLE_JIT="1", NUMBA_CACHE_DIR=str(tmp_path / "cache"))
    proc = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)  # Python's json reads NaN and Infinity
    assert out["jit_disabled"]
    m = ChainModel(contact_exponent=0.8)
    want = [chainid.force(x), chainid.stiffness(x), chainid.displacement(np.abs(x)),
            chainid.force(x, variant="inner_bend_shear"), m.force(x), m.stiffness(x)]
    for got, exp in zip(out["r"], want):
        got = np.array(got, dtype=float)
        np.testing.assert_allclose(got, exp, rtol=1e-13, atol=0.0)  # NaN where NaN, inf where inf
    assert not (tmp_path / "cache").exists(), "nothing is compiled, so nothing is cached"


def test_a_loaded_kernel_module_is_returned_without_probing_the_cache_again(monkeypatch):
    """``load_kernel_module`` on a module it loaded before returns that module at once: numba's cache locators are
    not probed again (a probe compiles a stub and builds a cache object, ~0.3 ms, and
    ``chainid.model.kernels.power_module`` loads on every use).  Bug caught: the early return's condition
    negated (every call re-probed)."""
    import chainid.infra.numba_cache as nc

    first = nc.load_kernel_module("contact_power")
    calls = []
    monkeypatch.setattr(nc, "_choose_cache", lambda py_file: calls.append(py_file) or "default")
    assert nc.load_kernel_module("contact_power") is first
    assert calls == [] and first._chainid_cache_mode == nc.cache_mode()


def test_private_temp_cache_folder_is_the_users_own_or_a_fresh_one(tmp_path, monkeypatch):
    """The fallback numba cache folder is ``<tmp>/chainid-numba-<uid>``, created with mode 0700; a folder of that
    name that others may write (mode 0777) is not trusted: a fresh ``mkdtemp`` folder is used instead."""
    import stat
    import tempfile

    import chainid.infra.numba_cache as nc

    monkeypatch.setattr(tempfile, "gettempdir", lambda: str(tmp_path))
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    own = tmp_path / f"chainid-numba-{os.getuid()}"
    assert nc._private_temp_dir() == str(own)
    assert stat.S_IMODE(os.stat(own).st_mode) & 0o077 == 0
    os.chmod(own, 0o777)
    other = nc._private_temp_dir()
    assert other != str(own) and os.path.basename(other).startswith("chainid-numba-")
    assert os.path.dirname(other) == str(tmp_path) and stat.S_IMODE(os.stat(other).st_mode) == 0o700


def test_cache_warnings_are_given_once_per_key_as_one_line():
    """``_warn_once``: a NumbaCacheWarning (a RuntimeWarning) per key, the second call with the same key silent,
    another key warned again; line 0 so no source line is printed under it."""
    import warnings

    import chainid.infra.numba_cache as nc

    key = f"test-key-{os.getpid()}-{id(object())}"
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        nc._warn_once(key, "first")
        nc._warn_once(key, "again")
        nc._warn_once(key + "-2", "other")
    assert [str(w.message) for w in got] == ["first", "other"]
    assert all(issubclass(w.category, nc.NumbaCacheWarning) and w.lineno == 0 for w in got)
    assert issubclass(nc.NumbaCacheWarning, RuntimeWarning)


def test_njit_cached_gives_the_recovering_cache_with_and_without_options():
    """``njit_cached`` as ``@njit_cached`` and as ``@njit_cached(**options)``: a compiled dispatcher whose disk
    cache is the recovering one (an unreadable entry is a miss), computing the function."""
    import chainid.infra.numba_cache as nc

    if nc.cache_mode() == "nojit":  # pragma: no cover - NUMBA_DISABLE_JIT=1: plain functions
        pytest.skip("numba JIT disabled")

    @nc.njit_cached
    def twice(v):
        return 2.0 * v

    @nc.njit_cached(fastmath=True)
    def thrice(v):
        return 3.0 * v

    assert twice(1.5) == 3.0 and thrice(1.5) == 4.5
    for disp in (twice, thrice):
        assert type(disp._cache).__name__ in ("_RecoveringCache", "NullCache")


_CALLER = """
from chainid.infra.numba_cache import njit_cached
import dep
from dep import g

@njit_cached
def via_module(x):
    return dep.g(x) * 2.0

@njit_cached
def via_name(x):
    return g(x) * 3.0
"""


def _callers(folder: Path, cache: Path) -> list[float]:
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache),
               PYTHONPATH=os.pathsep.join([str(folder), str(REPO), os.environ.get("PYTHONPATH", "")]))
    env.pop("NUMBA_DISABLE_JIT", None)
    proc = subprocess.run([sys.executable, "-c", "import json, top; print(json.dumps([top.via_module(1.0), "
                           "top.via_name(1.0)]))"], env=env, capture_output=True, text=True, timeout=300, cwd=folder)
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout.splitlines()[-1])


@pytest.mark.slow
def test_a_cached_caller_is_recompiled_when_a_kernel_it_calls_changes(tmp_path):
    """numba stamps a cache entry with the function's own file only: a caller in an unchanged file kept calling the
    old kernel after the kernel's file changed (4.0 for 6.0 below, checked on numba 0.68).  The callee's file is
    part of the stamp now, whether it is called by name or as a module attribute."""
    dep = tmp_path / "dep.py"
    dep.write_text("from chainid.infra.numba_cache import njit_cached\n\n@njit_cached\ndef g(x):\n    return x + 1.0\n")
    (tmp_path / "top.py").write_text(_CALLER)
    cache = tmp_path / "cache"
    assert _callers(tmp_path, cache) == [4.0, 6.0]
    st = dep.stat()
    dep.write_text(dep.read_text().replace("x + 1.0", "x + 2.0"))
    os.utime(dep, (st.st_atime + 5, st.st_mtime + 5))  # a later edit, whatever the file system's time resolution
    assert _callers(tmp_path, cache) == [6.0, 9.0]
    assert _callers(tmp_path, cache) == [6.0, 9.0]  # and from the refreshed cache


def test_dependency_stamp_names_the_files_of_the_numba_functions_called_from_a_closure():
    from numba import njit

    from chainid.infra.numba_cache import dependency_stamp

    @njit
    def inner(x):
        return x + 1.0

    def outer(x):  # inner is a closure cell of outer
        return inner(x)

    stamp = dependency_stamp(outer)
    assert [s[0] for s in stamp] == [__file__] and stamp[0][2] == Path(__file__).stat().st_size
    assert dependency_stamp(inner.py_func) == ()
