"""Time-domain diagnosis benchmark (issue 18): 8 transient tests × 30 000 samples.

Usage (from the repository root)::

    python benchmarks/transient_bench.py            # 8 × 30 000 samples, target <= 30 s
    python benchmarks/transient_bench.py --quick    # 8 × 5 000 samples
    python benchmarks/transient_bench.py --json out.json

Records: the built-in chain (x0 = 2 mm) under band-limited random displacement (flat spectrum
below 2 Hz, 0.08 mm RMS, sampled at 1 kHz) with a hidden Dahl hysteresis (F_h = 80 N,
x_h = 0.02 mm, run causally), viscous c = 30 N·s/mm and 5 N force noise; test 8 held out.
Timed: ``chainid.gap.diagnose`` end to end (time-domain route: preparation, baseline, where,
forward selection over the whole library, block jack-knife).

Baseline measured in the same run: the harmonic diagnosis (phase-bin route) of 8 steady
harmonic tests of the same chain and effect with the same total sample count (8 × N).
Printed: both wall times and their ratio, and the verdict of each (so a fast wrong answer
does not pass unnoticed).
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))


def transient_set(n: int, n_rec: int = 8):
    from chainid.model.effects import dahl_operator
    from chainid.model import ChainModel
    from transient_forms import random_x, record

    model = ChainModel()
    recs = []
    for i in range(n_rec):
        t, x, xd, xdd = random_x(n, 1000.0, 2.0, 0.08, 2.0, seed=i)
        F = np.asarray(model.force(x), float) + 30.0 * xd + dahl_operator(x, 80.0, 0.02, periodic=False)
        recs.append(record(str(i + 1), t, x, F, 5.0, i))
    return model, recs


def harmonic_set(n: int, model, n_rec: int = 8):
    from chainid.gap import parse_effect
    from chainid.records.simulate import TestSpec, simulate

    plan = [TestSpec(str(i + 1), w, 2.0, a) for i, (w, a) in
            enumerate([(4, .05), (4, .12), (8, .08), (8, .05), (12, .12), (12, .08), (6, .1), (10, .06)])]
    spc = 256
    return simulate(plan, model, 30.0, n_cycles=n / spc, samples_per_cycle=spc, noise_F=5.0, seed=1,
                    force_fn=parse_effect("hysteresis:F_h=80,x_h=0.02", model))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--json")
    a = ap.parse_args(argv)
    from chainid.gap import diagnose

    n = 5000 if a.quick else 30000
    model, trans = transient_set(n)
    harm = harmonic_set(n, model)
    diagnose(trans[:3], ["3"], model, quiet=True, max_combo=1, effects=["hysteresis"])  # numba/jit warm-up
    t0 = time.perf_counter()
    rt = diagnose(trans, ["8"], model, quiet=True)
    tt = time.perf_counter() - t0
    t0 = time.perf_counter()
    rh = diagnose(harm, ["8"], model, quiet=True)
    th = time.perf_counter() - t0
    ns = sum(r.t.size for r in trans)
    out = {"samples": ns, "transient_s": tt, "harmonic_s": th, "ratio": tt / th, "target_s": 30.0,
           "verdict_transient": rt["verdict"], "verdict_harmonic": rh["verdict"],
           "shrinkage_transient": rt["steps"][-1]["shrinkage"]}
    print(f"time-domain diagnosis, 8 tests x {n} samples ({ns} samples): {tt:.1f} s (target <= 30 s), verdict "
          f"{rt['verdict']}, held-out shrinkage {100 * out['shrinkage_transient']:.0f} %")
    print(f"baseline, harmonic diagnosis of the same sample count: {th:.1f} s, verdict {rh['verdict']}")
    print(f"ratio time-domain / harmonic: {tt / th:.2f}")
    if a.json:
        Path(a.json).write_text(json.dumps(out, indent=2))
    return 0 if tt <= 30.0 or a.quick else 1


if __name__ == "__main__":
    sys.exit(main())
