"""The one place for parallel execution of independent cases (sweeps, benchmark-gap).

:func:`run_cases` maps a picklable top-level function over a list of cases and
returns the results in the order of the cases, on one of four back ends:

* ``None`` / ``"local"`` - a dask.distributed ``LocalCluster`` of worker
  processes (one thread each) when ``distributed`` is importable (the optional
  extra ``chainid[dask]``), otherwise a ``concurrent.futures.ProcessPoolExecutor``;
* ``"processes"`` - a ``ProcessPoolExecutor`` (spawned workers: safe with numba's
  and dask's threads in the parent);
* ``"serial"`` - a plain loop in this process (debugging, profiling, tiny runs);
* any other string - the address of a running dask scheduler, e.g.
  ``"tcp://10.0.0.5:8786"`` (``Client(address)``; the cluster is left running).

A progress bar (tqdm) goes to stderr on a terminal unless ``progress=False`` (none in pipes and logs).  On an exception
in a case, or on SIGINT (KeyboardInterrupt), pending cases are cancelled, the
workers this function started are shut down (no orphan processes) and the
exception is re-raised; a case's own exception is re-raised as it was.
"""
from __future__ import annotations

import os
import sys
import time
from collections.abc import Callable, Iterable
from typing import Any

__all__ = ["run_cases", "dask_available", "SCHEDULERS"]

#: The named schedulers; any other string is a dask scheduler address.
SCHEDULERS: tuple[str, ...] = ("local", "processes", "serial")


def dask_available() -> bool:
    """True when dask.distributed can be imported (the ``dask`` extra is installed)."""
    try:
        import distributed  # noqa: F401
    except Exception:  # ImportError, or a broken install
        return False
    return True


class _Bar:
    """A progress bar (tqdm) on stderr, shown only on a terminal (:func:`chainid.infra.progress.progress_enabled`):
    quiet when stderr is a pipe or a log, when ``enabled`` is False, or without tqdm."""

    def __init__(self, total: int, desc: str, enabled: bool):
        from chainid.infra.progress import progress_enabled

        self.enabled = bool(enabled and total > 0 and progress_enabled())
        self._bar = None
        if self.enabled:
            from tqdm import tqdm

            self._bar = tqdm(total=total, desc=desc or None, file=sys.stderr, leave=True, dynamic_ncols=True)

    def update(self, n: int = 1) -> None:
        if self._bar is not None:
            self._bar.update(n)

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None


def _check_args(fn: Callable[[Any], Any], scheduler: str | None, n_workers: int | None) -> None:
    if not callable(fn):
        raise ValueError(f"fn = {fn!r} is invalid: valid values are callables (a picklable top-level function)")
    if scheduler is not None and (not isinstance(scheduler, str) or not scheduler.strip()):
        raise ValueError(f"scheduler = {scheduler!r} is invalid: valid values are None, {list(SCHEDULERS)} "
                         "or the address of a dask scheduler (e.g. 'tcp://host:8786')")
    if n_workers is not None and (isinstance(n_workers, bool) or not isinstance(n_workers, int) or n_workers < 1):
        raise ValueError(f"n_workers = {n_workers!r} is invalid: valid values are None or an int >= 1")


def run_cases(
    fn: Callable[[Any], Any],
    cases: Iterable[Any],
    *,
    scheduler: str | None = None,
    n_workers: int | None = None,
    progress: bool = True,
    desc: str = "",
) -> list:
    """Run ``fn(case)`` for every case and return the results in the order of ``cases``.

    Parameters
    ----------
    fn : callable
        A picklable top-level function of one case (module-level ``def``; not a
        lambda or closure unless ``scheduler="serial"``).
    cases : iterable
        The cases (picklable); consumed once into a list.
    scheduler : str, optional
        ``None`` or ``"local"``: dask.distributed ``LocalCluster`` (processes,
        one thread per worker) when importable, else a process pool;
        ``"processes"``: ``concurrent.futures.ProcessPoolExecutor``;
        ``"serial"``: a loop in this process; any other string: the address of
        an existing dask scheduler.
    n_workers : int, optional
        Worker processes for ``"local"``/``"processes"``; default
        ``min(os.cpu_count(), len(cases))``.  Ignored for ``"serial"`` and for
        an existing cluster.
    progress : bool
        Progress bar on stderr when it is a terminal (default on).
    desc : str
        Label in front of the progress bar.

    Returns
    -------
    list
        ``[fn(c) for c in cases]``, computed on the chosen back end.

    Raises
    ------
    ValueError
        Bad ``fn``, ``scheduler`` or ``n_workers`` (the message names the field and the valid values).
    Exception
        The first exception raised by a case, after the other cases were cancelled and the workers shut down.
    KeyboardInterrupt
        On SIGINT, after the same clean-up.
    """
    _check_args(fn, scheduler, n_workers)
    cases = list(cases)
    if not cases:
        return []
    name = "local" if scheduler is None else scheduler.strip()
    workers = n_workers or max(1, min(os.cpu_count() or 1, len(cases)))
    bar = _Bar(len(cases), desc, progress)
    try:
        if name == "serial":
            return _run_serial(fn, cases, bar)
        if name == "processes" or (name == "local" and not dask_available()):
            return _run_processes(fn, cases, workers, bar)
        if name == "local":
            return _run_dask(fn, cases, bar, n_workers=workers, address=None)
        return _run_dask(fn, cases, bar, n_workers=None, address=name)
    finally:
        bar.close()


def _run_serial(fn: Callable[[Any], Any], cases: list, bar: _Bar) -> list:
    out = []
    for case in cases:
        out.append(fn(case))
        bar.update()
    return out


def _run_processes(fn: Callable[[Any], Any], cases: list, workers: int, bar: _Bar) -> list:
    import multiprocessing
    from concurrent.futures import FIRST_EXCEPTION, ProcessPoolExecutor, wait

    before = set(multiprocessing.active_children())
    ex = ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("spawn"))
    ok = False
    try:
        futures = [ex.submit(fn, c) for c in cases]
        pending = set(futures)
        while pending:
            done, pending = wait(pending, timeout=0.5, return_when=FIRST_EXCEPTION)
            for f in done:
                if f.exception() is not None:
                    raise f.exception()
            bar.update(len(done))
        results = [f.result() for f in futures]
        ok = True
        return results
    finally:
        if ok:
            ex.shutdown(wait=True)
        else:
            # Cancel what has not started; stop what is running (no orphan workers).
            procs = list((getattr(ex, "_processes", None) or {}).values())
            ex.shutdown(wait=False, cancel_futures=True)
            # every worker this pool started, including one spawned after the snapshot
            procs += [p for p in multiprocessing.active_children() if p not in before and p not in procs]
            for p in procs:
                if p.is_alive():
                    p.terminate()
            for p in procs:
                p.join(timeout=5)
            ex.shutdown(wait=True)  # the pool's manager thread ends too (it may still start a worker)
            deadline = time.monotonic() + 10.0
            while time.monotonic() < deadline:  # and no worker of this pool outlives the call
                late = [p for p in multiprocessing.active_children() if p not in before]
                if not late:
                    break
                for p in late:
                    p.terminate()
                    p.join(timeout=1)


def _run_dask(fn: Callable[[Any], Any], cases: list, bar: _Bar, *, n_workers: int | None,
              address: str | None) -> list:
    import logging

    from distributed import Client, LocalCluster, as_completed

    cluster = None
    client = None
    futures: list = []
    try:
        if address is None:
            cluster = LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True,
                                   dashboard_address=None, silence_logs=logging.ERROR)
            client = Client(cluster)
        else:
            try:
                client = Client(address, timeout="10s")
            except OSError as exc:
                raise ValueError(f"scheduler = {address!r} is invalid: no dask scheduler answers at that address "
                                 f"({exc}); valid values are None, {list(SCHEDULERS)} or a running scheduler's "
                                 "address") from exc
        futures = client.map(fn, cases, pure=False)
        for fut in as_completed(futures):
            if fut.status == "error":
                fut.result()  # re-raises the case's exception
            bar.update()
        return client.gather(futures)
    finally:
        if client is not None:
            try:
                if futures:
                    client.cancel(futures)
            finally:
                client.close()
        if cluster is not None:
            cluster.close()
