"""Progress bars for long work (reading many or large files, benchmark-gap, sweeps, diagnoses).

A bar (tqdm) appears only on a terminal: quiet when stderr is not a TTY (pipes, logs, CI) or when asked.
"""
from __future__ import annotations

import sys
import time
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Any, Iterable, Iterator, TypeVar

__all__ = ["progress_enabled", "progress_iter", "Stages", "stage", "tracking"]

T = TypeVar("T")


def progress_enabled(quiet: bool = False) -> bool:
    """True when a bar should show: not ``quiet``, stderr is a terminal, and tqdm is installed."""
    if quiet:
        return False
    try:
        if not sys.stderr.isatty():
            return False
    except (AttributeError, ValueError):  # a closed or replaced stderr
        return False
    try:
        import tqdm  # noqa: F401
    except ImportError:
        return False
    return True


def progress_iter(items: Iterable[T], desc: str = "", total: int | None = None, quiet: bool = False,
                  unit: str = "it") -> Iterator[T]:
    """``items`` with a progress bar on stderr when :func:`progress_enabled`, else ``items`` unchanged."""
    if not progress_enabled(quiet):
        yield from items
        return
    from tqdm import tqdm

    with tqdm(items, desc=desc, total=total, unit=unit, file=sys.stderr, leave=False, dynamic_ncols=True) as bar:
        yield from bar


class Stages:
    """The stages of a long run: a one-line status on a terminal (the stage and its elapsed time, tqdm), and the
    time spent in each stage [s] for a report (:attr:`times`, in the order first entered)."""

    def __init__(self, desc: str, quiet: bool = False):
        self.desc = desc
        self.times: dict[str, float] = {}
        self._current: str | None = None
        self._t0 = time.perf_counter()
        self._bar: Any = None
        if progress_enabled(quiet):
            from tqdm import tqdm

            self._bar = tqdm(total=None, desc=desc, file=sys.stderr, leave=False, dynamic_ncols=True,
                             bar_format="{desc}: {postfix} [{elapsed}]")

    def enter(self, name: str, detail: str = "") -> None:
        """Start stage ``name`` (the previous one ends); ``detail`` shows beside it (e.g. a candidate)."""
        now = time.perf_counter()
        if self._current is not None:
            self.times[self._current] = self.times.get(self._current, 0.0) + now - self._t0
        self._current, self._t0 = name, now
        if self._bar is not None:
            self._bar.set_postfix_str(f"{name}{': ' + detail if detail else ''}", refresh=True)

    def close(self) -> dict[str, float]:
        """End the last stage; returns the times [s] per stage."""
        self.enter("done")
        self._current = None
        if self._bar is not None:
            self._bar.close()
        return dict(self.times)


_STAGES: ContextVar[Stages | None] = ContextVar("chainid_stages", default=None)


def stage(name: str, detail: str = "") -> None:
    """Report entering stage ``name`` to the run being tracked (:func:`tracking`); nothing when none is."""
    s = _STAGES.get()
    if s is not None:
        s.enter(name, detail)


@contextmanager
def tracking(desc: str, quiet: bool = False) -> Iterator[Stages]:
    """Track the stages reported by :func:`stage` within the block (a status line on a terminal, times kept)."""
    s = Stages(desc, quiet)
    tok = _STAGES.set(s)
    try:
        yield s
    finally:
        _STAGES.reset(tok)
        s.close()
