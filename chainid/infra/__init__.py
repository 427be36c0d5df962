"""Plumbing every floor may use: atomic files and strict JSON (:mod:`.fileio`), parallel execution on
dask.distributed or a process pool (:mod:`.parallel`), a numba cache that never crashes (:mod:`.numba_cache`)
and progress bars on a terminal (:mod:`.progress`), exact CSV text of doubles by a numba kernel
(:mod:`.floattext`).
Nothing here knows about chains.
"""
from __future__ import annotations

from .lazy import exports

#: Public name -> module of this package that defines it (imported on first use, so that importing the
#: package stays cheap).
_LAZY = {
    "OutputError": "fileio",
    "EXIT_INTERRUPTED": "fileio",
    "check_output_file": "fileio",
    "check_output_dir": "fileio",
    "atomic_open": "fileio",
    "atomic_write_text": "fileio",
    "to_jsonable": "jsonio",
    "dumps_json": "jsonio",
    "write_json": "fileio",
    "json_to_stdout": "fileio",
    "check_inputs_not_outputs": "fileio",
    "replace_file": "fileio",
    "save_figure": "fileio",
    "safe_filename": "fileio",
    "deferred_sigint": "fileio",
    "interrupted": "fileio",
    "exports": "lazy",
    "NumbaCacheWarning": "numba_cache",
    "load_kernel_module": "numba_cache",
    "njit_cached": "numba_cache",
    "cache_mode": "numba_cache",
    "run_cases": "parallel",
    "dask_available": "parallel",
    "SCHEDULERS": "parallel",
    "MAX_WORKERS": "parallel",
    "worker_count": "parallel",
    "probe_scheduler": "parallel",
    "progress_enabled": "progress",
    "csv_chunks": "floattext",
    "progress_iter": "progress",
}

__all__ = sorted(_LAZY)
__getattr__, __dir__ = exports(__name__, _LAZY, globals())
