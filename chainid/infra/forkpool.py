"""Map a function over items on forked worker processes that inherit the caller's state.

A diagnosis' problem (its records, kinematics and column cache: hundreds of megabytes at millions of samples) is
not pickled: the workers are forked after the function and its items are set, so they see them as they are, and
only each result travels back.  The results are the same as ``[fn(x) for x in items]``, in the items' order, and so
are the warnings: each worker records the warnings of its items and this process issues them again, item by item
(so they reach the run's JSON as a serial run's do).

The map runs in this process instead (:func:`can_fork` is 0) when there is one core, off Linux (macOS' system
libraries are not safe in a forked child; Windows has no fork), inside a process that ``multiprocessing`` started
(a benchmark case's pool, a dask worker, a worker of this module: their cores are already taken), or when fewer
than ``min_items`` items would not pay the start of the workers.

The workers ignore SIGINT and die with this process, and a Ctrl-C or an error in an item stops them and reaches the
caller as it was (:func:`chainid.infra.parallel.process_pool`).  A worker
that dies (the OOM killer, a signal) does not hang the map: its items, and all others not done, run in this process,
with a warning.  One map at a time per process (a lock): the workers inherit this module's job.
"""

from __future__ import annotations

import multiprocessing as mp
import os
import sys
import threading
import warnings
from typing import Any, Callable, Sequence

from chainid.infra.parallel import process_pool

__all__ = ["fork_map", "can_fork"]

_JOB: dict[str, Any] = {}
_LOCK = threading.Lock()


def can_fork(workers: int | None = None) -> int:
    """The worker processes a :func:`fork_map` would start here: ``workers`` (default: the cores), or 0 when it
    runs in this process (one worker, not Linux, or a process that ``multiprocessing`` started)."""
    n = workers if workers is not None else (os.cpu_count() or 1)
    if n < 2 or not sys.platform.startswith("linux") or mp.parent_process() is not None:
        return 0
    return int(n)


def _call(i: int) -> tuple[Any, list[tuple[str, type]]]:  # pragma: no cover - runs in the workers
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        out = _JOB["fn"](_JOB["items"][i])
    return out, [(str(w.message), w.category) for w in seen]


def fork_map(fn: Callable[[Any], Any], items: Sequence[Any], workers: int | None = None, min_items: int = 2,
             chunksize: int = 1) -> list[Any]:
    """``[fn(x) for x in items]``, on forked workers where that is possible and worth it (see the module docstring).

    Parameters
    ----------
    fn : callable
        Any function of one item (a closure too: it is inherited, not pickled); its results must pickle.
    items : sequence
        The items, inherited by the workers.
    workers : int, optional
        Worker processes (default: the cores), at most one per item.
    min_items : int
        Fewer items than this run in this process.
    chunksize : int
        Items handed to a worker at a time (>= 1).

    Returns
    -------
    list
        ``fn(item)`` per item, in order.
    """
    items = list(items)
    n = can_fork(workers)
    if not n or len(items) < max(2, min_items):
        return [fn(x) for x in items]
    with _LOCK:
        _JOB.update(fn=fn, items=items)
        try:
            outs = _run(min(n, len(items)), len(items), max(1, int(chunksize)))
        finally:
            _JOB.clear()
    if outs is None:  # a worker died: everything again, here (deterministic items)
        warnings.warn("a worker process died (killed, or out of memory): the items ran again in this process",
                      RuntimeWarning, stacklevel=2)
        return [fn(x) for x in items]
    results = []
    for out, seen in outs:
        for msg, cat in seen:
            warnings.warn(msg, cat, stacklevel=2)
        results.append(out)
    return results


def _run(workers: int, n: int, chunksize: int) -> list[Any] | None:
    """The workers' results, or None when one of them died."""
    from concurrent.futures.process import BrokenProcessPool

    try:
        with process_pool(workers, "fork") as ex:
            return list(ex.map(_call, range(n), chunksize=chunksize))
    except BrokenProcessPool:
        return None
