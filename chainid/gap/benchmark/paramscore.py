"""Parameters of a benchmark row against its truth, for both generators (``sim`` and ``ode``).

For every true effect that a verdict names (by canonical name, :data:`CANONICAL`), each of its true parameters that
the diagnosis estimates (``effect.param`` in the row's ``params``) is compared with the truth: the relative error
|est − true|/|true| (none for a true value of 0), and whether the reported interval covers the truth —
``params_ci90`` [lo, hi] (percentile interval over resamples) when given, else est ± 1.645·``params_sd`` (a 90 %
normal interval); no interval, no coverage.  The scores are pooled per parameter (:func:`param_table`) and per effect
(:func:`coverage_by_effect`): the calibration table of the 90 % intervals (calibrated: 85–95 %).

A truth is ``{"effects": {effect: {param: value}}}``, optionally with ``covariate`` (the ODE world: a parameter
that follows an operating condition is compared with its law at the mean condition).

Units: each parameter's own (N, mm, s, mm/N, kg, -).
"""

from __future__ import annotations

from typing import Any, Iterable

import numpy as np

__all__ = ["CANONICAL", "Z90", "param_scores", "pool_scores", "param_table", "coverage_by_effect", "coverage_lines"]

#: effects that are the same physics for the diagnosis (the canonical name is what a right verdict says)
CANONICAL = {"machine_compliance": "stiffness_level"}
#: z of a two-sided 90 % normal interval
Z90 = 1.6448536269514722


def _truth_value(truth: dict[str, Any], eff: str, p: str, v: float) -> float:
    cov = truth.get("covariate")
    if cov and cov["effect"] == eff and cov["param"] == p:
        return float(cov["p0"] + cov["p1"] * np.mean(cov["values"]))
    return float(v)


def param_scores(row: dict[str, Any], named: list[str]) -> list[dict[str, Any]]:
    """Estimate vs truth for every parameter of a named true effect that the diagnosis reports.

    Parameters
    ----------
    row : a benchmark row: ``truth`` (see the module docstring), ``params`` and optionally ``params_ci90`` and
        ``params_sd`` keyed ``effect.param`` (each parameter in its own unit)
    named : the canonical names of the effects the verdict names

    Returns
    -------
    list of dict
        Per parameter: ``param`` (``effect.param``), ``truth``, ``estimate``, ``rel_error`` (None for a true 0) and
        ``covered`` (None without an interval).
    """
    truth = row.get("truth") or {}
    out = []
    for eff, params in (truth.get("effects") or {}).items():
        if CANONICAL.get(eff, eff) not in named:
            continue
        for p, v in params.items():
            key = f"{eff}.{p}"
            est = (row.get("params") or {}).get(key)
            if est is None:
                continue
            tv = _truth_value(truth, eff, p, v)
            rel = abs(est - tv) / abs(tv) if tv != 0 else None
            ci, sd = (row.get("params_ci90") or {}).get(key), (row.get("params_sd") or {}).get(key)
            if ci is not None:
                cover: bool | None = bool(ci[0] <= tv <= ci[1])
            elif sd is not None and sd > 0:
                cover = bool(abs(est - tv) <= Z90 * sd)
            else:
                cover = None
            out.append({"param": key, "truth": tv, "estimate": float(est), "rel_error": rel, "covered": cover})
    return out


def pool_scores(scores: Iterable[list[dict[str, Any]]]) -> dict[str, list[dict[str, Any]]]:
    """The scores of many rows (each a :func:`param_scores` list) by parameter name, names sorted."""
    ps: dict[str, list[dict[str, Any]]] = {}
    for row_scores in scores:
        for p in row_scores:
            ps.setdefault(p["param"], []).append(p)
    return dict(sorted(ps.items()))


def _median_rel(v: list[dict[str, Any]]) -> float | None:
    rel = [p["rel_error"] for p in v if p["rel_error"] is not None]
    return float(np.median(rel)) if rel else None


def param_table(ps: dict[str, list[dict[str, Any]]]) -> dict[str, Any]:
    """Per parameter: ``n`` scores, ``median_rel_error``, ``n_interval`` (scores with an interval) and
    ``coverage`` (the share of those whose interval covers the truth; None without any)."""
    out = {}
    for k, v in ps.items():
        cov = [bool(p["covered"]) for p in v if p["covered"] is not None]
        out[k] = {"n": len(v), "median_rel_error": _median_rel(v), "n_interval": len(cov),
                  "coverage": sum(cov) / len(cov) if cov else None}
    return out


def coverage_by_effect(ps: dict[str, list[dict[str, Any]]]) -> dict[str, Any]:
    """Per effect (the part of ``effect.param`` before the dot), every parameter of it pooled: ``n_interval``
    (scores with an interval), ``covered`` (whose 90 % interval covers the truth), ``coverage`` (the share;
    calibrated: 0.85–0.95) and ``median_rel_error`` (over every score of the effect with a relative error)."""
    groups: dict[str, list[dict[str, Any]]] = {}
    for key, v in ps.items():
        groups.setdefault(key.split(".", 1)[0], []).extend(v)
    out: dict[str, Any] = {}
    for eff, v in sorted(groups.items()):
        cov = [bool(p["covered"]) for p in v if p["covered"] is not None]
        out[eff] = {"n_interval": len(cov), "covered": sum(cov), "coverage": sum(cov) / len(cov) if cov else None,
                    "median_rel_error": _median_rel(v)}
    return out


def _pct(v: float | None, digits: int = 0) -> str:
    return "n/a" if v is None else f"{100 * v:.{digits}f} %"


def coverage_lines(cov: dict[str, Any], title: str) -> list[str]:
    """Terminal table of :func:`coverage_by_effect`: one line per effect (intervals, covered, rate, median relative
    error), the rate marked ``ok`` inside the calibrated 85–95 % and ``LOW``/``HIGH`` outside it."""
    lines = [title, f"  {'effect':<20}{'intervals':>10}{'covered':>9}{'rate':>8}{'':>6}{'median rel. error':>19}"]
    for eff, v in cov.items():
        r = v["coverage"]
        mark = "" if r is None else ("ok" if 0.85 <= r <= 0.95 else ("LOW" if r < 0.85 else "HIGH"))
        lines.append(f"  {eff:<20}{v['n_interval']:>10}{v['covered']:>9}{_pct(r):>8}{mark:>6}"
                     f"{_pct(v['median_rel_error'], 1):>19}")
    return lines
