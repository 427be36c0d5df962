"""Import the generated numba kernels so that numba's on-disk cache never crashes chainid.

Numba picks a cache folder for an ``@njit(cache=True)`` function when the function
is *decorated*, i.e. when its module is imported: ``numba.core.caching.CacheImpl``
tries its locators in order (``UserProvidedCacheLocator``: ``NUMBA_CACHE_DIR`` /
``numba.config.CACHE_DIR``; ``InTreeCacheLocator``: ``__pycache__`` beside the
source; ``UserWideCacheLocator``: the per-user cache folder, e.g.
``~/.cache/numba``; then the IPython and zip locators), keeps the first whose
folder it can create and write a temporary file in, and raises
``RuntimeError("cannot cache function ...: no locator available")`` when none
works (a read-only install with an unwritable HOME).  A cache entry is read on
the first call of a signature (``Cache.load_overload`` → ``pickle.loads``), so a
truncated ``.nbi``/``.nbc`` file raises ``UnpicklingError`` there.  With
``NUMBA_DISABLE_JIT=1`` the decorators return the Python functions, but an
``@intrinsic`` cannot run in Python (``NotImplementedError``).

:func:`load_kernel_module` imports ``chainid.generated.<name>`` and handles all three:

1. **No writable cache folder**: probe numba's own locators (the same classes,
   in numba's order) for the module's file before importing it; if none works,
   set ``numba.config.CACHE_DIR`` (and ``NUMBA_CACHE_DIR`` for child processes)
   to a private folder in the temporary directory, ``<tmp>/chainid-numba-<uid>``,
   and warn once (:class:`NumbaCacheWarning`).  If that is not writable either,
   import with a locator that never touches the disk and give every kernel
   numba's ``NullCache`` (compiled in memory on each run), again with one warning.
2. **Corrupt or stale cache entry**: every kernel's cache is a :class:`_RecoveringCache`:
   an entry that cannot be read counts as a miss (the kernel is recompiled from
   its source, one warning), and a corrupt index is rewritten when the new entry
   is saved.  numba's index is stamped with the function's own file only; here the
   stamp also holds the files of every numba function it calls
   (:func:`dependency_stamp`), so an edited callee makes its callers' entries stale.
   Only the index and data files of chainid's own kernels are ever
   written (by numba, with its atomic temp-file + rename); nothing is deleted.
3. **NUMBA_DISABLE_JIT=1**: the bit-cast intrinsics of the cube-root start value
   are replaced by their numpy equivalents (``ndarray.view``), so the kernels run
   as plain Python with the same results (slowly: for checks and debugging).
"""
from __future__ import annotations

import functools
import importlib
import importlib.util
import inspect
import os
import sys
import tempfile
import threading
import warnings
from contextlib import contextmanager
from pathlib import Path
from types import ModuleType
from typing import Any, Callable, Iterator

import numpy as np

__all__ = ["NumbaCacheWarning", "load_kernel_module", "njit_cached", "cache_mode", "dependency_stamp"]


class NumbaCacheWarning(RuntimeWarning):
    """Numba's disk cache could not be used as configured; chainid fell back (see the message)."""


_LOCK = threading.RLock()
_STATE: dict[str, str] = {"mode": ""}  # "", "default", "temp", "none" or "nojit"
_WARNED: set[str] = set()


def cache_mode() -> str:
    """How the kernels are cached in this process.

    Returns
    -------
    str
        ``"default"`` (numba's own choice), ``"temp"`` (the fallback folder in the
        temporary directory), ``"none"`` (compiled in memory only), ``"nojit"``
        (``NUMBA_DISABLE_JIT=1``, pure Python) or ``""`` (no kernel loaded yet).
    """
    return _STATE["mode"]


def _warn_once(key: str, message: str) -> None:
    if key not in _WARNED:
        _WARNED.add(key)
        # line 0: no source line under the message, so the warning is one line on stderr
        warnings.warn_explicit(message, NumbaCacheWarning, __file__, 0, module=__name__)


def _probe(py_file: str) -> bool:
    """True if numba would find a cache locator for a function defined in ``py_file``."""
    from numba.core import caching

    namespace: dict = {}
    exec(compile("def _chainid_cache_probe():\n    pass\n", py_file, "exec"), namespace)
    try:
        caching.CompileResultCacheImpl(namespace["_chainid_cache_probe"])
    except RuntimeError:
        return False
    return True


def _private_temp_dir() -> str:
    """A folder only this user can write: ``<tmp>/chainid-numba-<uid>``, else a fresh ``mkdtemp``."""
    base = tempfile.gettempdir()
    uid = os.getuid() if hasattr(os, "getuid") else None
    if uid is not None:
        path = os.path.join(base, f"chainid-numba-{uid}")
        try:
            os.makedirs(path, mode=0o700, exist_ok=True)
            st = os.lstat(path)
            if st.st_uid == uid and not (st.st_mode & 0o022) and os.path.isdir(path):
                return path
        except OSError:
            pass
    return tempfile.mkdtemp(prefix="chainid-numba-")


def _choose_cache(py_file: str) -> str:
    """Make sure numba can cache functions of ``py_file`` (see the module docstring); return the mode."""
    from numba.core import config

    if config.DISABLE_JIT:
        return "nojit"
    if _probe(py_file):
        return "temp" if _STATE["mode"] == "temp" else "default"
    old = config.CACHE_DIR
    try:
        folder = _private_temp_dir()
        config.CACHE_DIR = folder
        if _probe(py_file):
            os.environ["NUMBA_CACHE_DIR"] = folder
            _warn_once("temp", (
                f"numba cannot write its cache beside {os.path.dirname(py_file)!r} nor in the user cache folder; "
                f"caching the compiled kernels in {folder!r} instead (set NUMBA_CACHE_DIR to choose a folder)"
            ))
            return "temp"
    except OSError:
        pass
    config.CACHE_DIR = old
    _warn_once("none", (
        f"numba cannot write a cache for {py_file!r} anywhere (install folder, user cache folder and the "
        "temporary folder are not writable); the kernels are compiled in memory on every run "
        "(set NUMBA_CACHE_DIR to a writable folder to avoid this)"
    ))
    return "none"


class _NoDiskLocator:
    """A numba cache locator that never touches the disk (used with ``NullCache`` only)."""

    def __init__(self, py_func, py_file: str) -> None:
        self._lineno = py_func.__code__.co_firstlineno

    @classmethod
    def from_function(cls, py_func, py_file: str) -> "_NoDiskLocator":
        return cls(py_func, py_file)

    def ensure_cache_path(self) -> None:
        pass

    def get_cache_path(self) -> str:
        return "<no cache>"

    def get_source_stamp(self) -> str:
        return "<no cache>"

    def get_disambiguator(self) -> str:
        return str(self._lineno)


@contextmanager
def _without_disk_cache() -> Iterator[None]:
    from numba.core import config

    old = config.CACHE_LOCATOR_CLASSES
    config.CACHE_LOCATOR_CLASSES = f"{__name__}._NoDiskLocator"
    try:
        yield
    finally:
        config.CACHE_LOCATOR_CLASSES = old


def _called_dispatchers(py_func: Callable) -> list[Any]:
    """The numba dispatchers a Python function's code names: globals (``g(x)``), attributes of global modules
    (``kernels.g(x)``, every code object nested in it included) and closure cells."""
    from numba.core.dispatcher import Dispatcher

    code, names = py_func.__code__, set()
    stack = [code]
    while stack:
        c = stack.pop()
        names.update(c.co_names)
        stack.extend(k for k in c.co_consts if inspect.iscode(k))
    glb = getattr(py_func, "__globals__", {})
    found = [glb[n] for n in names if isinstance(glb.get(n), Dispatcher)]
    for n in names:
        mod = glb.get(n)
        if isinstance(mod, ModuleType):
            found += [a for a in (getattr(mod, m, None) for m in names) if isinstance(a, Dispatcher)]
    for cell in py_func.__closure__ or ():
        try:
            if isinstance(cell.cell_contents, Dispatcher):
                found.append(cell.cell_contents)
        except ValueError:  # an empty cell
            pass
    return found


def dependency_stamp(py_func: Callable) -> tuple[tuple[str, float, int], ...]:
    """The source files of every numba function ``py_func`` calls, directly or through others, with their
    modification time and size: numba's cache checks only the function's own file, so an edit of a kernel in another
    module (a ``git pull`` that changes ``chainid/generated`` and not its callers) left the callers' compiled code
    calling the old kernel; with this in the index's stamp such an entry is stale and recompiled."""
    seen: dict[int, Callable] = {}
    stack = [py_func]
    while stack:
        f = stack.pop()
        for d in _called_dispatchers(f):
            g = d.py_func
            if id(g) not in seen and g is not py_func:
                seen[id(g)] = g
                stack.append(g)
    out = set()
    for g in seen.values():
        try:
            path = inspect.getfile(g)
            st = os.stat(path)
        except (TypeError, OSError):
            continue
        out.add((path, st.st_mtime, st.st_size))
    return tuple(sorted(out))


@functools.lru_cache(maxsize=None)
def _recovering_cache_class():
    from numba.core.caching import FunctionCache

    class _RecoveringCache(FunctionCache):
        """numba's FunctionCache, but an unreadable entry is a miss, a corrupt index is rewritten, and an entry is
        stale when any numba function it calls has changed (:func:`dependency_stamp`)."""

        def _restamp(self) -> None:
            cf = self._cache_file
            if not hasattr(self, "_chainid_stamp"):
                self._chainid_stamp = cf._source_stamp  # numba's: the function's own file
            cf._source_stamp = (self._chainid_stamp, dependency_stamp(self._py_func))

        def load_overload(self, sig, target_context):
            try:
                self._restamp()
                return super().load_overload(sig, target_context)
            except Exception as exc:  # any failure to read or rebuild an entry: compile from source instead
                name = getattr(self._py_func, "__qualname__", "?")
                _warn_once(f"corrupt:{self.cache_path}", (
                    f"numba cache entry of kernel {name!r} ({self._impl.filename_base}.*) in {self.cache_path!r} "
                    f"is unreadable ({type(exc).__name__}: {exc}); recompiling the kernel and rewriting its entry "
                    "(further unreadable entries in this folder are recovered silently)"
                ))
                return None

        def save_overload(self, sig, data):
            try:
                self._restamp()
                super().save_overload(sig, data)
                return
            except Exception:
                pass
            try:  # the index of this function is unreadable: start it afresh (our own file), then save again
                self.flush()
                super().save_overload(sig, data)
            except Exception as exc:  # the compiled kernel is in memory already; only the disk copy is missing
                _warn_once(f"save:{self.cache_path}", (
                    f"could not write the numba cache in {self.cache_path!r} ({type(exc).__name__}: {exc}); "
                    "the kernel stays compiled in memory for this run"
                ))

    return _RecoveringCache


def _harden_dispatcher(obj, mode: str) -> None:
    """Give one numba dispatcher numba's NullCache (mode "none") or the recovering cache."""
    from numba.core.caching import FunctionCache, NullCache

    if mode == "none":
        obj._cache = NullCache()
    elif type(obj._cache) is FunctionCache:
        obj._cache.__class__ = _recovering_cache_class()


def _harden(mod: ModuleType, mode: str) -> None:
    """Give every kernel of ``mod`` a recovering cache (or none), or the pure-Python bit casts under nojit."""
    if getattr(mod, "_chainid_cache_mode", None) == mode:
        return
    if mode == "nojit":
        if hasattr(mod, "_bits"):
            mod._bits = lambda v: np.float64(v).view(np.int64)
        if hasattr(mod, "_from_bits"):
            mod._from_bits = lambda v: np.int64(v).view(np.float64)
    else:
        from numba.core.dispatcher import Dispatcher

        for obj in list(vars(mod).values()):
            if isinstance(obj, Dispatcher):
                _harden_dispatcher(obj, mode)
    mod._chainid_cache_mode = mode


def njit_cached(func: Callable | None = None, **options: Any) -> Any:
    """``numba.njit(cache=True, **options)`` that never fails because of the cache.

    For chainid's own hand-written numba functions (the generated kernels go through
    :func:`load_kernel_module`): the same fallbacks (temporary folder, then no disk
    cache, one warning each) and corrupt-entry recovery.  With ``NUMBA_DISABLE_JIT=1``
    it returns the Python function.  Use as ``@njit_cached`` or ``@njit_cached(fastmath=True)``.
    """
    def decorate(f: Callable) -> Any:
        try:
            from numba import njit
        except ImportError:  # pragma: no cover - numba is a dependency; plain Python then
            return f

        with _LOCK:
            mode = _choose_cache(inspect.getfile(f))
            _STATE["mode"] = _STATE["mode"] or mode
            if mode == "none":
                with _without_disk_cache():
                    disp = njit(cache=True, **options)(f)
            else:
                disp = njit(cache=True, **options)(f)
            if mode != "nojit":
                _harden_dispatcher(disp, mode)
        return disp

    return decorate(func) if func is not None else decorate


def load_kernel_module(name: str) -> ModuleType:
    """Import ``chainid.generated.<name>`` with a usable numba cache (see the module docstring).

    Parameters
    ----------
    name : str
        Module name inside ``chainid.generated``, e.g. ``"stiffness_paper"``.

    Returns
    -------
    ModuleType
        The module; its kernels compile on first call and never fail because of the cache.
    """
    full = f"chainid.generated.{name}"
    with _LOCK:
        mod = sys.modules.get(full)
        if mod is not None and getattr(mod, "_chainid_cache_mode", None):
            return mod
        spec = importlib.util.find_spec(full)
        if spec is None or spec.origin is None:
            raise ImportError(f"kernel module {full!r} not found")
        mode = _choose_cache(str(Path(spec.origin)))
        if mod is None:
            if mode == "none":
                with _without_disk_cache():
                    mod = importlib.import_module(full)
            else:
                mod = importlib.import_module(full)
        _STATE["mode"] = mode
        _harden(mod, mode)
        return mod
