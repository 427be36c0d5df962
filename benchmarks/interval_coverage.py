"""Coverage of the time route's 90 % intervals in family: how often ``params_ci90`` contains the truth.

One friction case — the linear device of the tests (``tests/recovery_cases.py``: k = 10 N/mm, c = 0.2 N·s/mm,
a preload per record) + Coulomb friction 2·sgn(ẋ) N on the true velocity, 5 records of 2 000 samples at 200 Hz,
band 0.5–4 Hz, σ_x = 1 µm, σ_F = 0.1 N, r4 held out — simulated with ``--seeds`` noise realisations, each
diagnosed with ``--resamples`` resamples (the library restricted to ``friction``: the intervals are under test,
not the selection).  Printed: the share of intervals that contain F_c = 2 N, the seed-to-seed spread of the
estimate, its mean error, and the median half-width of the intervals: the resampling's percentiles alone, and the
reported interval (widened by the sampling's and the displacement noise's biases,
:mod:`chainid.gap.timedomain.discretisation`, :mod:`chainid.gap.timedomain.simex`, and joined with the profile's).
A calibrated 90 % interval covers in 85–95 %.

Usage (from the repository root)::

    python benchmarks/interval_coverage.py [--seeds 40] [--resamples 100]

Nothing is asserted; the test of the same case is tests/gap/timedomain/test_resampling_intervals.py.
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
F_C = 2.0


def one(seed: int, resamples: int) -> dict:
    """The diagnosis of one realisation: estimate, reported interval, the resampling's percentile interval."""
    import recovery_cases as rc
    from chainid.gap.diagnose import diagnose

    recs = rc.linear_random(lambda mo, t: F_C * np.sign(mo(t)[1]), n=2000, band=(0.5, 4.0), seed=seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = diagnose(recs, ["r4"], None, quiet=True, effects=["friction"], max_combo=1, resamples=resamples,
                       seed=seed)
    step = res["steps"][-1]
    raw = res["stability"]["steps"][-1]["params_ci90_percentile"]["friction.F_c"]
    lo, hi = step["params_ci90"]["friction.F_c"]
    return {"est": step["params"]["friction.F_c"], "ci": (lo, hi), "raw": tuple(raw)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seeds", type=int, default=40)
    ap.add_argument("--resamples", type=int, default=100)
    args = ap.parse_args()
    sys.path.insert(0, str(ROOT / "tests"))
    t0 = time.perf_counter()
    rows = [one(s, args.resamples) for s in range(args.seeds)]
    est = np.array([r["est"] for r in rows])
    cov = sum(r["ci"][0] <= F_C <= r["ci"][1] for r in rows)
    raw = [r["raw"] for r in rows]
    cov_raw = sum(lo <= F_C <= hi for lo, hi in raw)
    hw = np.median([(r["ci"][1] - r["ci"][0]) / 2 for r in rows])
    hw_raw = np.median([(hi - lo) / 2 for lo, hi in raw])
    print(f"friction F_c = {F_C} N, {args.seeds} realisations, {args.resamples} resamples each "
          f"({time.perf_counter() - t0:.0f} s)")
    print(f"  estimate: mean error {est.mean() - F_C:+.5f} N, seed-to-seed sd {est.std(ddof=1):.5f} N "
          f"(1.645 sd = {1.645 * est.std(ddof=1):.5f} N)")
    print(f"  percentile interval alone:        covers {cov_raw}/{args.seeds} ({100 * cov_raw / args.seeds:.0f} %), "
          f"median half-width {hw_raw:.5f} N")
    print(f"  reported (widened, with profile):  covers {cov}/{args.seeds} ({100 * cov / args.seeds:.0f} %), "
          f"median half-width {hw:.5f} N")


if __name__ == "__main__":
    main()
