"""The Eq. 28 audit on the user's own records (``chainid audit --data``) instead of the paper's Table 1.

c_e(ω, A) is identified per test by :func:`chainid.damping.identify.identify_records` (Eq. 17–20, 27: the one place
of that equation), then audited as :mod:`chainid.damping.audit` audits Table 1: Eq. 21 fitted by ``lstsq`` and by
the paper's normal equations G·α = C (Eq. 22–24), with standard errors, condition numbers and leave-one-out error,
in rad/s and in the paper's column unit (20·f [Hz] = ω·10/π, so that the coefficients compare with Eq. 28), and
the findings that apply to measured data:

* (a) c_e·ω·A = F_ac per test (Eq. 27; a check of the identification's units);
* (c) the dynamic stiffness F_A/A against the model's k_e(x0), and tests whose minimum force F0 − F_A < 0;
* (d) the tested range of ω and A, the stationary points of the fitted Eq. 21 and where it is ≤ 0 inside that
  range (an extrapolation or an unphysical damping);
* (e) tests whose velocity component F_ac or loop energy W is ≤ 0 (energy generated, not dissipated);
* whether Eq. 21's five-parameter form is the best of the laws by leave-one-out error (:func:`rank_laws`).

Units: ω rad/s, A and x0 mm, forces N, c_e N·s/mm, W N·mm.
"""
from __future__ import annotations

import math
from typing import Any, Callable, Sequence

import numpy as np

from chainid.damping.audit import OMEGA_COLUMN_TO_RAD_S, EQ28_PAPER
from chainid.damping.identify import TestResult, identify_records
from chainid.model.laws import MIN_TESTS, PolynomialLaw, fit_law, rank_laws
from chainid.records.record import Record

__all__ = ["audit_records", "audit_results", "format_audit_data"]


def _fit(omega: np.ndarray, A: np.ndarray, ce: np.ndarray, scale: float) -> dict[str, Any]:
    """The polynomial law c_e(ω·scale, A) [N·s/mm] (Eq. 21) fitted to the tests, as the audit's JSON rows."""
    f = fit_law(PolynomialLaw(), omega * scale, A, ce)
    return {"omega_scale": scale, "alpha": [float(v) for v in f.params],
            "alpha_normal_equations": [float(v) for v in f.params_normal], "stderr": [float(v) for v in f.stderr],
            "cond_X": f.cond_X, "cond_G": f.cond_G, "residuals": [float(v) for v in f.residuals], "rmse": f.rmse,
            "loo_rmse": f.loo_rmse}


def audit_records(records: Sequence[Record], model: Any, *, mass_kg: float | None = None,
                  allow_compression: bool = True, steady_tol: float | None = None, strict: bool = False,
                  progress: Callable[[int, int, str], None] | None = None) -> dict[str, Any]:
    """Identify c_e per test from harmonic records and audit Eq. 28 on them.

    Parameters
    ----------
    records : sequence of Record
        Harmonic tests x = x0 + A sin ωt (t s, x mm, F N).
    model : StiffnessModel
        Elastic force F_k(x) [N] and k_e(x) [N/mm] removed before c_e (Eq. 17, 20).
    mass_kg, allow_compression, steady_tol, strict, progress
        As :func:`chainid.damping.identify.identify_records`.

    Returns
    -------
    dict
        :func:`audit_results` plus ``"excluded"`` (tests left out, with the reason).

    Raises
    ------
    ValueError
        Fewer than :data:`chainid.model.laws.MIN_TESTS` identified tests (Eq. 21 has five parameters), and
        what :func:`identify_records` raises.
    """
    res = identify_records(records, model, mass_kg=mass_kg, allow_compression=allow_compression,
                           steady_tol=steady_tol, strict=strict, progress=progress)
    if len(res) < MIN_TESTS:
        raise ValueError(f"only {len(res)} test(s) identified ({len(res.excluded)} excluded): the Eq. 28 audit fits "
                         f"Eq. 21's five parameters and needs at least {MIN_TESTS} tests (paper Eq. 22: M > 5)")
    rep = audit_results(list(res), model)
    rep["excluded"] = list(res.excluded)
    return rep


def audit_results(results: Sequence[TestResult], model: Any = None) -> dict[str, Any]:
    """The Eq. 28 audit of identified tests (see the module docstring); every number is computed here.

    Parameters
    ----------
    results : sequence of TestResult
        Per-test identification (ω rad/s, x0 and A mm, F0, F_A, F_ac N, c_e N·s/mm, W N·mm).
    model : StiffnessModel, optional
        For finding (c): k_e(x0) [N/mm].

    Returns
    -------
    dict
        ``{"source": "data", "tests": [...], "eq28_alpha": α (ω rad/s), "eq28": fit, "eq28_column_unit": fit with ω
        in the paper's column unit, "eq28_alpha_paper", "findings": [{"id", "title", "numbers", "summary"}],
        "ranking": [...]}``.
    """
    g = {k: np.array([getattr(r, k) for r in results], dtype=float)
         for k in ("omega", "A", "x0", "F0", "FA", "F_ac", "c_e", "W")}
    w, A, ce = g["omega"], g["A"], g["c_e"]
    ids = [r.test for r in results]
    fit = _fit(w, A, ce, 1.0)
    fit_col = _fit(w, A, ce, 1.0 / OMEGA_COLUMN_TO_RAD_S)
    al = fit["alpha"]
    findings = [_finding_units(g), _finding_stiffness(g, ids, model), _finding_range(w, A, al), _finding_signs(g, ids)]
    rows, laws = _finding_laws(w, A, ce, g["x0"], model)
    findings.append(laws)
    return {"source": "data", "tests": [r.to_dict() for r in results], "eq28_alpha": al, "eq28": fit,
            "eq28_column_unit": fit_col, "eq28_alpha_paper": list(EQ28_PAPER), "findings": findings,
            "ranking": rows}


def _finding_units(g: dict[str, np.ndarray]) -> dict[str, Any]:
    """Finding (a): F_ac/(c_e·ω·A) per test (Eq. 27; F_ac N, c_e N·s/mm, ω rad/s, A mm), 1 when ω is in rad/s."""
    ratio = g["F_ac"] / (g["c_e"] * g["omega"] * g["A"])
    dev = float(np.max(np.abs(ratio - 1.0)))
    return {"id": "a", "title": "c_e = F_ac/(omega A) per test (Eq. 27), omega in rad/s",
            "numbers": {"F_ac_over_ce_omega_A": [float(v) for v in ratio], "max_rel_deviation": dev},
            "summary": f"F_ac/(c_e omega A) is 1 within {dev:.2g} for every test: omega is in rad/s "
                       f"throughout (the paper's Table 1 needs omega = (pi/10) x its column)."}


def _finding_stiffness(g: dict[str, np.ndarray], ids: list[str], model: Any) -> dict[str, Any]:
    """Finding (c): the dynamic stiffness F_A/A [N/mm] against the model's k_e(x0) [N/mm] (``model`` None: not
    compared), and the tests whose minimum force F0 − F_A [N] is < 0."""
    A = g["A"]
    kdyn = g["FA"] / A
    fmin = g["F0"] - g["FA"]
    num_c: dict[str, Any] = {"dynamic_stiffness_FA_over_A_N_per_mm": [float(v) for v in kdyn],
                             "F_min_N": [float(v) for v in fmin],
                             "tests_with_compressive_minimum": [t for t, v in zip(ids, fmin) if v < 0]}
    text_c = ""
    if model is not None:
        ke = np.asarray(model.stiffness(g["x0"]), dtype=float)
        num_c["k_e_at_x0_N_per_mm"] = [float(v) for v in ke]
        num_c["ratio_dynamic_over_k_e"] = [float(v) for v in kdyn / ke]
        text_c = (f"F_A/A is {float(np.min(kdyn / ke)):.3g}-{float(np.max(kdyn / ke)):.3g} x the model's k_e(x0) "
                  f"({getattr(model, 'name', 'model')}). ")
    neg = num_c["tests_with_compressive_minimum"]
    return {"id": "c", "title": "Dynamic stiffness F_A/A against the model's k_e, and the minimum force",
            "numbers": num_c,
            "summary": text_c + (f"F0 - F_A < 0 (compression) in test(s) {', '.join(neg)}." if neg else
                                 f"F0 - F_A >= {float(fmin.min()):.4g} N > 0: no test compresses.")}


def _finding_range(w: np.ndarray, A: np.ndarray, al: list[float]) -> dict[str, Any]:
    """Finding (d): the tested ranges of ω [rad/s] and A [mm], the stationary points of the fitted Eq. 21 (``al``)
    and its minimum c_e [N·s/mm] over the tested box."""
    wlo, whi, alo, ahi = float(w.min()), float(w.max()), float(A.min()), float(A.max())
    w_star = -al[1] / (2 * al[0]) if al[0] != 0 else math.inf
    a_star = -al[3] / (2 * al[2]) if al[2] != 0 else math.inf
    ww, aa = np.meshgrid(np.linspace(wlo, whi, 41), np.linspace(alo, ahi, 41))
    cgrid = al[0] * ww ** 2 + al[1] * ww + al[2] * aa ** 2 + al[3] * aa + al[4]
    cmin = float(cgrid.min())
    inside = [n for n, v, lo, hi in (("omega", w_star, wlo, whi), ("A", a_star, alo, ahi)) if lo < v < hi]
    return {"id": "d", "title": "Range of the tests and the fitted Eq. 21 inside and outside it",
            "numbers": {"omega_range_rad_s": [wlo, whi], "A_range_mm": [alo, ahi],
                        "stationary_omega_rad_s": w_star, "stationary_A_mm": a_star,
                        "stationary_points_inside_range": inside, "min_c_e_fit_in_range": cmin},
            "summary": (f"Tests cover omega {wlo:.4g}-{whi:.4g} rad/s and A {alo:.4g}-{ahi:.4g} mm; Eq. 21 "
                        f"is stationary at omega = {w_star:.4g} rad/s and A = {a_star:.4g} mm"
                        f"{' (inside the tested range: ' + ', '.join(inside) + ')' if inside else ''}; its "
                        f"minimum over the tested range is {cmin:.4g} N s/mm"
                        f"{' <= 0: unphysical' if cmin <= 0 else ''}. Outside the range it extrapolates.")}


def _finding_signs(g: dict[str, np.ndarray], ids: list[str]) -> dict[str, Any]:
    """Finding (e): the tests whose velocity component F_ac [N] or loop energy W [N·mm] is <= 0 (energy generated)."""
    bad = [t for t, f_, e in zip(ids, g["F_ac"], g["W"]) if not (f_ > 0 and e > 0)]
    return {"id": "e", "title": "Sign of the velocity component F_ac and of the loop energy W",
            "numbers": {"F_ac_N": [float(v) for v in g["F_ac"]], "W_Nmm": [float(v) for v in g["W"]],
                        "tests_generating_energy": bad},
            "summary": (f"F_ac <= 0 or W <= 0 (energy generated) in test(s) {', '.join(bad)}." if bad else
                        "F_ac > 0 and W > 0 in every test: the loops dissipate.")}


def _finding_laws(w: np.ndarray, A: np.ndarray, ce: np.ndarray, x0: np.ndarray,
                  model: Any) -> tuple[list[dict[str, Any]], dict[str, Any]]:
    """Finding (f): the damping laws ranked by leave-one-test-out error on c_e [N·s/mm] (ω rad/s, A and x0 mm):
    (the ranking's rows without the fitted laws, the finding)."""
    ranking = rank_laws(w, A, ce, x0, model=model)
    rows = [{k: v for k, v in r.items() if k != "fitted"} for r in ranking]
    best = rows[0]["law"] if rows else None
    poly = next((r for r in rows if r["law"] == "polynomial"), None)
    return rows, {"id": "f", "title": "Eq. 21's form against the other laws (leave-one-test-out error)",
                  "numbers": {"best_law": best, "polynomial_loo_rmse": poly.get("loo_rmse") if poly else None},
                  "summary": (f"Best law by leave-one-out RMSE: {best}"
                              + (f"; Eq. 21 (polynomial) {poly['loo_rmse']:.4g} N s/mm against "
                                 f"{rows[0]['loo_rmse']:.4g}." if poly and "loo_rmse" in poly else "."))}


def format_audit_data(rep: dict[str, Any]) -> str:
    """Readable text of :func:`audit_records` (the counterpart of :func:`chainid.damping.audit.format_audit`)."""
    lines = [f"Eq. 21 fitted to c_e of {len(rep['tests'])} identified test(s) (Eq. 22-24; omega rad/s):"]
    e, ec = rep["eq28"], rep["eq28_column_unit"]
    lines.append(f"  {'':8s} {'lstsq':>14s} {'normal eq.':>14s} {'std err':>12s} {'omega=20f':>14s} {'paper':>12s}")
    for i, (a, an, s) in enumerate(zip(e["alpha"], e["alpha_normal_equations"], e["stderr"])):
        lines.append(f"  alpha{i + 1:<3d} {a:14.6g} {an:14.6g} {s:12.4g} {ec['alpha'][i]:14.6g} "
                     f"{rep['eq28_alpha_paper'][i]:12.6g}")
    lines.append(f"  cond(X) = {e['cond_X']:.4g}, cond(G) = {e['cond_G']:.4g}, RMSE = {e['rmse']:.4g} N s/mm, "
                 f"LOO RMSE = {e['loo_rmse']:.4g} N s/mm")
    lines += ["", "Findings:"]
    for f in rep["findings"]:
        lines += [f"({f['id']}) {f['title']}", f"    {f['summary']}"]
    if rep.get("excluded"):
        lines.append(f"{len(rep['excluded'])} test(s) excluded: "
                     + "; ".join(f"{x['test']} ({x['reason']})" for x in rep["excluded"]))
    return "\n".join(lines)
