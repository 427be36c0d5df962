"""Map a function over items on forked worker processes that inherit the caller's state.

A diagnosis' problem (its records, kinematics and column cache: hundreds of megabytes at millions of samples) is
not pickled: the workers are forked after the function and its items are set, so they see them as they are, and
only each result travels back.  The map runs in this process instead when there is one core, fewer than
``min_items`` items, no ``fork`` start method (Windows, macOS' default), or when this process is itself a daemonic
worker (a benchmark's pool, a dask worker: no children allowed, its cores already taken).  The results are the
same either way, in the items' order.

The workers ignore SIGINT (a Ctrl-C at the terminal interrupts this process, which then terminates the pool) and
die with this process (:func:`chainid.infra.parallel.die_with_parent`): a killed diagnosis leaves no orphan.
"""

from __future__ import annotations

import multiprocessing as mp
import os
import signal
from typing import Any, Callable, Sequence

from chainid.infra.parallel import die_with_parent

__all__ = ["fork_map", "can_fork"]

_JOB: dict[str, Any] = {}


def can_fork(workers: int | None = None) -> int:
    """The worker processes a :func:`fork_map` would use here (0: it runs in this process)."""
    n = workers if workers is not None else (os.cpu_count() or 1)
    if n < 2 or mp.current_process().daemon or "fork" not in mp.get_all_start_methods():
        return 0
    return n


def _init() -> None:  # pragma: no cover - runs in the workers
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    die_with_parent()


def _call(i: int) -> Any:
    return _JOB["fn"](_JOB["items"][i])


def fork_map(fn: Callable[[Any], Any], items: Sequence[Any], workers: int | None = None, min_items: int = 2,
             chunksize: int = 1) -> list[Any]:
    """``[fn(x) for x in items]``, on forked workers when that is possible and worth it (module docstring)."""
    items = list(items)
    n = can_fork(workers)
    if not n or len(items) < max(2, min_items):
        return [fn(x) for x in items]
    _JOB.update(fn=fn, items=items)
    try:
        with mp.get_context("fork").Pool(min(n, len(items)), initializer=_init) as pool:
            return pool.map(_call, range(len(items)), chunksize=max(1, chunksize))
    finally:
        _JOB.clear()
