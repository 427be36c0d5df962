"""Offline: the coverage that other rules for merging an interval's parts would give, on stored benchmark rows.

A reported 90 % interval is made of parts that ``chainid benchmark-gap --json`` keeps apart in each row
(``params_ci90_parts``): ``percentile`` (the resamples' percentiles, time route only; on the harmonic route it is
``resampled`` itself), ``resampled`` (those widened by the time sampling's and the displacement noise's biases) and
``profile`` (profile likelihood).  Every rule below is computed from those parts alone, so it is scored on runs
already made, with no re-run.  Rows written before commit 2bb3e55 reported the ``union`` rule; since then they
report ``gated`` (:func:`chainid.gap.core.profile.merge`, which also stops a widened edge at the parameter's bound,
a clip that the rows cannot replay and that never moves a covered truth out).

Rules, per parameter (P percentile, R resampled, Q profile; B the bias widening R − P, applied edge by edge):

* ``union``: R ∪ Q, what the code reported before 2bb3e55;
* ``profile``, ``resampled``: Q, R alone;
* ``gated`` (what the code reports; its gate is :func:`chainid.gap.core.profile.heterogeneous`): R ∪ Q where the
  training units are heterogeneous — the percentile interval is wider than the profile's by more than its own
  sampling scatter allows, width(P) > (1 + z₉₅/√(2(m − 1)))·width(Q), m the training units
  (the relative sd of a spread read from m units is about 1/√(2(m − 1))), or m < 2; else Q widened by B and
  holding the estimate;
* ``gated_plain``: as ``gated``, but Q alone where the units are not heterogeneous;
* ``shifted``: P and Q both moved by the net bias (not widened), and their hull.

m is the row's ``resample_units`` (rows written since it was recorded); for older rows the harmonic plans' training
tests (grid3x3: 8, grid4x3: 9, measured) and ``--time-units`` otherwise (12 on the time route's cases; rows of
the ODE world name no plan and take it too), each such row counted as a fallback.

Usage (from the repository root)::

    python benchmarks/merge_rules.py RUN.json [RUN.json ...] [--time-units 12]

Nothing is asserted: a study to choose a rule, whose choice must then be re-run on both routes' full grids.
"""

from __future__ import annotations

import argparse
import collections
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RULES = ("union", "profile", "resampled", "gated", "gated_plain", "shifted")
#: training tests of the harmonic plans (their held-out tests excluded)
PLAN_UNITS = {"grid3x3": 8, "grid4x3": 9}


def rules(parts: dict, key: str, m: int, est: float) -> dict[str, list[float]] | None:
    """Every rule's interval for parameter ``key`` (estimate ``est``) from a row's parts; None without both a
    resampled and a profile interval."""
    R = (parts.get("resampled") or {}).get(key)
    Q = (parts.get("profile") or {}).get(key)
    if R is None or Q is None:
        return None
    P = (parts.get("percentile") or {}).get(key) or R
    b_lo, b_hi = max(0.0, P[0] - R[0]), max(0.0, R[1] - P[1])
    union = [min(R[0], Q[0]), max(R[1], Q[1])]
    from chainid.gap.core.profile import heterogeneous

    het = heterogeneous(P, Q, m)  # the code's own gate
    net = b_hi - b_lo
    shifted = [min(P[0], Q[0]) + net, max(P[1], Q[1]) + net]
    return {"union": union, "profile": Q, "resampled": R, "gated": union if het else [min(Q[0] - b_lo, est), max(Q[1] + b_hi, est)],
            "gated_plain": union if het else Q, "shifted": shifted}


def tally(files: list[str], time_units: int) -> tuple[dict, dict, int]:
    """Covered and scored intervals per (effect, rule), cases per effect, and the rows whose m was a fallback."""
    import json

    from chainid.gap.benchmark.report import row_param_scores

    hits: dict = collections.defaultdict(lambda: [0, 0])
    cases: dict = collections.defaultdict(set)
    fallback = 0
    for f in files:
        for j, row in enumerate(json.loads(Path(f).read_text())["rows"]):
            m = row.get("resample_units")
            if m is None:
                m = PLAN_UNITS.get(row.get("plan")) or time_units
                fallback += 1
            for s in row_param_scores(row):
                iv = rules(row.get("params_ci90_parts") or {}, s["param"], m, s["estimate"])
                if iv is None:
                    continue
                eff = s["param"].split(".")[0]
                cases[eff].add((f, j))
                for name in RULES:
                    h = hits[eff, name]
                    h[0] += iv[name][0] <= s["truth"] <= iv[name][1]
                    h[1] += 1
    return hits, cases, fallback


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("runs", nargs="+", help="benchmark-gap --json files")
    ap.add_argument("--time-units", type=int, default=12, help="m for time-route rows that do not record it")
    a = ap.parse_args(argv)
    sys.path.insert(0, str(ROOT))
    from chainid.gap.benchmark.paramscore import calibration_mark, rate_range

    hits, cases, fallback = tally(a.runs, a.time_units)
    print(f"{'effect':16s}{'cases':>6s}" + "".join(f"{r:>22s}" for r in RULES))
    for eff in sorted(cases):
        nc, cells = len(cases[eff]), []
        for name in RULES:
            c, n = hits[eff, name]
            lo, hi = rate_range(c / n, nc)
            mark = calibration_mark({"coverage": c / n, "consistent": lo <= 0.9 <= hi})
            cells.append(f"{100 * c / n:5.1f}% {100 * lo:3.0f}-{100 * hi:3.0f} {mark:4s}")
        print(f"{eff:16s}{nc:6d}" + "".join(f"{c:>22s}" for c in cells))
    print(f"(rate, the exact 95 % range over the cases, mark as in benchmark-gap --summary; {fallback} rows took m "
          f"from the plan or --time-units)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
