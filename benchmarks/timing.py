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


#: Python source for a child process that measures the peak memory of one step: ``status(key)`` reads
#: /proc/self/status [bytes]; ``base`` is the resident set before the step; ``reset`` says whether the peak
#: (VmHWM) was reset (clear_refs), so that imports' own transient peak does not count.  After the step, the
#: child takes its peak as ``status("VmHWM") if reset else ru_maxrss``: see :data:`PEAK_RSS_AFTER`.
PEAK_RSS_BEFORE = r"""
import gc, resource

def status(key):
    with open("/proc/self/status") as fh:
        for line in fh:
            if line.startswith(key + ":"):
                return int(line.split()[1]) * 1024
    return 0

gc.collect()
base = status("VmRSS")
try:  # reset the peak (VmHWM) so that the imports' own transient peak does not count
    with open("/proc/self/clear_refs", "w") as fh:
        fh.write("5")
    reset = True
except OSError:
    reset = False
"""
PEAK_RSS_AFTER = r"""
peak = status("VmHWM") if reset else resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
"""


def run_child(code: str, args: list[str], root: str) -> dict:
    """Run ``code`` in a fresh interpreter (``root`` on PYTHONPATH) and return the JSON of its last line."""
    import json
    import os
    import subprocess
    import sys

    out = subprocess.run([sys.executable, "-c", code, *args], capture_output=True, text=True,
                         env={**os.environ, "PYTHONPATH": root})
    if out.returncode != 0:
        raise SystemExit(f"child failed: {out.stderr.strip()}")
    return json.loads(out.stdout.strip().splitlines()[-1])
