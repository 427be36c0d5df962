"""Audit of the paper's damping numbers: Table 1, Eq. 25–28 and the validation case.

Everything here is computed from the shipped transcription of Table 1
(``chainid/data/table1.csv``) and the numbers printed in the paper's text
(Eq. 25, 26, 27, 28 and the validation case); nothing is typed in as a result.

* Eq. 28 reproduced: Eq. 21 fitted to Table 1 with omega taken as the table's
  column, both by the normal equations G A = C (Eq. 23–24) and by lstsq.
* (a) c_e = F_ac/(omega A) holds for tests 2–9 only with omega [rad/s] =
  (pi/10) x column.
* (b) Test 1: F_ac = 8000 N is inconsistent with c_e = 5095.5 by a factor ≈ 20.
* (c) Eq. 26: F_A/A ≈ 78 kN/mm, several times the model's k_e(2.2 mm);
  F0 - F_A < 0 would compress the chain.
* (d) Validation case (x0 = 2.25 mm, 7 Hz, A = 0.32 mm): Eq. 21 fed omega = 7
  (as the paper does), 14 pi rad/s, or the table's own unit give very different c_e.
* (e) Eq. 26's phase phi = -0.835 rad puts the velocity component of F at
  F_A sin(phi) < 0 (energy generated), while Eq. 27 reports F_ac = +1335 N.
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np

from chainid.model.laws import PolynomialLaw, fit_law
from chainid.records.table1 import load_table1

__all__ = [
    "load_table1",
    "EQ28_PAPER",
    "EQ26",
    "EQ27",
    "VALIDATION",
    "OMEGA_COLUMN_TO_RAD_S",
    "eq28",
    "audit",
    "format_audit",
    "sig_round",
]

#: Eq. 28 as printed [alpha1..alpha5] (omega in the table's column unit, A mm, c_e N·s/mm).
EQ28_PAPER = (28.02, -651.57, -8386.50, 7394.84, 4378.89)
#: Eq. 26 as printed: F = F0 + FA sin(omega t + phi), test 3.
EQ26 = {"F0": 11117.21, "FA": 19522.1, "omega": 1.883, "phi": -0.8350, "r2": 0.9999}
#: Eq. 25/27 as printed for test 3: x0 mm, A mm, omega rad/s, ramp mm/s, F_ac N, c_e N·s/mm.
EQ27 = {"x0": 2.2, "A": 0.25, "omega": 1.884, "ramp_rate": 0.08973, "F_ac": 1335.0, "c_e": 2834.4}
#: The validation case of the paper: x = 2.25 + 0.32 sin(14 pi t).
VALIDATION = {"x0": 2.25, "A": 0.32, "f_Hz": 7.0}
#: omega [rad/s] = (pi/10) x Table 1's column (see finding a).
OMEGA_COLUMN_TO_RAD_S = math.pi / 10.0


def sig_round(v: float, n: int = 4) -> float:
    """Round v to n significant figures."""
    if v == 0 or not math.isfinite(v):
        return v
    return round(v, n - 1 - int(math.floor(math.log10(abs(v)))))


def eq28(omega_scale: float = 1.0) -> dict[str, Any]:
    """Fit Eq. 21 to Table 1 (Eq. 22–24) with omega = omega_scale x column.

    Parameters
    ----------
    omega_scale : float
        1.0 reproduces the paper (column used as omega); pi/10 gives rad/s.

    Returns
    -------
    dict
        ``alpha`` (lstsq), ``alpha_normal_equations`` (G A = C), ``stderr``,
        ``cond_X``, ``cond_G``, ``residuals`` [N·s/mm], ``rmse``, ``loo_rmse``.
    """
    tb = load_table1()
    fit = fit_law(PolynomialLaw(), tb["omega_col"] * omega_scale, tb["A"], tb["c_e"])
    return {
        "omega_scale": omega_scale,
        "alpha": [float(v) for v in fit.params],
        "alpha_normal_equations": [float(v) for v in fit.params_normal],
        "stderr": [float(v) for v in fit.stderr],
        "cond_X": fit.cond_X,
        "cond_G": fit.cond_G,
        "residuals": [float(v) for v in fit.residuals],
        "rmse": fit.rmse,
        "loo_rmse": fit.loo_rmse,
    }


def _default_model() -> Any:
    try:
        from chainid.model.base import model_for  # type: ignore[attr-defined]
    except ImportError:
        return None
    return model_for(None)


def _poly(alpha: Any, omega: float, A: float) -> float:
    a = np.asarray(alpha, dtype=float)
    return float(a[0] * omega**2 + a[1] * omega + a[2] * A**2 + a[3] * A + a[4])


def audit(model: Any = None) -> dict[str, Any]:
    """Run the audit; every number is computed here.

    Parameters
    ----------
    model : StiffnessModel, optional
        For finding (c): k_e(x) [N/mm] and F_k(x) [N]; default the built-in
        chain (``chainid.model.base.model_for(None)``) when available.

    Returns
    -------
    dict
        ``{"eq28_alpha": [α1..α5], "eq28_alpha_paper", "eq28_matches_4sf", "eq28",
        "eq28_rad_s", "findings": [{"id", "title", "numbers", "summary"}, ...],
        "practice": {"chain", "table", "summary"}}`` (practice: :func:`chainid.model.practice.practice_section`).
    """
    tb = load_table1()
    w_col, A, F_ac, c_e = tb["omega_col"], tb["A"], tb["F_ac"], tb["c_e"]
    fit_col = eq28(1.0)
    fit_rad = eq28(OMEGA_COLUMN_TO_RAD_S)
    alpha = fit_col["alpha"]
    matches = all(sig_round(a, 4) == sig_round(p, 4) for a, p in zip(alpha, EQ28_PAPER))

    findings: list[dict[str, Any]] = []
    findings.append(_finding_omega_unit(w_col, A, F_ac, c_e))
    findings.append(_finding_test1(w_col, A, F_ac, c_e))
    if model is None:
        model = _default_model()
    findings.append(_finding_eq26_stiffness(model))
    findings.append(_finding_validation(alpha, fit_rad["alpha"], w_col, model))
    findings.append(_finding_eq26_phase())

    return {
        "eq28_alpha": alpha,
        "eq28_alpha_paper": list(EQ28_PAPER),
        "eq28_alpha_4sf": [sig_round(a, 4) for a in alpha],
        "eq28_matches_4sf": matches,
        "eq28": fit_col,
        "eq28_rad_s": fit_rad,
        "findings": findings,
        "practice": _practice(model),
    }


def _finding_omega_unit(w_col: Any, A: Any, F_ac: Any, c_e: Any) -> dict[str, Any]:
    """Finding (a): the omega unit implied by c_e = F_ac/(omega A) [rad/s per column unit], from Table 1's columns."""
    implied_omega = F_ac / (c_e * A)  # rad/s such that c_e = F_ac/(omega A)
    factor = implied_omega / w_col
    f29 = factor[1:]
    ratio_col = F_ac / (w_col * A) / c_e  # c_e(as computed with column) / c_e(table)
    return {
        "id": "a",
        "title": "c_e = F_ac/(omega A) holds for tests 2-9 only if omega [rad/s] = (pi/10) x the table's column",
        "numbers": {
            "implied_omega_rad_s": [float(v) for v in implied_omega],
            "implied_factor_omega_over_column": [float(v) for v in factor],
            "factor_tests_2_9_mean": float(np.mean(f29)),
            "factor_tests_2_9_rel_spread": float((f29.max() - f29.min()) / np.mean(f29)),
            "pi_over_10": OMEGA_COLUMN_TO_RAD_S,
            "factor_mean_over_pi_10": float(np.mean(f29) / OMEGA_COLUMN_TO_RAD_S),
            "ce_from_Fac_with_column_as_omega_over_table_ce": [float(v) for v in ratio_col],
            "eq25_omega_test3_rad_s": EQ27["omega"],
            "eq25_over_column_test3": EQ27["omega"] / 6.0,
            "column_equals_f_Hz_times": 2 * math.pi / OMEGA_COLUMN_TO_RAD_S,
        },
        "summary": (
            f"For tests 2-9, F_ac/(c_e A) = {np.mean(f29):.5f} x column "
            f"(spread {100 * (f29.max() - f29.min()) / np.mean(f29):.3f} %), "
            f"i.e. pi/10 = {OMEGA_COLUMN_TO_RAD_S:.5f} to {100 * abs(np.mean(f29) / OMEGA_COLUMN_TO_RAD_S - 1):.3f} % "
            f"(the paper rounds it to {EQ27['omega'] / 6:.4f}, Eq. 25: 1.884 rad/s for column 6). "
            f"With the column used as rad/s, F_ac/(omega A) is {np.mean(ratio_col[1:]):.3f} x the tabulated c_e. "
            f"The column is 20 x f [Hz]; yet Eq. 28 is fitted with the column as omega."
        ),
    }


def _finding_test1(w_col: Any, A: Any, F_ac: Any, c_e: Any) -> dict[str, Any]:
    """Finding (b): test 1's F_ac [N] against its c_e [N·s/mm] at omega [rad/s] = (pi/10) x column."""
    w1 = w_col[0] * OMEGA_COLUMN_TO_RAD_S
    ce1_from_Fac = F_ac[0] / (w1 * A[0])
    Fac1_from_ce = c_e[0] * w1 * A[0]
    return {
        "id": "b",
        "title": "Test 1: F_ac = 8000 N is inconsistent with c_e = 5095.5 N s/mm by a factor of about 20",
        "numbers": {
            "omega_rad_s": w1,
            "F_ac_table": float(F_ac[0]),
            "c_e_table": float(c_e[0]),
            "c_e_implied_by_F_ac": float(ce1_from_Fac),
            "F_ac_implied_by_c_e": float(Fac1_from_ce),
            "factor": float(ce1_from_Fac / c_e[0]),
        },
        "summary": (
            f"At omega = {w1:.4f} rad/s, F_ac = 8000 N gives c_e = {ce1_from_Fac:.1f} N s/mm, "
            f"{ce1_from_Fac / c_e[0]:.2f} x the tabulated 5095.5; c_e = 5095.5 needs F_ac = {Fac1_from_ce:.1f} N."
        ),
    }


def _finding_eq26_stiffness(model: Any) -> dict[str, Any]:
    """Finding (c): Eq. 26's dynamic stiffness F_A/A [N/mm] against the model's k_e [N/mm], and F0 - F_A [N]."""
    kdyn = EQ26["FA"] / EQ27["A"]
    numbers_c: dict[str, Any] = {
        "F0": EQ26["F0"],
        "FA": EQ26["FA"],
        "A": EQ27["A"],
        "dynamic_stiffness_FA_over_A_N_per_mm": kdyn,
        "F0_minus_FA": EQ26["F0"] - EQ26["FA"],
    }
    if model is not None:
        xs = np.array([EQ27["x0"] - EQ27["A"], EQ27["x0"], EQ27["x0"] + EQ27["A"]])
        ke = np.asarray(model.stiffness(xs), dtype=float)
        Fk = np.asarray(model.force(xs), dtype=float)
        numbers_c.update({
            "model": getattr(model, "name", "model"),
            "k_e_at_x0_N_per_mm": float(ke[1]),
            "k_e_range_x0_pm_A_N_per_mm": [float(ke.min()), float(ke.max())],
            "ratio_dynamic_over_k_e": float(kdyn / ke[1]),
            "F_k_at_x0_N": float(Fk[1]),
            "F_k_swing_half_N": float(0.5 * (Fk[2] - Fk[0])),
        })
        extra = (f" The model's k_e(2.2 mm) = {ke[1]:.0f} N/mm, so F_A/A is {kdyn / ke[1]:.2f} x k_e; "
                 f"the model's F_k(2.2 mm) = {Fk[1]:.0f} N against F0 = {EQ26['F0']:.0f} N.")
    else:
        numbers_c["model"] = None
        extra = " (stiffness model not available: k_e not evaluated)"
    return {
        "id": "c",
        "title": "Eq. 26 implies a dynamic stiffness far above the model's k_e, and a compressive minimum force",
        "numbers": numbers_c,
        "summary": (
            f"F_A/A = {EQ26['FA']:.1f}/{EQ27['A']} = {kdyn:.0f} N/mm.{extra} "
            f"F0 - F_A = {EQ26['F0'] - EQ26['FA']:.1f} N < 0: the fitted force would compress the chain."
        ),
    }


def _validation_forces(model: Any, f: float, w_true: float, Av: float, c_paper: float,
                       c_14pi: float) -> dict[str, Any]:
    """Eq. 1 forward prediction of one validation cycle (f [Hz], w_true [rad/s], Av [mm]): F extremes [N]."""
    from chainid.model.predict import predict_force

    numbers_pred: dict[str, Any] = {}
    tt = np.linspace(0.0, 1.0 / f, 721)
    ps = w_true * tt
    xv = VALIDATION["x0"] + Av * np.sin(ps)
    for key, cv in (("omega_7", c_paper), ("omega_14pi", c_14pi)):
        Fv = predict_force(tt, xv, model, cv, xdot=w_true * Av * np.cos(ps), xddot=-w_true**2 * Av * np.sin(ps))
        numbers_pred[f"F_max_N_{key}"] = float(Fv.max())
        numbers_pred[f"F_min_N_{key}"] = float(Fv.min())
    Fk = np.asarray(model.force(xv), dtype=float)
    numbers_pred["F_k_range_N"] = [float(Fk.min()), float(Fk.max())]
    return numbers_pred


def _finding_validation(alpha: Any, alpha_rad: Any, w_col: Any, model: Any) -> dict[str, Any]:
    """Finding (d): Eq. 21's c_e [N·s/mm] at the 7 Hz validation case under each reading of omega."""
    f = VALIDATION["f_Hz"]
    w_true = 2 * math.pi * f
    w_colunit = w_true / OMEGA_COLUMN_TO_RAD_S
    Av = VALIDATION["A"]
    c_paper = _poly(alpha, f, Av)
    c_14pi = _poly(alpha, w_true, Av)
    c_consistent = _poly(alpha, w_colunit, Av)
    c_rad_fit = _poly(alpha_rad, w_true, Av)
    w_min = -alpha[1] / (2 * alpha[0])
    numbers_pred: dict[str, Any] = {}
    if model is not None:  # Eq. 1 forward prediction of one cycle under each reading
        numbers_pred = _validation_forces(model, f, w_true, Av, c_paper, c_14pi)
    return {
        "id": "d",
        "title": ("Validation case: Eq. 21 fed omega = 7 (as the paper does) or 14 pi rad/s "
                  "gives very different damping"),
        "numbers": {
            "x0": VALIDATION["x0"],
            "A": Av,
            "f_Hz": f,
            "omega_rad_s": w_true,
            "c_e_omega_7": c_paper,
            "c_e_omega_14pi": c_14pi,
            "ratio_14pi_over_7": c_14pi / c_paper,
            "omega_in_table_column_unit": w_colunit,
            "c_e_consistent_units": c_consistent,
            "c_e_rad_s_refit_at_14pi": c_rad_fit,
            "F_ac_omega_7_times_true_velocity_N": c_paper * w_true * Av,
            "table_column_range": [float(w_col.min()), float(w_col.max())],
            "table_omega_range_rad_s": [float(w_col.min() * OMEGA_COLUMN_TO_RAD_S),
                                        float(w_col.max() * OMEGA_COLUMN_TO_RAD_S)],
            "omega_of_minimum_c_e_column_unit": w_min,
            **numbers_pred,
        },
        "summary": (
            f"Eq. 21 with omega = 7 gives c_e = {c_paper:.0f} N s/mm; "
            f"with omega = 14 pi = {w_true:.2f} rad/s it gives "
            f"{c_14pi:.0f} N s/mm ({c_14pi / c_paper:.1f} x); "
            f"in the table's own unit (20 f = {w_colunit:.0f}) it gives "
            f"{c_consistent:.4g} N s/mm. The tests cover only {w_col.min() * OMEGA_COLUMN_TO_RAD_S:.3f}-"
            f"{w_col.max() * OMEGA_COLUMN_TO_RAD_S:.3f} rad/s (0.05-0.5 Hz), so 7 Hz is a far extrapolation; the "
            f"minimum of Eq. 21 in omega is at {w_min:.2f} column units, outside the tested 1-10."
            + _validation_forces_text(numbers_pred)
        ),
    }


def _validation_forces_text(numbers_pred: dict[str, Any]) -> str:
    """The sentence on the predicted force range [N] of finding (d); empty without a prediction."""
    return (
        f" Eq. 1 at 7 Hz: F in [{numbers_pred['F_min_N_omega_7']:.0f}, {numbers_pred['F_max_N_omega_7']:.0f}] N "
        f"with c_e(omega = 7), [{numbers_pred['F_min_N_omega_14pi']:.0f}, "
        f"{numbers_pred['F_max_N_omega_14pi']:.0f}] N "
        f"with c_e(14 pi); the elastic part alone spans [{numbers_pred['F_k_range_N'][0]:.0f}, "
        f"{numbers_pred['F_k_range_N'][1]:.0f}] N."
        if numbers_pred else ""
    )


def _finding_eq26_phase() -> dict[str, Any]:
    """Finding (e): Eq. 26's velocity component F_A sin(phi) [N] and work per cycle [N·mm]."""
    v_comp = EQ26["FA"] * math.sin(EQ26["phi"])
    W26 = math.pi * EQ27["A"] * v_comp
    return {
        "id": "e",
        "title": "Eq. 26's phase gives a negative velocity component, contradicting Eq. 27's F_ac = +1335 N",
        "numbers": {
            "FA_sin_phi_N": v_comp,
            "W_per_cycle_Nmm": W26,
            "F_ac_eq27": EQ27["F_ac"],
        },
        "summary": (
            f"With x = x0 + A sin(omega t), the part of F in phase with the velocity is F_A sin(phi) = {v_comp:.0f} N "
            f"(an elastic F_k(x) and the inertia term add nothing at cos(omega t)), so F_ac should be {v_comp:.0f} N "
            f"and W = pi A F_A sin(phi) = {W26:.0f} N mm < 0, against Eq. 27's F_ac = +1335 N."
        ),
    }


def _practice(model: Any) -> dict[str, Any]:
    """The model against practice (:mod:`chainid.model.practice`) for the model's chain (default: the built-in one)."""
    from chainid.model.practice import practice_section

    return practice_section(getattr(model, "chain", None))


def format_audit(rep: dict[str, Any]) -> str:
    """Readable text report of :func:`audit`."""
    lines = ["Eq. 28 reproduced from Table 1 (omega = table column, Eq. 22-24):"]
    names = ["alpha1", "alpha2", "alpha3", "alpha4", "alpha5"]
    e = rep["eq28"]
    lines.append(f"  {'':8s} {'computed':>14s} {'normal eq.':>14s} {'paper':>12s} {'std err':>12s}")
    for n, a, an, p, s in zip(names, e["alpha"], e["alpha_normal_equations"], rep["eq28_alpha_paper"], e["stderr"]):
        lines.append(f"  {n:8s} {a:14.6g} {an:14.6g} {p:12.6g} {s:12.4g}")
    lines.append(f"  matches the paper to 4 significant figures: {'yes' if rep['eq28_matches_4sf'] else 'NO'}")
    lines.append(f"  cond(X) = {e['cond_X']:.4g}, cond(G) = {e['cond_G']:.4g}, RMSE = {e['rmse']:.4g} N s/mm, "
                 f"LOO RMSE = {e['loo_rmse']:.4g} N s/mm")
    r = rep["eq28_rad_s"]
    lines.append("  same fit with omega in rad/s (pi/10 x column): "
                 + ", ".join(f"{v:.5g}" for v in r["alpha"]))
    lines.append("")
    lines.append("Findings:")
    for f in rep["findings"]:
        lines.append(f"({f['id']}) {f['title']}")
        lines.append(f"    {f['summary']}")
    if "practice" in rep:
        from chainid.model.practice import format_practice

        lines += ["", format_practice(rep["practice"])]
    return "\n".join(lines)
