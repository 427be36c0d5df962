"""Time and score the full ``chainid benchmark-gap`` grid (issue 18: <= 20 minutes here with the non-harmonic
families and the transfer cases; issue 10: the harmonic families alone <= 15 minutes).

Usage::

    python benchmarks/gap_bench.py [--workers N] [--scheduler ADDRESS] [--json F] [--force]

Prints the wall time of the whole grid, the time per case, the serial-equivalent time (sum of the per-case
diagnosis times) and the parallel efficiency measured in the same run, then the family rates against the
issues' targets: harmonic single >= 92 %, compound both named >= 85 %, control none >= 95 %; non-harmonic
(random, sweep, start-up with load steps, earthquake-like; each reported apart, then pooled) single >= 90 %,
compound >= 80 %, control >= 95 %, out-of-library never named with confidence; transfer median shrinkage >= 0.7.
"""

from __future__ import annotations

import argparse
import os
import sys
import time


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--workers", type=int, default=None, help="worker processes (default: the machine's cores)")
    ap.add_argument("--scheduler", default=None, help="dask scheduler address, local, processes or serial")
    ap.add_argument("--json", default=None, help="write the benchmark summary (every row) here")
    ap.add_argument("--force", action="store_true", help="overwrite --json")
    ap.add_argument("--excitations", default=None, help="comma-separated subset (default: all)")
    a = ap.parse_args(argv)
    from chainid.gap.benchmark.grid import grid, run_benchmark

    from chainid.gap.benchmark.grid import ALL_EXCITATIONS

    exc = tuple(a.excitations.split(",")) if a.excitations else ALL_EXCITATIONS
    n = len(grid(excitations=exc))
    t0 = time.perf_counter()
    s = run_benchmark(json_path=a.json, overwrite=a.force, scheduler=a.scheduler, n_workers=a.workers,
                      excitations=exc)
    wall = time.perf_counter() - t0
    serial = sum(r["seconds"] for r in s["rows"])
    workers = a.workers or os.cpu_count() or 1
    print(f"\n{n} cases in {wall:.0f} s wall ({wall / n:.2f} s per case); serial-equivalent diagnosis time "
          f"{serial:.0f} s; speed-up {serial / wall:.2f}x on {workers} worker(s) "
          f"(efficiency {serial / wall / workers:.0%}); target <= 1200 s: {'PASS' if wall <= 1200 else 'MISS'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
