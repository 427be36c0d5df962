"""Part 4b of the gap report section, Table 1: the damping trend (energy per cycle W = π F_ac A against A and ω,
c_e exponents, classified as viscous, hysteretic or Coulomb), and its figure.

Units: x mm, F N, ω rad/s, k N/mm, c_e N·s/mm, W N·mm.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from chainid.gap.harmonic.where import classify_slopes, energy_slopes


# -- Table 1 -----------------------------------------------------------------------

def _slope(xv: np.ndarray, yv: np.ndarray) -> tuple[float, float]:
    """Least-squares slope of log y on log x and its R²."""
    lx, ly = np.log(xv), np.log(yv)
    p = np.polyfit(lx, ly, 1)
    res = ly - np.polyval(p, lx)
    ss = float(np.sum((ly - ly.mean()) ** 2))
    return float(p[0]), 1.0 - float(np.sum(res**2)) / ss if ss > 0 else float("nan")


def table1_analysis(model: Any) -> dict[str, Any]:
    """Damping trend of Table 1: W = π F_ac A against A and ω, c_e exponents, classification.

    ω [rad/s] = (π/10) × the table's column (audit finding a).  A-slope from
    tests 3, 6–9 (column 6, x0 co-varies 2.15–2.35 mm), ω-slope from tests 2–5
    (A = 0.25 mm, x0 = 2.2 mm); test 1 is inconsistent (audit finding b) and
    left out, with the slopes it would give shown for reference.

    Returns
    -------
    dict
        ``tests`` (per test: ω, x0, A, F_ac, c_e, W, loss factor η = F_ac/(k_e(x0) A)),
        ``slope_A``, ``slope_omega`` (+ R²), ``class``, ``c_e_exponent_A/omega``,
        ``joint`` (:func:`energy_slopes` over tests 2–9), ``test1``.
    """
    from chainid.damping import audit

    tb = audit.load_table1()
    rep_b = next(f for f in audit.audit(model)["findings"] if f["id"] == "b")["numbers"]
    test = tb["test"]
    w = tb["omega_col"] * audit.OMEGA_COLUMN_TO_RAD_S
    A, x0, Fac, ce = tb["A"], tb["x0"], tb["F_ac"], tb["c_e"]
    W = math.pi * Fac * A
    ke = np.asarray(model.stiffness(x0), dtype=float)
    eta = Fac / (ke * A)
    iA = np.isin(test, [3, 6, 7, 8, 9])
    iw = np.isin(test, [2, 3, 4, 5])
    sA, r2A = _slope(A[iA], W[iA])
    sw, r2w = _slope(w[iw], W[iw])
    qA, _ = _slope(A[iA], ce[iA])
    pw, _ = _slope(w[iw], ce[iw])
    forms = {"viscous": (2, 1), "hysteretic": (2, 0), "Coulomb": (1, 0), "micro-slip": (3, 0)}
    dist = {k: math.hypot(v[0] - sA, v[1] - sw) for k, v in forms.items()}
    i1w = np.isin(test, [1, 2, 3, 4, 5])
    sw1, _ = _slope(w[i1w], W[i1w])
    W1 = W.copy()
    W1[0] = math.pi * rep_b["F_ac_implied_by_c_e"] * A[0]
    sw1c, _ = _slope(w[i1w], W1[i1w])
    m29 = test >= 2
    joint = energy_slopes(w[m29], A[m29], W[m29])
    joint["class"] = classify_slopes(joint["slope_A"], joint["slope_omega"])
    return {
        "tests": [{"test": int(t), "omega_rad_s": float(a), "x0_mm": float(b), "A_mm": float(c), "F_ac_N": float(d),
                   "c_e_N_s_per_mm": float(e), "W_Nmm": float(f), "k_e_x0_N_per_mm": float(g), "loss_factor": float(h),
                   "in_A_fit": bool(i), "in_omega_fit": bool(j)}
                  for t, a, b, c, d, e, f, g, h, i, j in zip(test, w, x0, A, Fac, ce, W, ke, eta, iA, iw)],
        "slope_A": sA, "r2_A": r2A, "tests_A": [int(t) for t in test[iA]],
        "slope_omega": sw, "r2_omega": r2w, "tests_omega": [int(t) for t in test[iw]],
        "class": classify_slopes(sA, sw), "distance_to_forms": dist,
        "c_e_exponent_A": qA, "c_e_exponent_omega": pw,
        "joint": joint,
        "test1": {"omega_rad_s": float(w[0]), "F_ac_N": float(Fac[0]), "F_ac_implied_by_c_e_N": rep_b["F_ac_implied_by_c_e"],
                  "factor": rep_b["factor"], "slope_omega_tests_1_5_as_printed": sw1,
                  "slope_omega_tests_1_5_with_F_ac_from_c_e": sw1c},
    }


def plot_table1_energy(path: Path, t1: dict[str, Any]) -> None:
    """log W against log A (tests 3, 6–9) and log ω (tests 2–5) with the reference forms."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FixedLocator, FuncFormatter, NullFormatter

    T = t1["tests"]
    tA = [t for t in T if t["in_A_fit"]]
    tw = [t for t in T if t["in_omega_fit"]]
    t1d = next(t for t in T if t["test"] == 1)
    xl_A = (f"amplitude A [mm] (ω = {tA[0]['omega_rad_s']:.4g} rad/s; x₀ {min(t['x0_mm'] for t in tA):g}–"
            f"{max(t['x0_mm'] for t in tA):g} mm)")
    xl_w = f"ω [rad/s] = (π/10) × Table 1 column (A = {tw[0]['A_mm']:g} mm, x₀ = {tw[0]['x0_mm']:g} mm)"
    fig, axs = plt.subplots(1, 2, figsize=(11, 4.3))
    plain = FuncFormatter(lambda v, _: f"{v:g}")
    for ax, key, sel, slope, refs, xl in (
        (axs[0], "A_mm", tA, t1["slope_A"], ((1, "Coulomb"), (2, "viscous / hysteretic"), (3, "micro-slip")), xl_A),
        (axs[1], "omega_rad_s", tw, t1["slope_omega"], ((0, "hysteretic / Coulomb"), (1, "viscous")), xl_w),
    ):
        xs = np.array([t[key] for t in sel])
        Ws = np.array([t["W_Nmm"] for t in sel])
        ax.loglog(xs, Ws, "ko", ms=6, label="Table 1: W = π F_ac A")
        for t in sel:
            ax.annotate(f"test {t['test']}", (t[key], t["W_Nmm"]), textcoords="offset points", xytext=(5, -11),
                        fontsize=7.5)
        gx = np.exp(np.mean(np.log(xs)))
        gW = np.exp(np.mean(np.log(Ws)))
        xx = np.geomspace(xs.min() * 0.85, xs.max() * 1.15, 20)
        ax.loglog(xx, gW * (xx / gx) ** slope, "C3-", lw=1.6, label=f"fit: slope {slope:.2f}")
        for (s, lab), st in zip(refs, (":", "--", "-.")):
            ax.loglog(xx, gW * (xx / gx) ** s, color="0.45", ls=st, lw=1, label=f"slope {s}: {lab}")
        if key == "omega_rad_s":
            ax.loglog([t1d["omega_rad_s"]], [t1d["W_Nmm"]], "x", color="C1", ms=8,
                      label=f"test 1 as printed (F_ac = {t1d['F_ac_N']:g} N; excluded)")
            Fi = t1["test1"]["F_ac_implied_by_c_e_N"]
            ax.loglog([t1d["omega_rad_s"]], [math.pi * Fi * t1d["A_mm"]], "+", color="C1", ms=9,
                      label=f"test 1 with F_ac from its c_e ({Fi:.0f} N)")
            ticks = [0.3, 0.5, 1.0, 2.0, 3.0]
        else:
            ticks = [0.2, 0.25, 0.3, 0.35, 0.4]
        ax.xaxis.set_major_locator(FixedLocator(ticks))
        ax.xaxis.set_major_formatter(plain)
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.yaxis.set_major_formatter(plain)
        ax.yaxis.set_minor_formatter(FuncFormatter(lambda v, _: f"{v:g}" if str(int(round(v)))[0] in "2357" else ""))
        ax.tick_params(axis="y", which="minor", labelsize=7.5)
        ax.set_xlabel(xl, fontsize=9)
        ax.set_ylabel("energy dissipated per cycle W [N·mm]")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7.5)
    axs[0].set_title(f"W against amplitude (tests {', '.join(str(t['test']) for t in tA)})", fontsize=10)
    axs[1].set_title(f"W against frequency (tests {', '.join(str(t['test']) for t in tw)})", fontsize=10)
    fig.tight_layout()
    from chainid.infra.fileio import save_figure

    save_figure(fig, path, force=True, what="report figure", dpi=110)
    plt.close(fig)
