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

Workers and signals: the worker processes are started with SIGINT ignored (they
inherit SIG_IGN; a pool initializer and a dask preload set it again), so a Ctrl-C
at the terminal, which reaches the whole process group, interrupts only this
process; it cancels the cases and stops the workers (no traceback from any
worker).  A Ctrl-C while the workers start (a dask LocalCluster: a few seconds)
is ignored.  SIGTERM to this process does the same clean-up
and exits with 143 (``SystemExit``): no pool process outlives it.

A parent that is killed outright (SIGKILL, the OOM killer) runs no clean-up, so every worker this module starts
watches its parent itself (:func:`die_with_parent`): on Linux the kernel sends it SIGKILL when its parent dies
(``prctl(PR_SET_PDEATHSIG)``, set in the pool's initializer and in the dask workers' preload; a LocalCluster's
nannies run inside this process), and a watchdog thread, on every system, ends it within :data:`WATCHDOG_S` seconds of its parent's end
(it polls ``os.getppid()``, which changes when the parent is gone).  No orphan keeps running a case.

Worker count: ``min(n_workers or cores, cases, MAX_WORKERS)``, with
:data:`MAX_WORKERS` = 4 × the machine's cores, at most 64.  The cases are
CPU-bound, so more workers than cores only add start-up time (~1 s each) and
memory (~150 MB of numpy/numba/scipy per process); 4× leaves room for cases
that wait on I/O, and 64 bounds the memory of a large machine (~10 GB).  A
larger request is capped with a ``RuntimeWarning``.

A scheduler address is probed first (5 s): a dask scheduler greets a new TCP
connection with its handshake; a server that sends nothing (an HTTP server) or
something else (a proxy's "HTTP/1.1 400") is refused with a one-line
``ValueError`` within ~5 s instead of a hang or a ``MemoryError``.
"""
from __future__ import annotations

import contextlib
import gc
import os
import signal
import socket
import sys
import threading
import time
import warnings
from collections.abc import Callable, Iterable, Iterator
from typing import Any

__all__ = ["run_cases", "dask_available", "SCHEDULERS", "MAX_WORKERS", "worker_count", "probe_scheduler",
           "die_with_parent", "worker_init", "stop_pool", "sigint_ignored", "process_pool"]

#: The named schedulers; any other string is a dask scheduler address.
SCHEDULERS: tuple[str, ...] = ("local", "processes", "serial")

#: Most worker processes one call starts: 4 × the machine's cores, at most 64 (see the module notes).
MAX_WORKERS: int = min(64, 4 * (os.cpu_count() or 1))

#: Seconds a scheduler address has to greet a new connection with the dask handshake.
PROBE_TIMEOUT_S = 5.0

#: Poll interval [s] of a worker's watchdog on its parent (the fallback of PR_SET_PDEATHSIG).
WATCHDOG_S = 0.5

_PR_SET_PDEATHSIG = 1  # <linux/prctl.h>


def worker_count(n_workers: int | None, n_cases: int) -> int:
    """Worker processes for ``n_cases`` cases: ``min(n_workers or cores, n_cases, MAX_WORKERS)`` (>= 1).

    A request above :data:`MAX_WORKERS` is capped with a ``RuntimeWarning``.
    """
    if n_workers is not None and n_workers > MAX_WORKERS:
        warnings.warn(f"n_workers = {n_workers} is more than this machine runs usefully; capped at {MAX_WORKERS} "
                      f"(4 x {os.cpu_count()} cores, at most 64)", RuntimeWarning, stacklevel=3)
    want = n_workers if n_workers is not None else (os.cpu_count() or 1)
    return max(1, min(want, n_cases, MAX_WORKERS))


@contextlib.contextmanager
def sigint_ignored() -> Iterator[None]:
    """Ignore SIGINT (SIG_IGN) while worker processes are started: an ignored signal stays ignored across
    exec, and Python then installs no KeyboardInterrupt handler, so the workers never see a Ctrl-C (no
    traceback each, no race with their start-up).  A Ctrl-C in this window is lost (a blocked mask would
    keep it, but spawned children get a fresh mask); press it again once the workers run."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    old = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, old)


def _terminated(signum: int, frame: Any) -> None:
    raise SystemExit(128 + signum)


@contextlib.contextmanager
def _sigterm_cleans_up() -> Iterator[None]:
    """SIGTERM raises SystemExit(143) here, so the ``finally`` clean-up stops the workers before the exit."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    old = signal.signal(signal.SIGTERM, _terminated)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, old)


def _parent_death_signal() -> bool:
    """Ask the kernel to SIGKILL this process when its parent ends (Linux ``prctl``); False where unavailable."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        return libc.prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0) == 0
    except (OSError, AttributeError):  # no libc symbol: the watchdog alone
        return False


def _watchdog(parent: int, interval: float) -> None:  # pragma: no cover - runs in the workers
    while True:
        time.sleep(interval)
        if os.getppid() != parent:
            os._exit(1)  # the parent is gone: end now (no clean-up to run, the results have no reader)


def die_with_parent(parent: int | None = None, interval: float = WATCHDOG_S) -> None:
    """End this (worker) process when its parent process ends, however the parent ends (SIGKILL included).

    Parameters
    ----------
    parent : int, optional
        The expected parent pid (default: the current parent).  When the parent already is another process
        (the expected one ended before this call), the process ends at once.
    interval : float
        Seconds between the watchdog's looks at the parent (> 0).

    Notes
    -----
    Linux: ``prctl(PR_SET_PDEATHSIG, SIGKILL)``; everywhere: a daemon thread that polls ``os.getppid()``.
    """
    expected = os.getppid() if parent is None else int(parent)
    _parent_death_signal()
    if os.getppid() != expected:  # the parent ended before the death signal was set
        os._exit(1)
    threading.Thread(target=_watchdog, args=(expected, float(interval)), name="chainid-parent-watchdog",
                     daemon=True).start()


def worker_init(parent: int | None = None) -> None:  # pragma: no cover - runs in the workers
    """A pool worker's start: SIGINT ignored, and it ends with its parent (``parent``: the expected pid)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    die_with_parent(parent)


def dask_setup(worker: Any) -> None:  # pragma: no cover - runs in the dask workers
    """dask preload hook (``preload=["chainid.infra.parallel"]``): a LocalCluster worker ignores SIGINT and ends
    with its parent, the process whose nanny started it (:func:`die_with_parent`).

    A Ctrl-C reaches the whole process group; this process (the client) cancels the cases and closes the
    cluster, so the workers need not, and must not print a traceback each.
    """
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    die_with_parent()


def _refused(address: str, why: str) -> ValueError:
    return ValueError(f"scheduler = {address!r} is invalid: {why}; valid values are None, {list(SCHEDULERS)} or "
                      "the address of a running dask scheduler (e.g. 'tcp://host:8786')")


def probe_scheduler(address: str, timeout: float = PROBE_TIMEOUT_S) -> None:
    """Check that a dask scheduler answers at a ``tcp://host:port`` (or ``host:port``) address.

    A dask scheduler sends its handshake as soon as a connection is accepted: an 8-byte little-endian
    length (a few hundred bytes), then msgpack.  Other schemes (tls://, ucx://, inproc://) are not probed.

    Raises
    ------
    ValueError
        No connection, nothing within ``timeout`` seconds, the connection closed, or a greeting that is
        not a dask handshake (one line naming the address).
    """
    scheme, _, rest = address.rpartition("://")
    if scheme not in ("", "tcp"):
        return
    host, _, port = rest.rpartition(":")
    host = host.strip("[]")
    if not host or not port.isdigit():
        raise _refused(address, "expected host:port")
    deadline = time.monotonic() + timeout
    try:
        with socket.create_connection((host, int(port)), timeout=timeout) as sock:
            head = b""
            while len(head) < 8:
                left = deadline - time.monotonic()
                if left <= 0:
                    raise _refused(address, f"the server there sent no dask handshake within {timeout:g} s "
                                            "(not a dask scheduler; an HTTP server?)")
                sock.settimeout(left)
                try:
                    chunk = sock.recv(8 - len(head))
                except socket.timeout:
                    continue
                if not chunk:
                    raise _refused(address, "the server there closed the connection without a dask handshake")
                head += chunk
    except OSError as exc:
        raise _refused(address, f"no dask scheduler answers at that address ({exc.strerror or exc})") from None
    size = int.from_bytes(head, "little")
    if not 0 < size <= 1 << 20:
        shown = head.decode("latin-1").encode("unicode_escape").decode()
        raise _refused(address, f"the server there answered {shown!r}..., not a dask handshake")


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
        raise ValueError(f"n_workers = {n_workers!r} is invalid: valid values are None or an int >= 1 "
                         f"(capped at {MAX_WORKERS})")


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
        Worker processes for ``"local"``/``"processes"``; default the cores.
        Capped at the number of cases and at :data:`MAX_WORKERS` (see
        :func:`worker_count`).  Ignored for ``"serial"`` and for an existing cluster.
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
    workers = worker_count(n_workers, len(cases))
    if name not in SCHEDULERS:
        probe_scheduler(name)  # before the progress bar: a bad address is one line
    bar = _Bar(len(cases), desc, progress)
    try:
        with _sigterm_cleans_up():
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
    from concurrent.futures import FIRST_EXCEPTION, wait

    with process_pool(workers, "spawn") as ex:
        with sigint_ignored():  # the workers start on submit
            futures = [ex.submit(fn, c) for c in cases]
        pending = set(futures)
        while pending:
            done, pending = wait(pending, timeout=0.5, return_when=FIRST_EXCEPTION)
            for f in done:
                if f.exception() is not None:
                    raise f.exception()
            bar.update(len(done))
        return [f.result() for f in futures]


@contextlib.contextmanager
def process_pool(workers: int, start: str = "spawn") -> Iterator[Any]:
    """A ``concurrent.futures.ProcessPoolExecutor`` of ``workers`` processes started by ``start`` ("spawn",
    "fork"), whose workers ignore SIGINT and die with this process (:func:`worker_init`).  Leaving the block
    normally shuts the pool down; leaving it by any exception (a Ctrl-C included) stops its workers at once
    (:func:`stop_pool`) and re-raises."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    before = set(multiprocessing.active_children())
    ex = ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context(start),
                             initializer=worker_init, initargs=(os.getpid(),))
    try:
        yield ex
    except BaseException:
        with sigint_ignored():  # a second Ctrl-C must not break the clean-up half-way
            stop_pool(ex, before)
        raise
    ex.shutdown(wait=True)


def stop_pool(ex: Any, before: set) -> None:
    """Cancel what has not started; stop what is running (no orphan workers)."""
    import multiprocessing

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
            with sigint_ignored():
                cluster = LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True,
                                       # (a worker's case error comes back as an exception; shutdown
                                       # chatter such as a heartbeat to a closed scheduler is not shown)
                                       dashboard_address=None, silence_logs=logging.CRITICAL,
                                       preload=["chainid.infra.parallel"])
                client = Client(cluster)
        else:
            # bytes that pass the probe but are no dask handshake make dask's reader raise almost anything
            # (ValueError, TypeError, IndexError, struct.error, MemoryError, OSError) and log a CRITICAL
            # traceback: one line instead, and dask's logs held back while connecting
            previous = logging.root.manager.disable
            logging.disable(logging.CRITICAL)
            why = ""
            try:
                client = Client(address, timeout="10s")
            except Exception as exc:  # what a non-scheduler can provoke
                why = f"{type(exc).__name__}: {str(exc)[:200]}"
            finally:
                logging.disable(previous)
            if why:
                # the half-built Client is garbage now: collect it here, where no lock is held, so that its
                # finaliser (which closes its connections on dask's loop thread) cannot run inside a later
                # thread start's wait and block it (seen once as a hang of the test suite)
                gc.collect()
                raise _refused(address, f"no dask scheduler answers at that address ({why})")
        futures = client.map(fn, cases, pure=False)
        for fut in as_completed(futures):
            if fut.status == "error":
                fut.result()  # re-raises the case's exception
            bar.update()
        return client.gather(futures)
    finally:
        with sigint_ignored():  # a second Ctrl-C must not break the clean-up half-way
            if client is not None:
                try:
                    if futures:
                        client.cancel(futures)
                finally:
                    client.close()
            if cluster is not None:
                cluster.close()
