"""Is what is left stationary?  Trends of the force over the cycles of a displacement-controlled test.

In a displacement-controlled harmonic test the displacement is periodic over the
steady window; every static effect of the library (and the model) then gives a
periodic force.  A trend of the per-cycle mean force or of its first harmonic
(in phase with x: stiffness; with ẋ: damping) over the cycles is a
non-stationarity — relaxation, creep, heating, wear, a drifting sensor — that no
static library member explains.

Per test and per quantity q ∈ {mean, a (sin ψ), b (cos ψ)} the trend is the
time slope of a least-squares fit q = β₀ + β₁·x_c + slope·t over the cycles,
where x_c is the cycle's own mean displacement (for q = mean) or amplitude (for
a, b): a force that merely follows a wandering shaker amplitude is not a trend.
Its significance is the slope over its standard error (scatter about the fit);
its size is the change of the line over the window, |slope|·span [N].

Units: N, s.
"""

from __future__ import annotations

import math
from typing import Any, Sequence

import numpy as np

#: a trend must exceed this many standard errors to count (pooled over tests)
Z_TREND = 4.0
#: fewest whole cycles a test needs for a trend estimate
MIN_CYCLES = 4


def trend(t: np.ndarray, y: np.ndarray, cov: np.ndarray | None = None,
          sd_floor: float = 0.0) -> tuple[float, float, float]:
    """Time slope [N/s] of y (given the covariate ``cov`` when it varies), its standard error, and the change
    of the trend over the span, |slope|·span [N].

    The standard error uses the larger of the scatter about the fit and ``sd_floor`` (the white-noise
    standard deviation of one cycle's value, σ·sqrt(c/n)): with a handful of cycles the scatter alone is
    too uncertain to judge a trend by.
    """
    n = t.size
    if n < 3 or float(np.ptp(t)) <= 0:
        return 0.0, float("inf"), 0.0
    cols = [np.ones(n), t - t.mean()]
    if cov is not None and n >= 6 and float(np.std(cov)) > 1e-9 * max(float(np.abs(cov).max()), 1e-300):
        cols.append(cov - cov.mean())
    X = np.column_stack(cols)
    coef, *_ = np.linalg.lstsq(X, y, rcond=None)
    r = y - X @ coef
    dof = n - X.shape[1]
    if dof < 1:
        return 0.0, float("inf"), 0.0
    s2 = max(float(r @ r) / dof, sd_floor**2)
    cov_b = np.linalg.pinv(X.T @ X) * s2
    sl = float(coef[1])
    se = math.sqrt(max(float(cov_b[1, 1]), 0.0)) or 1e-300
    return sl, se, abs(sl) * float(t[-1] - t[0])


def check(data: Sequence[Any]) -> dict[str, Any]:
    """Stationarity of the force over the cycles of each test (model-free: the displacement is periodic).

    Parameters
    ----------
    data : sequence of TestData (with ``cycles`` from :func:`chainid.gap.harmonic.prepare.cycle_stats`)

    Returns
    -------
    dict
        ``stationary`` (bool or None when no test has >= MIN_CYCLES cycles), ``trend_change_N``
        (change over the window of the significant trends, RMS over tests, summed over quantities), ``z`` (largest pooled z), per-test rows.
    """
    rows = []
    for d in data:
        cy = getattr(d, "cycles", None) or {}
        t = cy.get("t", np.zeros(0))
        if t.size < MIN_CYCLES:
            continue
        row: dict[str, Any] = {"test": d.test, "n_cycles": int(t.size)}
        n_mean = float(np.mean(cy["n"])) if "n" in cy and cy["n"].size else 1.0
        for q in ("mean", "a", "b"):
            # one cycle's mean has variance σ²/n, a harmonic amplitude 2σ²/n (white noise)
            floor = d.sigma * math.sqrt((1.0 if q == "mean" else 2.0) / max(n_mean, 1.0))
            sl, se, chg = trend(t, cy[q], cy.get("xm" if q == "mean" else "xa"), floor)
            row[q] = {"slope_N_per_s": sl, "z": abs(sl) / se if se > 0 else float("inf"), "change_N": chg}
        rows.append(row)
    if not rows:
        return {"stationary": None, "trend_change_N": 0.0, "z": 0.0, "tests": [],
                "finding": f"stationarity not checked: no test has >= {MIN_CYCLES} whole steady cycles"}
    # pooled z per quantity: sum of signed z over tests / sqrt(n) (a common trend) and max |z| (any test)
    out_q = {}
    for q in ("mean", "a", "b"):
        zs = np.array([r[q]["z"] for r in rows])
        chg = np.array([r[q]["change_N"] if r[q]["z"] >= Z_TREND else 0.0 for r in rows])
        out_q[q] = {"max_z": float(zs.max()), "change_N": float(np.sqrt(np.mean(chg**2))),
                    "n_tests": int(np.sum(zs >= Z_TREND))}
    zmax = max(v["max_z"] for v in out_q.values())
    tchg = math.sqrt(sum(v["change_N"] ** 2 for v in out_q.values()))
    # a test-level trend counts when it is significant in at least a quarter of the tests (not one outlier)
    n_sig = max(v["n_tests"] for v in out_q.values())
    stationary = not (n_sig >= max(1, math.ceil(0.25 * len(rows))) and zmax >= Z_TREND)
    names = {"mean": "mean force", "a": "force amplitude in phase with x", "b": "force amplitude in phase with ẋ"}
    worst = max(out_q, key=lambda q: out_q[q]["change_N"])
    finding = ("the force is stationary over the cycles of each test (no significant trend of its mean or first "
               "harmonic)") if stationary else (
        f"non-stationary: the {names[worst]} trends over the cycles in {out_q[worst]['n_tests']} of {len(rows)} "
        f"tests (change over the window {out_q[worst]['change_N']:.3g} N RMS over tests, up to {zmax:.1f} standard errors) while the displacement "
        "is periodic: relaxation, creep, heating or drift, which no static library effect explains")
    return {"stationary": stationary, "trend_change_N": tchg, "z": zmax, "by_quantity": out_q, "tests": rows,
            "finding": finding}
