"""Profile-likelihood 90 % intervals of a fitted candidate's parameters.

A parameter θ_j is held at a value v and every other parameter refitted; the profile χ²_p(v) is the least χ² of
the training data with θ_j = v.  The 90 % interval is every v with

    χ²_p(v) − χ²_min ≤ q₉₀ · s²,      q₉₀ = 2.7055 (the 90 % point of χ² with one degree of freedom),

(Wilks' theorem for one parameter), where s² = max(1, χ²_min / (n − p)) scales the level by the residual's
excess over its noise when the model does not reach it (the misfit is read as noise of that size: quasi-likelihood).
No linearisation: the profile is scanned, so a parameter in a flat or rough valley (a sensor delay against a sharp
friction, whose χ² steps as a switch crosses a sample) gets the width the data allow.  Resampling the training
units cannot see that width when every refit, polished from the full fit, stays in the same flat spot; the
profile cannot see the variation between units that the resampling does, beyond the pooled residual.  The reported
interval (:func:`merge`) is the union of both where the units are evidently heterogeneous (:func:`heterogeneous`:
the resampling's spread exceeds the profile's by more than its own scatter from m units), and otherwise the
profile's alone, widened by the biases that widened the resampling's: two intervals that each cover 90 % cover
more together.

Before the scan, the least χ²_p near the estimate is searched for (:func:`refine_minimum`, a bounded Brent search
within the first step): where χ² is not smooth in a parameter (a play's or a friction's switch crossing samples)
the fit's own search can stop short of it, and every edge is read against the least χ².

The scan walks out from that minimum on each side, doubling its step (the first is the resampling interval's
half-width, at least 10⁻⁴ of the bounds' span, or of the estimate where a bound is infinite) until χ²_p exceeds
the level or the bound is reached, then bisects the bracket [last point inside, first point outside] at least
:data:`BISECT` times, and on until it is no wider than an eighth (2^−:data:`RESOLVE`) of its inside end's distance
from the scan's start (at most :data:`BISECT_MAX` times), so a first step far wider than the interval still finds it
and a profile that is not quadratic is read within that bracket.  A refit that fails (a NaN χ²) counts as
outside the level.  The edge is the crossing
interpolated in that bracket on √(χ²_p − χ²_min), which is linear in the parameter where the profile is quadratic
(:func:`crossing`): the interval is not cut short to the last point scanned inside it.  A lower χ² met on the way
(the fit had stopped short of the optimum) lowers χ²_min, and the edges are read at the end against the least χ²
seen.  Each refit starts from the last point inside the level.  The intervals of a candidate are finally the union
of each parameter's own edges and the points of all its parameters' profiles inside the level (:func:`project`).

What it cannot see: an optimum in another basin that no scan reaches (the fit's search decides that), and a
residual correlated over more samples than the route counts as independent (the resampling's blocks see that).

Units: each parameter's own; χ² dimensionless.
"""

from __future__ import annotations

import math
from typing import Any, Callable, Sequence

from chainid.infra.forkpool import fork_map

__all__ = ["Q90", "BISECT", "BISECT_MAX", "RESOLVE", "MAX_DOUBLINGS", "REFINE", "least", "level", "crossing",
           "scan_side", "refine_minimum", "profile_interval", "project", "heterogeneous", "merge", "problem_hooks",
           "attach_profiles"]

#: the 90 % point of χ² with one degree of freedom (scipy.stats.chi2.ppf(0.9, 1))
Q90 = 2.705543454095404
#: the one-sided 95 % point of the standard normal (scipy.stats.norm.ppf(0.95))
Z95 = 1.6448536269514722
#: least bisections of a crossing's bracket
BISECT = 4
#: most bisections of a crossing's bracket (a first step 2⁹ times wider than the interval still resolves it)
BISECT_MAX = 12
#: the bracket is bisected until it is no wider than 2^−RESOLVE of its inside end's distance from the scan's start
RESOLVE = 3
#: most doublings of the step on one side before the scan gives up (the interval then reaches the last point)
MAX_DOUBLINGS = 14
#: most refits of the search for the least χ² near the estimate before the scan (:func:`refine_minimum`)
REFINE = 8

Chi2 = Callable[[dict[str, float]], float]
Refit = Callable[[str, float, dict[str, float]], dict[str, float]]


def least(pts: Sequence[tuple[float, float, Any]]) -> float:
    """The least finite χ² among scanned points (value, χ², parameters); inf when none is finite (a failed refit's
    NaN never becomes the minimum)."""
    return min((q[1] for q in pts if math.isfinite(q[1])), default=math.inf)


def level(chi2_min: float, n: int, p: int) -> float:
    """The profile's level above χ²_min: q₉₀ · max(1, χ²_min / (n − p)) (dimensionless)."""
    if n <= p:
        raise ValueError(f"n = {n} residuals for p = {p} fitted values: a profile needs n > p")
    return Q90 * max(1.0, chi2_min / (n - p))


def crossing(bracket: tuple[float, float, float, float], chi2_min: float, lev: float) -> float | None:
    """Where χ²_p − χ²_min crosses ``lev`` inside a bracket (v_in, χ²_in, v_out, χ²_out) [the parameter's unit]:
    interpolated linearly in √(χ²_p − χ²_min), exact for a quadratic profile (√ of a square is linear in the
    parameter); None when the inside end is no longer inside the level (χ²_min fell since) or the outside end is
    not outside it."""
    v_in, c_in, v_out, c_out = bracket
    d_in, d_out = max(c_in - chi2_min, 0.0), c_out - chi2_min
    if not d_in <= lev < d_out:  # a NaN at either end: no crossing to read
        return None
    if not math.isfinite(d_out):
        return v_in
    r_in, r_out, r_lev = math.sqrt(d_in), math.sqrt(d_out), math.sqrt(lev)
    return v_in + (v_out - v_in) * (r_lev - r_in) / (r_out - r_in)


def scan_side(key: str, est: dict[str, float], bound: float, step: float, chi2: Chi2, refit: Refit,
              lev: Callable[[], float], pts: list[tuple[float, float, dict[str, float]]], c0: float | None = None
              ) -> tuple[float, float, float, float] | None:
    """Walk from ``est[key]`` towards ``bound`` until χ²_p passes ``lev()`` above the least χ² seen, then bisect
    the bracket (at least :data:`BISECT` times, on while it is wider than 2^−RESOLVE of its inside end's distance
    from the start, at most :data:`BISECT_MAX`); a NaN χ² counts as outside.

    Every point scanned is appended to ``pts`` as (value, χ²_p, parameters); ``c0`` is χ² at ``est`` (default
    ``pts[0]``'s).  Returns the final bracket
    (v_in, χ²_in, v_out, χ²_out) for :func:`crossing`; None when the scan reached the bound inside the level or
    never left it."""
    v0 = est[key]
    inside, p_in, c_in = v0, est, pts[0][1] if c0 is None else c0
    sign = 1.0 if bound >= v0 else -1.0
    h = abs(step)
    out = None
    for _ in range(MAX_DOUBLINGS):
        v = v0 + sign * h
        if sign * (v - bound) >= 0:
            v = bound
        p = refit(key, v, p_in)
        c = chi2(p)
        pts.append((v, c, p))
        if not c - least(pts) <= lev():  # a failed refit's NaN χ² counts as outside
            out, c_out = v, c
            break
        inside, p_in, c_in = v, p, c
        if v == bound:
            return None
        h *= 2.0
    if out is None:
        return None
    for k in range(BISECT_MAX):
        if k >= BISECT and abs(out - inside) * 2**RESOLVE <= abs(inside - v0):
            break
        v = 0.5 * (inside + out)
        p = refit(key, v, p_in)
        c = chi2(p)
        pts.append((v, c, p))
        if not c - least(pts) <= lev():
            out, c_out = v, c
        else:
            inside, p_in, c_in = v, p, c
    return inside, c_in, out, c_out


def refine_minimum(key: str, est: dict[str, float], bounds: tuple[float, float], step: float, chi2: Chi2,
                   refit: Refit, pts: list[tuple[float, float, dict[str, float]]]
                   ) -> tuple[dict[str, float], float]:
    """The parameters at the least χ²_p within ``step`` of ``est[key]``, and that χ²: a bounded Brent search of
    χ²_p(v) on [est − step, est + step] ∩ ``bounds`` (at most :data:`REFINE` refits, to 2^−RESOLVE of ``step``);
    ``est`` and its χ² when no point is lower.

    A fit's search can stop short of the least χ² along one parameter where χ² is not smooth (the switch of a play
    or a friction moves across samples), and every profile edge is read against the least χ²: a χ²_min too high
    by δ widens the interval as a level too high by δ does.  The points are appended to ``pts``, whose first
    point is ``est``'s."""
    from scipy.optimize import minimize_scalar

    v0 = est[key]
    lo, hi = max(bounds[0], v0 - step), min(bounds[1], v0 + step)
    if not lo < hi:
        return est, pts[0][1]

    def f(v: float) -> float:
        q = refit(key, float(v), est)
        c = chi2(q)
        pts.append((float(v), c, q))
        return c if math.isfinite(c) else math.inf

    minimize_scalar(f, bounds=(lo, hi), method="bounded",
                    options={"maxiter": REFINE, "xatol": step * 2.0**-RESOLVE})
    best = min(pts, key=lambda q: q[1] if math.isfinite(q[1]) else math.inf)
    if math.isfinite(best[1]) and not best[1] >= pts[0][1]:  # a NaN at est: any finite χ² is lower
        return best[2], best[1]
    return est, pts[0][1]


def profile_interval(key: str, est: dict[str, float], bounds: tuple[float, float], step: float, chi2: Chi2,
                     refit: Refit, n: int, p: int) -> dict[str, Any]:
    """The 90 % profile interval of one parameter.

    Parameters
    ----------
    key : the parameter (``effect.param``)
    est : the fitted parameters (the scan starts from the least χ² found near them, :func:`refine_minimum`)
    bounds : the parameter's bounds [its unit]
    step : the first step [its unit] (> 0)
    chi2 : χ² of the training data at a parameter set
    refit : ``refit(key, value, start) -> parameters`` with ``key`` held at ``value``, the others fitted from ``start``
    n, p : the number of residuals and of fitted values (for s²)

    Returns
    -------
    dict
        ``ci90`` [lo, hi] ([nan, nan] when no refit gave a finite χ²), ``chi2_min`` (the least finite χ² seen),
        ``level`` (q₉₀·s² at it), ``refits``, ``to_bound``
        (the sides whose scan reached the parameter's bound inside the level), ``points`` (χ², parameters) of
        every point scanned.
    """
    pts: list[tuple[float, float, dict[str, float]]] = [(est[key], chi2(est), est)]
    lev = lambda: level(least(pts), n, p)  # noqa: E731
    span = bounds[1] - bounds[0]
    step = max(abs(step), 1e-4 * (span if math.isfinite(span) else max(abs(est[key]), 1e-12)))
    start, c0 = refine_minimum(key, est, bounds, step, chi2, refit, pts)
    brackets = [scan_side(key, start, b, step, chi2, refit, lev, pts, c0) for b in bounds if b != start[key]]
    cmin = least(pts)
    edges = [v for v, c, _ in pts if c - cmin <= lev()]
    edges += [v for v in (crossing(b, cmin, lev()) for b in brackets if b is not None) if v is not None]
    lo, hi = (min(edges), max(edges)) if edges else (math.nan, math.nan)  # no finite χ² anywhere: no interval
    return {"ci90": [float(lo), float(hi)], "chi2_min": float(cmin), "level": float(lev()), "refits": len(pts) - 1,
            "to_bound": [s for s, b, v in (("low", bounds[0], lo), ("high", bounds[1], hi)) if v == b],
            "points": [(float(c), q) for _, c, q in pts]}


def heterogeneous(percentile: Sequence[float], profiled: Sequence[float], units: int | None) -> bool:
    """Whether the training units vary more than the profile allows: the resamples' percentile interval is wider
    than the profile's by more than a spread read from ``units`` units scatters,

        width(percentile) > (1 + z₉₅ / √(2·(m − 1))) · width(profile),

    1/√(2(m − 1)) the relative standard deviation of a spread estimated from m units (that of a sample standard
    deviation), z₉₅ = 1.6449 (a one-sided 5 % test).  Without a count of units (None) or with fewer than 2, always
    True: nothing can show the units alike."""
    if units is None or units < 2:
        return True
    g = 1.0 + Z95 / math.sqrt(2.0 * (units - 1))
    return (percentile[1] - percentile[0]) > g * (profiled[1] - profiled[0])


def merge(resampled: dict[str, list[float]], profiled: dict[str, dict[str, Any]],
          percentile: dict[str, list[float]] | None = None, units: int | None = None,
          estimates: dict[str, float] | None = None, bounds: dict[str, tuple[float, float]] | None = None
          ) -> tuple[dict[str, list[float]], dict[str, bool]]:
    """The reported 90 % intervals from the resampling's (``resampled``: the percentile intervals, on the time route
    widened by the biases resampling cannot see; ``percentile``: those before widening, default ``resampled``) and
    the profile's (``profiled[k]["ci90"]``; one that is not finite, a profile with no finite χ², is left out), per
    parameter:

    * where the units are :func:`heterogeneous` (or ``units`` is None): the union of both, since the profile reads
      the units' scatter only as noise of the pooled residual;
    * else the profile's interval, widened on each side as far as the biases widened the resampling's (a widened
      edge stops at the parameter's ``bounds``), and holding the reported estimate (``estimates``; the profile is
      centred on the least χ² found, which can lie off the fit's own estimate): both measure the same spread, and
      the union of two intervals that each cover 90 % covers more.

    Either alone where the other has none.  Returns the intervals and, per parameter, whether the union was taken."""
    out = {k: list(v) for k, v in resampled.items()}
    union: dict[str, bool] = {}
    for k, pr in profiled.items():
        lo, hi = pr["ci90"]
        if not (math.isfinite(lo) and math.isfinite(hi)):
            continue
        if k not in out:
            out[k] = [lo, hi]
            continue
        r = out[k]
        pc = (percentile or {}).get(k, r)
        union[k] = heterogeneous(pc, [lo, hi], units)
        if union[k]:
            out[k] = [min(lo, r[0]), max(hi, r[1])]
            continue
        blo, bhi = (bounds or {}).get(k, (-math.inf, math.inf))
        lo, hi = min(lo, max(lo - max(0.0, pc[0] - r[0]), blo)), max(hi, min(hi + max(0.0, r[1] - pc[1]), bhi))
        e = (estimates or {}).get(k)
        out[k] = [min(lo, e), max(hi, e)] if e is not None and math.isfinite(e) else [lo, hi]
    return out, union


def project(points: Sequence[tuple[float, dict[str, float]]], keys: Sequence[str], n: int, p: int
            ) -> dict[str, list[float]]:
    """The 90 % intervals read from every point scanned in a candidate's profiles: per parameter the least and
    the largest value among the points whose χ² is within the level of the least χ² of all.

    The profile interval is the projection of the region χ² − χ²_min ≤ q₉₀·s² on the parameter's axis, so a point
    of another parameter's profile inside that region belongs to it too: a parameter whose own profile's refits
    cannot move a rough partner (a delay against a sharp friction) gets the width the partner's profile found."""
    cmin = min((c for c, _ in points if math.isfinite(c)), default=math.inf)
    if not math.isfinite(cmin):
        return {}
    lev = level(cmin, n, p)
    inside = [q for c, q in points if c - cmin <= lev]
    return {k: [float(min(q[k] for q in inside)), float(max(q[k] for q in inside))] for k in keys
            if all(k in q and math.isfinite(q[k]) for q in inside)}


def problem_hooks(prob: Any, cand: Any) -> dict[str, Any]:
    """What :func:`attach_profiles` needs for a candidate of a route's problem (harmonic or time): ``chi2(params)``
    (the problem's ``train_chi2``), ``refit(key, value, start)`` (its ``fit``: a polish with ``key`` held),
    ``bounds`` (``param_bounds``) and ``n``, ``p`` (residuals or independent cells, fitted values)."""
    names = list(cand.names)
    _, n, p = prob.train_chi2(names, cand.params)

    def chi2(q: dict[str, float]) -> float:
        return float(prob.train_chi2(names, q)[0])

    def refit_held(key: str, value: float, start: dict[str, float]) -> dict[str, float]:
        return dict(prob.fit(names, start=start, polish_only=True, fix={key: value}).params)

    return {"chi2": chi2, "refit": refit_held, "bounds": prob.param_bounds(names), "n": n, "p": p}


def _hull(a: list[float] | None, b: list[float]) -> list[float]:
    """The least interval holding both ``a`` (None: none) and ``b``."""
    return list(b) if a is None else [min(a[0], b[0]), max(a[1], b[1])]


def _steps(ci: dict[str, list[float]]) -> dict[str, float]:
    """First scan steps: the resampling intervals' half-widths [their units]."""
    return {k: 0.5 * (hi - lo) for k, (lo, hi) in ci.items() if math.isfinite(hi - lo)}


def attach_profiles(stab: dict[str, Any], steps: Sequence[Any], hooks_for: Callable[[Any], dict[str, Any]],
                    workers: int | None = None) -> None:
    """Profile every fitted parameter of every step of the chain and merge the intervals into a resampling's
    numbers: per step ``params_ci90_resampled`` (the percentile intervals), ``params_ci90_profile`` (with the scan's
    χ²_min, level and refits), ``params_ci90`` (the two merged, :func:`merge`, with ``stab["units"]`` training
    units, the step's estimates and its parameters' bounds) and ``units_heterogeneous`` (per parameter, whether the
    merge took the union); ``stab["profile"]`` says how.

    ``hooks_for(candidate)`` gives ``chi2``, ``refit``, ``bounds``, ``n``, ``p`` (:func:`problem_hooks`).  The
    parameters are profiled in parallel (:func:`chainid.infra.forkpool.fork_map`)."""
    hooks = [hooks_for(c) for c in steps]
    jobs = [(i, k) for i, c in enumerate(steps) for k in c.params if k in hooks[i]["bounds"]
            and math.isfinite(c.params[k])]

    def one(job: tuple[int, str]) -> dict[str, Any]:
        i, k = job
        h = hooks[i]
        st = _steps(stab["steps"][i]["params_ci90"]) if i < len(stab["steps"]) else {}
        return profile_interval(k, dict(steps[i].params), h["bounds"][k], st.get(k, 0.0), h["chi2"], h["refit"],
                                h["n"], h["p"])

    res = fork_map(one, jobs, workers, min_items=2)
    for i, row in enumerate(stab["steps"]):
        mine = [(k, r) for (j, k), r in zip(jobs, res) if j == i]
        row["params_ci90_resampled"] = dict(row["params_ci90"])
        pts = [pt for _, r in mine for pt in r.pop("points")]
        proj = project(pts, [k for k, _ in mine], hooks[i]["n"], hooks[i]["p"]) if pts else {}
        row["params_ci90_profile"] = {k: r | {"ci90": _hull(proj.get(k), r["ci90"])} for k, r in mine}
        row["params_ci90"], row["units_heterogeneous"] = merge(
            row["params_ci90_resampled"], row["params_ci90_profile"], row.get("params_ci90_percentile"),
            stab.get("units"), dict(steps[i].params), hooks[i]["bounds"])
    stab["profile"] = {"method": "profile likelihood: χ²_p(v) − χ²_min ≤ 2.7055·max(1, χ²_min/(n − p)), the others "
                                 "refitted; the reported interval is the union with the resampling's where the "
                                 "units are heterogeneous, else the profile's widened by the same biases (within "
                                 "the bounds) and holding the estimate",
                       "refits": int(sum(r["refits"] for r in res))}
