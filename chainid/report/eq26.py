"""Part 4b of the gap report section, the paper's record: Eq. 26 (test 3 of Table 1) against the model with the
gap "where" tools (stiffness level, in-phase dynamic stiffness, phase of the velocity component, residual
harmonics over one period), and its figure.

Units: x mm, F N, t s, ω rad/s, m kg, k N/mm, c_e N·s/mm, W N·mm.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from chainid.gap.harmonic.where import residual_harmonics


# -- Eq. 26 record ----------------------------------------------------------------

def _x_at_force(model: Any, F: float, x_hi: float) -> float:
    """Elongation x [mm] where the model's F_k(x) = F [N] (bisection on [0, x_hi]); NaN if out of range."""
    lo, hi = 0.0, float(x_hi)
    f = lambda x: float(np.asarray(model.force(np.array([x])), dtype=float)[0]) - F  # noqa: E731
    if f(lo) > 0 or f(hi) < 0:
        return float("nan")
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        if f(mid) < 0:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def eq26_analysis(model: Any, n_bins: int = 360) -> dict[str, Any]:
    """The paper's Eq. 26 record (test 3) against the model, with the gap "where" tools.

    x = x0 + A sin ψ (Eq. 25), F = F0 + F_A sin(ψ + φ) (Eq. 26), ψ = ωt over one
    period.  F_A cos φ is the part of F in phase with x (stiffness), F_A sin φ
    the part in phase with ẋ (damping; Eq. 27 calls it F_ac).

    Parameters
    ----------
    model : StiffnessModel
        F_k(x) [N], k_e(x) [N/mm], mass [kg].
    n_bins : int
        Samples of ψ over one period.

    Returns
    -------
    dict
        ``record``, ``stiffness_level``, ``in_phase``, ``quadrature``,
        ``residual_harmonics``, ``audit_findings`` (c, e of :func:`chainid.damping.audit.audit`).
    """
    from chainid.damping import audit
    from chainid.model.predict import inertia_force_N

    E26, E27 = audit.EQ26, audit.EQ27
    x0, A, w = E27["x0"], E27["A"], E27["omega"]
    F0, FA, phi = E26["F0"], E26["FA"], E26["phi"]
    m = float(model.mass_kg)
    rep = audit.audit(model)
    fnd = {f["id"]: f["numbers"] for f in rep["findings"]}

    psi = (np.arange(n_bins) + 0.5) * 2 * math.pi / n_bins
    x = x0 + A * np.sin(psi)
    xdd = -w * w * A * np.sin(psi)
    F = F0 + FA * np.sin(psi + phi)
    Fk = np.asarray(model.force(x), dtype=float)
    Fin = np.asarray(inertia_force_N(m, xdd), dtype=float)
    r = F - (Fk + Fin)
    h = residual_harmonics(r, n_max=5)

    Fk0 = float(np.asarray(model.force(np.array([x0])), dtype=float)[0])
    ke = np.asarray(model.stiffness(np.array([x0 - A, x0, x0 + A])), dtype=float)
    x_F0 = _x_at_force(model, F0, 3 * x0)
    k_in = FA * math.cos(phi) / A
    k_model_h1 = 2 * float(np.mean(Fk * np.sin(psi))) / A  # model's secant (first-harmonic) stiffness
    k_inertia = m * w * w * 1e-3  # N/mm, subtracts from the in-phase stiffness
    Fq = FA * math.sin(phi)
    ce_record = Fq / (w * A)
    W_rec = math.pi * A * Fq
    W_27 = math.pi * A * E27["F_ac"]
    h1 = math.hypot(h["h1_x"], h["h1_xdot"])
    return {
        "record": {"x0_mm": x0, "A_mm": A, "omega_x_rad_s": w, "omega_F_rad_s": E26["omega"], "F0_N": F0, "FA_N": FA,
                   "phi_rad": phi, "r2": E26["r2"], "model": getattr(model, "name", "model"), "mass_kg": m,
                   "phase_drift_per_cycle_rad": 2 * math.pi * abs(w - E26["omega"]) / w,
                   "F_min_N": F0 - FA, "F_max_N": F0 + FA},
        "stiffness_level": {"F0_N": F0, "F_k_x0_N": Fk0, "F_k_cycle_mean_N": float(np.mean(Fk)),
                            "F0_over_F_k_x0": F0 / Fk0, "x_where_F_k_equals_F0_mm": x_F0,
                            "offset_x0_minus_x_F0_mm": x0 - x_F0},
        "in_phase": {"F_A_cos_phi_N": FA * math.cos(phi), "k_in_phase_N_per_mm": k_in,
                     "k_e_x0_N_per_mm": float(ke[1]), "k_e_range_N_per_mm": [float(ke.min()), float(ke.max())],
                     "k_model_first_harmonic_N_per_mm": k_model_h1, "inertia_m_omega2_N_per_mm": k_inertia,
                     "ratio_in_phase_over_k_e": k_in / float(ke[1]),
                     "ratio_in_phase_over_model_dynamic": k_in / (k_model_h1 - k_inertia),
                     "F_A_over_A_N_per_mm": fnd["c"]["dynamic_stiffness_FA_over_A_N_per_mm"]},
        "quadrature": {"F_A_sin_phi_N": fnd["e"]["FA_sin_phi_N"], "F_ac_eq27_N": E27["F_ac"],
                       "c_e_eq27_N_s_per_mm": E27["c_e"], "c_e_implied_by_record_N_s_per_mm": ce_record,
                       "W_record_Nmm": fnd["e"]["W_per_cycle_Nmm"], "W_eq27_Nmm": W_27,
                       "ratio_abs_over_eq27": abs(Fq) / E27["F_ac"], "W_check_Nmm": W_rec},
        "residual_harmonics": {**h, "h1": h1, "h2_over_h1": h["h2"] / h1, "h3_over_h1": h["h3"] / h1,
                               "definition": "r(psi) = F_Eq26 - (F_k(x) + m xddot 1e-3), x = x0 + A sin psi"},
        "audit_findings": {"c": fnd["c"], "e": fnd["e"]},
    }


def plot_eq26(path: Path, model: Any, d: dict[str, Any]) -> None:
    """Eq. 26 loop against the model, and the residual over one period."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from chainid.model.predict import inertia_force_N

    rc = d["record"]
    x0, A, w, F0, FA, phi = rc["x0_mm"], rc["A_mm"], rc["omega_x_rad_s"], rc["F0_N"], rc["FA_N"], rc["phi_rad"]
    psi = np.linspace(0, 2 * math.pi, 361)
    x = x0 + A * np.sin(psi)
    F = F0 + FA * np.sin(psi + phi)
    base = np.asarray(model.force(x), dtype=float) + np.asarray(inertia_force_N(rc["mass_kg"], -w * w * A * np.sin(psi)))
    c27 = d["quadrature"]["c_e_eq27_N_s_per_mm"]
    F27 = base + c27 * w * A * np.cos(psi)
    fig, axs = plt.subplots(1, 2, figsize=(11, 4.4))
    ax = axs[0]
    ax.plot(x, F / 1000, "C3-", lw=1.8, label="Eq. 26 record (paper's fit)")
    ax.plot(x, base / 1000, "k--", lw=1.2, label="model F_k(x) + m·ẍ")
    ax.plot(x, F27 / 1000, "C0-", lw=1.2, label=f"model + Eq. 27 damping (c_e = {c27:g} N·s/mm)")
    for k, lab in ((0, "ψ = 0"), (90, "ψ = 90°")):
        ax.plot(x[k], F[k] / 1000, "C3o", ms=5)
        ax.annotate(lab, (x[k], F[k] / 1000), textcoords="offset points", xytext=(6, 4), fontsize=8, color="C3")
    ax.annotate("", xy=(x[40], F[40] / 1000), xytext=(x[20], F[20] / 1000),
                arrowprops={"arrowstyle": "-|>", "color": "C3", "lw": 1.5})
    ax.text(0.98, 0.04, "record loop runs counter-clockwise: energy generated\n"
            "(a dissipative loop, like the blue one, runs clockwise)", transform=ax.transAxes, ha="right",
            va="bottom", fontsize=7.5, color="C3")
    ax.axhline(0, color="0.5", lw=0.6)
    ax.set_xlabel("chain elongation x [mm]")
    ax.set_ylabel("force F [kN]")
    ax.set_title(f"test 3: x = {x0:g} + {A:g} sin({w:g}t) mm (Eq. 25/26)", fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="upper left")
    ax = axs[1]
    deg = np.degrees(psi)
    r = F - base
    h = d["residual_harmonics"]
    ax.plot(deg, r / 1000, "C3-", lw=1.8, label="residual F_Eq.26 − (F_k + m·ẍ)")
    ax.plot(deg, h["h1_x"] * np.sin(psi) / 1000, "C2--", lw=1.2,
            label=f"in phase with x: {h['h1_x'] / 1000:+.1f} kN (stiffness)")
    ax.plot(deg, h["h1_xdot"] * np.cos(psi) / 1000, "C1--", lw=1.2,
            label=f"in phase with ẋ: {h['h1_xdot'] / 1000:+.1f} kN (damping)")
    ax.axhline(h["mean"] / 1000, color="C4", ls=":", lw=1.2, label=f"mean {h['mean'] / 1000:+.2f} kN")
    ax.plot(deg, c27 * w * A * np.cos(psi) / 1000, "C0-", lw=1.0,
            label=f"Eq. 27 damping force {d['quadrature']['F_ac_eq27_N']:g}·cos ψ N")
    ax.axhline(0, color="0.5", lw=0.6)
    ax.set_xlabel("cycle phase ψ of x = x0 + A sin ψ [deg] (90: top turning point)")
    ax.set_ylabel("residual force [kN]")
    ax.set_xticks(range(0, 361, 90))
    ax.set_title("what the model lacks over one period", fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7.5, loc="lower left")
    fig.tight_layout()
    from chainid.infra.fileio import save_figure

    save_figure(fig, path, force=True, what="report figure", dpi=110)
    plt.close(fig)
