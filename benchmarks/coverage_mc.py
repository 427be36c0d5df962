"""Monte Carlo coverage of one effect family's 90 % intervals: the benchmark's own cases on many fresh seeds.

``chainid benchmark-gap --seed S`` draws every case's noise from its own seed block (``S·10⁷``,
:mod:`chainid.gap.benchmark.seeds`); a family has a few dozen cases per seed, so a coverage read from a handful of
seeds has a binomial spread of several per cent.  This study re-runs only the cases whose label contains
``--cases`` (e.g. ``harmonic/single/backlash``) at seeds ``--first``, ``--first`` + 1, … (default 100 on: disjoint
from the seeds the README's table uses), with ``--resamples`` resamples each, and prints, per parameter of the
family: how often the reported interval covers the truth, how often each of its parts does (the profile, the
resampled percentiles), the exact (Clopper–Pearson) 95 % range of each rate, and the RMS of the truth's distance from
the profile interval's centre in half-widths (0.608 = 1/z₉₅ for a calibrated normal interval).

Usage (from the repository root)::

    python benchmarks/coverage_mc.py --cases harmonic/single/backlash --excitations harmonic --seeds 8
        [--first 100] [--resamples 20] [--workers 2] [--json F]

Nothing is asserted: a study.  Units: each parameter's own.
"""

from __future__ import annotations

import argparse
import collections
import json
import math
import sys
import warnings
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from chainid.gap.benchmark.paramscore import rate_range  # noqa: E402  (the repository's own package first)


def one(case: dict[str, Any]) -> list[dict[str, Any]]:
    """Run one case blind; per scored parameter: truth, estimate, reported interval and its parts."""
    from chainid.gap.benchmark.grid import run_case
    from chainid.gap.benchmark.report import row_param_scores

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        row = run_case(case)
    parts = row.get("params_ci90_parts") or {}
    out = []
    for sc in row_param_scores(row):
        k = sc["param"]
        out.append({"label": case["label"], "seed": case["seed"], "param": k, "truth": sc["truth"],
                    "estimate": sc["estimate"], "ci": (row.get("params_ci90") or {}).get(k),
                    "profile": (parts.get("profile") or {}).get(k), "resampled": (parts.get("resampled") or {}).get(k)})
    return out


def cases_for(text: str, excitations: tuple[str, ...], first: int, seeds: int, resamples: int) -> list[dict]:
    """The benchmark's cases whose label contains ``text``, at seeds first … first + seeds − 1."""
    from chainid.gap.benchmark.grid import selected_cases

    return [c | {"resamples": resamples} for s in range(first, first + seeds)
            for c in selected_cases(False, s, excitations, None, text)]


def summary(rows: list[dict[str, Any]]) -> list[str]:
    """One line per parameter: the rate of each interval and its exact 95 % range, and the profile's RMS z."""
    by = collections.defaultdict(list)
    for r in rows:
        by[r["param"]].append(r)
    lines = [f"{'parameter':24s} {'n':>4s}  {'reported':>20s}  {'profile':>20s}  {'resampled':>20s}  rms z (0.608)"]
    for k, rs in sorted(by.items()):
        cells = []
        for part in ("ci", "profile", "resampled"):
            ok = [r for r in rs if r[part] is not None]
            hit = sum(r[part][0] <= r["truth"] <= r[part][1] for r in ok)
            lo, hi = rate_range(hit / len(ok), len(ok)) if ok else (math.nan, math.nan)
            cells.append(f"{hit:3d}/{len(ok):<3d} {100 * lo:3.0f}-{100 * hi:3.0f} %")
        z = [(r["truth"] - (r["profile"][0] + r["profile"][1]) / 2) / ((r["profile"][1] - r["profile"][0]) / 2)
             for r in rs if r["profile"] is not None and r["profile"][1] > r["profile"][0]]
        rms = math.sqrt(sum(v * v for v in z) / len(z)) if z else math.nan
        lines.append(f"{k:24s} {len(rs):4d}  {cells[0]:>20s}  {cells[1]:>20s}  {cells[2]:>20s}  {rms:.3f}")
    return lines


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cases", required=True, help="run the cases whose label contains this text")
    ap.add_argument("--excitations", default="harmonic", help="comma-separated, as benchmark-gap's")
    ap.add_argument("--seeds", type=int, default=8, help="fresh seeds per case (>= 1)")
    ap.add_argument("--first", type=int, default=100, help="the first seed (>= 0)")
    ap.add_argument("--resamples", type=int, default=20, help="resamples per diagnosis (>= 0)")
    ap.add_argument("--workers", type=int, default=2, help="processes (>= 1)")
    ap.add_argument("--json", default=None, help="write every row here")
    a = ap.parse_args(argv)
    for name, v, least in (("--seeds", a.seeds, 1), ("--first", a.first, 0), ("--resamples", a.resamples, 0),
                           ("--workers", a.workers, 1)):
        if v < least:
            ap.error(f"{name} = {v} is out of range; valid range: >= {least}")
    cases = cases_for(a.cases, tuple(e for e in a.excitations.split(",") if e), a.first, a.seeds, a.resamples)
    if not cases:
        ap.error(f"--cases {a.cases!r}: no benchmark case's label contains it")
    with ProcessPoolExecutor(max_workers=a.workers) as ex:
        rows = [r for out in ex.map(one, cases) for r in out]
    print(f"{len(cases)} diagnoses ({a.cases!r}, seeds {a.first}-{a.first + a.seeds - 1}, "
          f"{a.resamples} resamples each)")
    print("\n".join(summary(rows)))
    if a.json:
        tmp = Path(a.json).with_suffix(".tmp")
        tmp.write_text(json.dumps(rows, indent=1), encoding="utf-8")
        tmp.replace(a.json)
    return 0


if __name__ == "__main__":
    sys.exit(main())
