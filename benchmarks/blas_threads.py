"""The cost of BLAS threads on the diagnosis' small products: one effect set fitted and scored on a time-domain set,
with BLAS at its default thread count and at one (:mod:`chainid.infra.threads`), in the same run.

The set: ``--records`` records of ``--samples`` samples of a linear device with Coulomb friction under band-limited
random displacement (the project's simulator; the scale benchmark's device).  Each configuration is timed
``--repeats`` times (the median is printed), in alternation, after one warm-up fit (numba compilation, caches).

Usage::

    python benchmarks/blas_threads.py [--records 16] [--samples 31250] [--repeats 3]

Prints the times and their ratio; nothing is asserted (performance is measured, not tested).
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path


def _time(prob, names: list[str], base_hold: float) -> tuple[float, float]:
    t0 = time.perf_counter()
    c = prob.fit(names)
    t1 = time.perf_counter()
    prob.score(c, names, base_hold)
    return t1 - t0, time.perf_counter() - t1


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--records", type=int, default=16)
    ap.add_argument("--samples", type=int, default=31_250)
    ap.add_argument("--repeats", type=int, default=3)
    a = ap.parse_args(argv)
    sys.path.insert(0, str(Path(__file__).parent))
    from threadpoolctl import threadpool_info

    from chainid.gap.timedomain.route import build_problem
    from chainid.infra.threads import one_thread
    from diagnosis_scale import _device_records

    recs = _device_records(a.records, a.samples)
    prob = build_problem(recs, [recs[-1].test], 0, None)
    base = prob.score(prob.fit([]), [], float("nan"))
    names = ["hysteresis"]
    _time(prob, names, base.nrmse_holdout)
    default = max(i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas")
    runs: dict[str, list[tuple[float, float]]] = {"default": [], "one": []}
    for _ in range(a.repeats):
        runs["default"].append(_time(prob, names, base.nrmse_holdout))
        with one_thread():
            runs["one"].append(_time(prob, names, base.nrmse_holdout))
    med = {k: (statistics.median(r[0] for r in v), statistics.median(r[1] for r in v)) for k, v in runs.items()}
    n = sum(r.t.size for r in recs)
    print(f"{len(recs)} records, {n} samples, effect set {'+'.join(names)}, median of {a.repeats}")
    print(f"  BLAS threads {default} (default): fit {med['default'][0]:.3f} s, score {med['default'][1]:.3f} s")
    print(f"  BLAS threads 1:           fit {med['one'][0]:.3f} s, score {med['one'][1]:.3f} s")
    print(f"  ratio default/one: fit {med['default'][0] / med['one'][0]:.2f}, "
          f"score {med['default'][1] / med['one'][1]:.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
