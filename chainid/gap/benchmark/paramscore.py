"""Parameters of a benchmark row against its truth, for both generators (``sim`` and ``ode``).

For every true effect that a verdict names (by canonical name, :data:`CANONICAL`), each of its true parameters that
the diagnosis estimates (``effect.param`` in the row's ``params``) is compared with the truth: the relative error
|est − true|/|true| (none for a true value of 0), and whether the reported interval covers the truth —
``params_ci90`` [lo, hi] (percentile interval over resamples) when given, else est ± 1.645·``params_sd`` (a 90 %
normal interval); no interval, no coverage.  The scores are pooled per parameter (:func:`param_table`) and per effect
(:func:`coverage_by_effect`): the calibration table of the 90 % intervals (calibrated: 85–95 %).  The parameters of
one case share its data, so a family's coverage is as uncertain as its number of cases says, not its number of
intervals: its 95 % range is the exact (Clopper–Pearson) interval of the share over the cases (:func:`rate_range`),
and a rate outside 85–95 % whose range holds 90 % is a deviation those cases cannot tell from calibration.

A truth is ``{"effects": {effect: {param: value}}}``, optionally with ``covariate`` (the ODE world: a parameter
that follows an operating condition is compared with its law at the mean condition).

Units: each parameter's own (N, mm, s, mm/N, kg, -).
"""

from __future__ import annotations

from typing import Any, Iterable

import numpy as np

__all__ = ["CANONICAL", "Z90", "ERR_HW_CALIBRATED", "param_scores", "pool_scores", "param_table", "coverage_by_effect",
           "coverage_lines", "rate_range", "range_text", "calibration_mark"]

#: effects that are the same physics for the diagnosis (the canonical name is what a right verdict says)
CANONICAL = {"machine_compliance": "stiffness_level"}
#: z of a two-sided 90 % normal interval
Z90 = 1.6448536269514722
#: the nominal level of the intervals under calibration, and the band that counts as calibrated
NOMINAL, BAND = 0.90, (0.85, 0.95)
#: the median of |estimate − truth| / half-width for a calibrated 90 % interval of a normal error: z₇₅ / z₉₅
#: (0.6745 / 1.6449); a median well below it says the intervals are too wide, above it too narrow
ERR_HW_CALIBRATED = 0.4100606516861704


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
        Per parameter: ``param`` (``effect.param``), ``truth``, ``estimate``, ``rel_error`` (None for a true 0),
        ``covered`` (None without an interval), ``err_halfwidth`` (|est − truth| over the interval's half-width on
        the truth's side) and ``parts`` (the same two numbers for each part of the interval the row keeps apart in
        ``params_ci90_parts``: ``resampled``, ``profile``).
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
            if ci is None and sd is not None and sd > 0:
                ci = [est - Z90 * sd, est + Z90 * sd]
            parts = {name: _cover(part[key], est, tv) for name, part in (row.get("params_ci90_parts") or {}).items()
                     if key in part}
            out.append({"param": key, "truth": tv, "estimate": float(est), "rel_error": rel,
                        **_cover(ci, est, tv), "parts": parts})
    return out


def _cover(ci: Any, est: float, tv: float) -> dict[str, Any]:
    """``covered`` (whether [lo, hi] holds the truth ``tv``; None without an interval) and ``err_halfwidth``
    (|est − tv| over the interval's half-width on the truth's side; None without one or for a zero half-width)."""
    if ci is None:
        return {"covered": None, "err_halfwidth": None}
    hw = (ci[1] - est) if tv >= est else (est - ci[0])
    return {"covered": bool(ci[0] <= tv <= ci[1]), "err_halfwidth": abs(est - tv) / hw if hw > 0 else None}


def pool_scores(scores: Iterable[list[dict[str, Any]]]) -> dict[str, list[dict[str, Any]]]:
    """The scores of many rows (each a :func:`param_scores` list) by parameter name, names sorted; each score
    carries ``case``, the position of its row."""
    ps: dict[str, list[dict[str, Any]]] = {}
    for i, row_scores in enumerate(scores):
        for p in row_scores:
            ps.setdefault(p["param"], []).append({**p, "case": i})
    return dict(sorted(ps.items()))


def rate_range(rate: float, n: float, level: float = 0.95) -> tuple[float, float]:
    """The exact (Clopper–Pearson) two-sided interval [lo, hi] at ``level`` of a share ``rate`` observed over ``n``
    independent trials: the Beta quantiles lo = B⁻¹((1−level)/2; k, n−k+1), hi = B⁻¹((1+level)/2; k+1, n−k) with
    k = rate·n (lo = 0 at k = 0, hi = 1 at k = n; a pooled share of several parameters per case gives a k that need
    not be whole).  It never claims more than the trials show, also for a handful of cases, where the normal-theory
    (Wald, Wilson) intervals are too narrow at the ends: 0 of 1 gives 0–97.5 %, not Wilson's 0–79 %.

    Raises
    ------
    ValueError
        ``rate`` outside [0, 1], ``n`` not > 0, or ``level`` outside (0, 1).
    """
    from scipy.stats import beta

    if not n > 0 or not 0.0 <= rate <= 1.0 or not 0.0 < level < 1.0:
        raise ValueError(f"rate_range: rate = {rate!r} must be in [0, 1] and n = {n!r} > 0 (level = {level!r} in "
                         "(0, 1))")
    k, tail = rate * n, (1.0 - level) / 2.0
    lo = 0.0 if k <= 0.0 else float(beta.ppf(tail, k, n - k + 1.0))
    hi = 1.0 if k >= n else float(beta.ppf(1.0 - tail, k + 1.0, n - k))
    return lo, hi


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
    calibrated: 0.85–0.95), ``n_cases`` (the cases those intervals come from: ``case`` of :func:`pool_scores`),
    ``coverage_range95`` (:func:`rate_range` of the share over ``n_cases``), ``consistent`` (whether 0.90 is in
    that range), ``median_rel_error`` (over every score of the effect with a relative error),
    ``median_err_halfwidth`` (the median |error| / half-width, :data:`ERR_HW_CALIBRATED` when calibrated) and
    ``parts`` (coverage and that median for each part of the intervals alone, :func:`_parts`)."""
    groups: dict[str, list[dict[str, Any]]] = {}
    for key, v in ps.items():
        groups.setdefault(key.split(".", 1)[0], []).extend(v)
    out: dict[str, Any] = {}
    for eff, v in sorted(groups.items()):
        with_ci = [p for p in v if p["covered"] is not None]
        cov = [bool(p["covered"]) for p in with_ci]
        rate = sum(cov) / len(cov) if cov else None
        n_cases = len({p.get("case", ("score", i)) for i, p in enumerate(with_ci)})  # untagged: one case each
        rng = rate_range(rate, n_cases) if rate is not None else None
        out[eff] = {"n_interval": len(cov), "covered": sum(cov), "coverage": rate, "n_cases": n_cases,
                    "coverage_range95": list(rng) if rng else None,
                    "consistent": None if rng is None else bool(rng[0] <= NOMINAL <= rng[1]),
                    "median_rel_error": _median_rel(v), "median_err_halfwidth": _median_ratio(with_ci),
                    "parts": _parts(v)}
    return out


def _median_ratio(v: list[dict[str, Any]]) -> float | None:
    r = [p["err_halfwidth"] for p in v if p.get("err_halfwidth") is not None]
    return float(np.median(r)) if r else None


def _parts(v: list[dict[str, Any]]) -> dict[str, Any]:
    """Per part of the intervals (``resampled``, ``profile``: :func:`chainid.gap.benchmark.simtruth.interval_parts`)
    the share of its intervals that cover the truth and their median |error| / half-width (to compare with
    :data:`ERR_HW_CALIBRATED`)."""
    from chainid.gap.benchmark.simtruth import PARTS  # the parts in the order they are built

    out = {}
    for name in PARTS:
        got = [p["parts"][name] for p in v if name in p.get("parts", {})]
        if not got:
            continue
        out[name] = {"n_interval": len(got), "coverage": sum(g["covered"] for g in got) / len(got),
                     "median_err_halfwidth": _median_ratio(got)}
    return out


def range_text(v: dict[str, Any]) -> str:
    """An effect's ``coverage_range95`` (:func:`coverage_by_effect`) as ``51-100 %``; empty without one."""
    r = v.get("coverage_range95")
    return f"{100 * r[0]:.0f}-{100 * r[1]:.0f} %" if r else ""


def calibration_mark(v: dict[str, Any]) -> str:
    """``ok`` for a coverage inside 85–95 %; outside it ``low``/``high`` when its cases' range holds 90 % (the
    deviation is within what that many cases show), else ``LOW``/``HIGH``; empty without a rate."""
    r = v.get("coverage")
    if r is None:
        return ""
    if BAND[0] <= r <= BAND[1]:
        return "ok"
    side = "low" if r < BAND[0] else "high"
    return side if v.get("consistent") else side.upper()


def pct(v: float | None, digits: int = 0) -> str:
    """A rate as a percentage (``"91 %"``, ``digits`` decimals), ``"n/a"`` for None."""
    return "n/a" if v is None else f"{100 * v:.{digits}f} %"


def coverage_lines(cov: dict[str, Any], title: str) -> list[str]:
    """Terminal table of :func:`coverage_by_effect`: one line per effect (intervals, covered, cases, rate, the
    rate's 95 % range over the cases, :func:`calibration_mark`, median relative error)."""
    lines = [title, f"  {'effect':<20}{'intervals':>10}{'covered':>9}{'cases':>7}{'rate':>8}{'95 % range':>14}"
                    f"{'':>6}{'median rel. error':>19}{'|err|/hw':>10}"]
    for eff, v in cov.items():
        shown = range_text(v) or "n/a"
        lines.append(f"  {eff:<20}{v['n_interval']:>10}{v['covered']:>9}{v.get('n_cases', 0):>7}"
                     f"{pct(v['coverage']):>8}{shown:>14}{calibration_mark(v):>6}{pct(v['median_rel_error'], 1):>19}"
                     f"{_ratio(v.get('median_err_halfwidth')):>10}")
    lines.append("  (ok: inside 85-95 %; low/high: outside it, but 90 % is in the range its cases allow; LOW/HIGH: "
                 f"90 % is not; |err|/hw: median |error| / half-width, {ERR_HW_CALIBRATED:.2f} when calibrated)")
    parts = [f"{eff} {name} {pct(q['coverage'])} ({_ratio(q['median_err_halfwidth'])})"
             for eff, v in cov.items() for name, q in (v.get("parts") or {}).items()]
    if parts:
        lines.append("  each part alone, coverage (|err|/hw): " + "; ".join(parts))
    return lines


def _ratio(v: float | None) -> str:
    return "n/a" if v is None else f"{v:.2f}"
