"""Shared timing helper of the benchmark scripts (imported by run.py, dynamics_bench.py, records_bench.py)."""

from __future__ import annotations

import statistics
import time
from typing import Callable


def median_time(fn: Callable[[], object], reps: int) -> float:
    """Median wall time [s] of ``reps`` calls of ``fn`` (perf_counter)."""
    ts = []
    for _ in range(reps):
        t0 = time.perf_counter()
        fn()
        ts.append(time.perf_counter() - t0)
    return statistics.median(ts)
