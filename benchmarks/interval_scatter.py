"""Seed-to-seed scatter of a harmonic benchmark case's estimate against the width of its 90 % intervals.

One case of ``chainid benchmark-gap`` (the harmonic grid, :mod:`chainid.gap.benchmark.grid`), chosen by its label
(``--case``, e.g. ``harmonic/single/backlash``), strength, noise, chain and plan, is simulated with ``--seeds``
noise realisations and diagnosed blind with ``--resamples`` resamples.  Printed, over the realisations whose chain
holds the parameter (``--param``): the estimate's mean error and its standard deviation, the median half-width of
each part of the interval over 1.645 (the sd a calibrated 90 % interval implies: the profile's and the
resampling's) and its ratio to the estimate's rms error, and how often each part and the reported interval
contain the truth.  ``--untied`` reports the fit with each test's own c_e instead of the step's tie to its damping
law (:mod:`chainid.gap.harmonic.tie`): the estimator whose refits and profile the intervals are.

Usage (from the repository root)::

    python benchmarks/interval_scatter.py --case harmonic/single/backlash --param backlash.b [--level 1]
        [--noise 0.01] [--chain 14x50] [--plan grid3x3] [--seeds 25] [--resamples 20] [--untied]

Nothing is asserted: a study of one case, not the grid's coverage (``chainid benchmark-gap --summary``).
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def realisations(case: dict, seeds: int, resamples: int, key: str) -> tuple[list[tuple], dict[str, int]]:
    """(estimate, truth, profile, resampled, reported interval) of every realisation whose verdict is exactly the
    case's truth and which estimates ``key`` (the grid scores only those), and the count of the others by why."""
    from chainid.gap.benchmark.grid import run_case
    from chainid.gap.benchmark.report import row_param_scores

    out, left = [], {"error": 0, "other verdict": 0, "no estimate": 0}
    for s in range(seeds):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = run_case(case | {"seed": 1000 + 7919 * s, "resamples": resamples})
        scores = row_param_scores(r)
        if str(r.get("verdict", "")).startswith("error"):
            left["error"] += 1
        elif not any(sc["param"] == key for sc in scores):
            left["no estimate" if scores else "other verdict"] += 1
        else:
            parts = r.get("params_ci90_parts") or {}
            out.append((r["params"][key], r["true_params"][key], (parts.get("profile") or {}).get(key),
                        (parts.get("resampled") or {}).get(key), (r.get("params_ci90") or {}).get(key)))
    return out, left


def report(rows: list[tuple[float, float, list, list, list]]) -> str:
    """The scatter, the implied sds and the coverages of a list of realisations."""
    from chainid.gap.benchmark.paramscore import Z90

    est = np.array([r[0] for r in rows])
    truth = rows[0][1]
    err = est - truth
    rms = float(np.sqrt(np.mean(err**2)))
    lines = [f"realisations {len(rows)}; truth {truth:.6g}; mean error {err.mean():.3g}; sd {est.std(ddof=1):.3g}; "
             f"rms error {rms:.3g}"]
    for name, j in (("profile", 2), ("resampled", 3), ("reported", 4)):
        ivs = [r[j] for r in rows if r[j] is not None]
        if not ivs:
            continue
        hw = float(np.median([(b - a) / 2 for a, b in ivs])) / Z90
        cov = np.mean([a <= truth <= b for a, b in ivs])
        ratio = f"x{hw / rms:.2f} the rms error" if rms > 0 else "no error to compare"
        lines.append(f"  {name:10s} median half-width/1.645 {hw:.3g} ({ratio}); "
                     f"covers {100 * cov:.0f} % of {len(ivs)}")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--case", required=True, help="a harmonic grid label, e.g. harmonic/single/backlash")
    ap.add_argument("--param", required=True, help="effect.param, e.g. backlash.b")
    ap.add_argument("--level", type=float, default=1.0)
    ap.add_argument("--noise", type=float, default=0.01)
    ap.add_argument("--chain", default="14x50")
    ap.add_argument("--plan", default="grid3x3")
    ap.add_argument("--seeds", type=int, default=25)
    ap.add_argument("--resamples", type=int, default=20)
    ap.add_argument("--untied", action="store_true", help="report each test's own c_e fit, not the tie's")
    a = ap.parse_args(argv)
    sys.path.insert(0, str(ROOT))
    from chainid.gap.benchmark.grid import selected_cases

    if a.untied:  # a study switch: the tie is never kept
        import chainid.gap.harmonic.tie as tie

        tie.tie_damping = lambda *args, **kw: None
    try:
        cases = [c for c in selected_cases(False, 0, ("harmonic",), None, a.case) if c["label"] == a.case
                 and c["levels"][:1] == [a.level] and c["noise"] == a.noise and c["chain"] == a.chain
                 and c["plan"] == a.plan]
    except ValueError as exc:  # no case label holds the text
        ap.error(str(exc))
    if len(cases) != 1:
        ap.error(f"{len(cases)} harmonic cases labelled exactly {a.case} at level {a.level}, noise {a.noise}, chain "
                 f"{a.chain}, plan {a.plan} (one wanted; labels: chainid benchmark-gap --excitations harmonic)")
    rows, left = realisations(cases[0], a.seeds, a.resamples, a.param)
    if len(rows) < 3:
        ap.error(f"only {len(rows)} of {a.seeds} realisations estimate {a.param} with the right verdict ({left})")
    print(f"{a.case} {a.param}: level {a.level}, noise {a.noise}, chain {a.chain}, plan {a.plan}, "
          f"{a.resamples} resamples{', untied' if a.untied else ''}")
    print(report(rows))
    print(f"  left out: {left}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
