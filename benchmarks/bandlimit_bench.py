"""Time the band-limited comparison's zero-phase filter against its former form, in the same run.

Usage::

    python benchmarks/bandlimit_bench.py [--cases N] [--reps R]

The baseline is the former :func:`chainid.gap.timedomain.bandlimit.band_limited`, reproduced below: each run of a
view through ``scipy.signal.sosfiltfilt`` on its own, which solves the filter's steady state (``sosfilt_zi``) and
validates its input on every call.  The current one solves the steady state once per rate and cut.  Both give the
same bits (checked here on every shape, and pinned by ``tests/gap/timedomain/test_band_limited_comparison.py``).

Prints, per shape (samples, runs, columns), the median time of each and their ratio; then, with ``--cases N``
(default 3), the wall time of the first N resonant cases of the small ODE world (``chainid benchmark-gap
--generator ode --small``) diagnosed with each filter in this process, their verdicts (which must agree) and the
ratio.  A ratio > 1 is a speed-up.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from timing import median_time  # noqa: E402


def former_band_limited(a: np.ndarray, fs: float, f_cut: float, idx: np.ndarray | None = None) -> np.ndarray:
    """The former filter: every run through ``scipy.signal.sosfiltfilt`` on its own."""
    from scipy.signal import sosfiltfilt

    from chainid.gap.core.noise import lowpass_sos
    from chainid.gap.timedomain.bandlimit import runs

    if not math.isfinite(f_cut):
        return a
    sos = lowpass_sos(float(fs), float(f_cut), 1 << 12)  # the design the module uses
    if sos is None:
        return a
    a = np.asarray(a, float)
    starts, ends = runs(a.shape[0], idx)  # the same runs as the current filter's
    long = np.flatnonzero(ends - starts > 3 * (2 * sos.shape[0] + 1))
    if long.size == 0:
        return a
    out = a.copy()
    for i, j in zip(starts[long], ends[long]):
        out[i:j] = sosfiltfilt(sos, a[i:j], axis=0)
    return out


def micro(reps: int) -> None:
    """Median time per call of each filter on views of a record (runs of equal length, as time blocks are)."""
    from chainid.gap.timedomain.bandlimit import band_limited

    rng = np.random.default_rng(0)
    fs, fc = 2000.0, 60.0
    print(f"{'samples':>8} {'runs':>5} {'cols':>5} {'former [ms]':>12} {'current [ms]':>13} {'ratio':>6}")
    for n, runs, cols in [(4000, 1, 1), (20000, 4, 1), (20000, 4, 6), (2000, 4, 1), (30000, 8, 1)]:
        step = n // runs
        idx = np.concatenate([np.arange(2 * i * step, 2 * i * step + step) for i in range(runs)])
        a = rng.normal(size=(idx.size, cols)).squeeze()
        assert np.array_equal(former_band_limited(a, fs, fc, idx), band_limited(a, fs, fc, idx))
        t_old = median_time(lambda: former_band_limited(a, fs, fc, idx), reps)
        t_new = median_time(lambda: band_limited(a, fs, fc, idx), reps)
        print(f"{idx.size:>8} {runs:>5} {cols:>5} {1e3 * t_old:>12.3f} {1e3 * t_new:>13.3f} {t_old / t_new:>6.2f}")


def end_to_end(n_cases: int) -> None:
    """Diagnose the first resonant cases of the small ODE world with each filter; verdicts must agree."""
    import warnings

    import chainid.gap.timedomain.design as design
    from chainid.gap.benchmark.odeworld import run_case, world_cases

    cases = [c for c in world_cases(small=True) if c["base"] == "resonant"][:n_cases]
    current = design.band_limited
    run_case(cases[0])  # compile and warm the caches outside the timing
    totals = {}
    for name, fn in [("former", former_band_limited), ("current", current)]:
        design.band_limited = fn
        t0 = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            rows = [run_case(c) for c in cases]
        totals[name] = (time.perf_counter() - t0, [r["verdict"] for r in rows])
    design.band_limited = current
    (t_old, v_old), (t_new, v_new) = totals["former"], totals["current"]
    print(f"\n{len(cases)} resonant ODE-world cases: former {t_old:.1f} s, current {t_new:.1f} s, "
          f"ratio {t_old / t_new:.2f}; verdicts {'agree' if v_old == v_new else 'DIFFER'}: {v_new}")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cases", type=int, default=3, help="resonant ODE-world cases to diagnose (0: none)")
    ap.add_argument("--reps", type=int, default=50, help="calls per filter timing")
    a = ap.parse_args(argv)
    micro(a.reps)
    if a.cases > 0:
        end_to_end(a.cases)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
