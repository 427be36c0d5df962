"""Progress bars for long work (reading many or large files, benchmark-gap, sweeps, diagnoses).

A bar (tqdm) appears only on a terminal: quiet when stderr is not a TTY (pipes, logs, CI) or when asked.
"""
from __future__ import annotations

import sys
from typing import Iterable, Iterator, TypeVar

__all__ = ["progress_enabled", "progress_iter"]

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
