"""The search over an effect set's shape parameters, with the amplitudes profiled out (variable projection).

For shape parameters θ (in the unit box of their fit bounds) the amplitudes are the bounded linear least-squares
fit, so the cost J(θ) — the weighted training sum of squares — depends on θ alone.  The search:

1. **Grid.**  The shape parameters of the effect being added start from a grid over their range (log-spaced for
   travels, velocities and compliances; a few values for an exponent, a shape ratio, a centre); a lag (``.tau``)
   from a uniform grid over its whole range at :data:`LAG_POINTS_PER_PERIOD` points per period of the band edge
   (a global search: a lag of a quarter period is found as surely as a small one).  Parameters of effects
   fitted before start where they were.  At most :data:`MAX_GRID` combinations (a regular sub-sample beyond).
2. **Polish.**  The best :data:`N_POLISH` grid points (the second when its cost is within ``POLISH_WITHIN`` of the
   best's) are polished by a bounded least-squares fit of the whitened
   residual over θ (``scipy.optimize.least_squares``, finite-difference Jacobian; the amplitudes re-solved at
   every θ); the lowest cost wins.

Units: those of the parameters (see :mod:`chainid.model.effects.library`).
"""

from __future__ import annotations

import itertools
import math
from typing import Callable, Sequence

import numpy as np
from scipy.optimize import least_squares

from chainid.model.effects import pinned

__all__ = ["grid_values", "lag_points", "search", "MAX_GRID", "N_POLISH", "LAG_POINTS_PER_PERIOD"]

#: most grid combinations evaluated for a new effect
MAX_GRID = 72
#: grid points polished (the second only when its cost is within ``POLISH_WITHIN`` of the best's)
N_POLISH = 2
POLISH_WITHIN = 1.5
#: lag grid density: points per period of the band edge
LAG_POINTS_PER_PERIOD = 16
#: most lag grid points
MAX_LAG_POINTS = 600

_LOG = ("x_s", "x_h", "x_y", "v_s", "b", "g", "c")
_FEW = {"n": (1.0, 2.0, 4.0), "r": (0.25, 0.75, 1.0), "p": (1.0, 1.5, 2.5), "beta": (0.45, 2.0 / 3.0, 0.9)}


def lag_points(lo: float, hi: float, f_band: float) -> int:
    """Points of a lag's start grid over [lo, hi] (in s): ``LAG_POINTS_PER_PERIOD`` per period of the band edge
    ``f_band`` [Hz], between 16 and ``MAX_LAG_POINTS``."""
    return int(min(MAX_LAG_POINTS, max(16, math.ceil((hi - lo) * f_band * LAG_POINTS_PER_PERIOD))))


def grid_values(key: str, lo: float, hi: float, f_band: float = 1.0) -> list[float]:
    """Grid values of one shape parameter ``effect.param`` over [lo, hi] (see the module docstring)."""
    par = key.split(".", 1)[1]
    if hi <= lo:
        return [lo]
    if par == "tau":
        return list(np.linspace(lo, hi, lag_points(lo, hi, f_band)))
    if par in _FEW:
        return [v for v in _FEW[par] if lo <= v <= hi] or [0.5 * (lo + hi)]
    if par == "scale":
        return [v for v in (0.5, 0.7, 1.0, 1.4, 2.0) if lo <= v <= hi]
    if par in _LOG:
        a = max(lo, hi * 1e-3)
        vals = list(np.geomspace(a, hi, 6))
        return ([lo] if lo == 0.0 else []) + vals
    return list(np.linspace(lo, hi, 7))


def search(keys: Sequence[tuple[str, float, float]], cost: Callable[[dict[str, float]], float],
           resid: Callable[[dict[str, float]], np.ndarray], start: dict[str, float], *, f_band: float = 1.0,
           polish_only: bool = False, max_nfev: int | None = None) -> tuple[dict[str, float], list[str]]:
    """The best shape parameters of an effect set and those pinned at a bound of their fit range.

    Parameters
    ----------
    keys : (``effect.param``, low, high) of every shape parameter
    cost : J(θ) — the profiled weighted training sum of squares at θ (a dict of the shape parameters)
    resid : the whitened training residual vector at θ (for the polish)
    start : values of parameters fitted before (warm start; not gridded)
    f_band : the largest band edge [Hz] of the records (the lag grid's density)
    polish_only : only a short polish from ``start`` (resampling, refits)
    """
    if not keys:
        return {}, []
    names = [k for k, _, _ in keys]
    lo = np.array([a for _, a, _ in keys])
    hi = np.array([b for _, _, b in keys])
    span = np.where(hi > lo, hi - lo, 1.0)

    def to_p(u: np.ndarray) -> dict[str, float]:
        return dict(zip(names, lo + np.clip(u, 0.0, 1.0) * (hi - lo)))

    def to_u(p: dict[str, float]) -> np.ndarray:
        return np.clip((np.array([p[k] for k in names]) - lo) / span, 0.0, 1.0)

    base = {k: float(start[k]) if k in start and math.isfinite(start[k]) else None for k in names}
    if polish_only:
        cands = [{k: (v if v is not None else 0.5 * (a + b)) for (k, a, b), v in zip(keys, base.values())}]
    else:
        cands = _grid(keys, base, f_band)
        costs = [cost(c) for c in cands]
        order = np.argsort(costs)
        new = [k for k in names if base[k] is None]
        if len(names) == 1 and len(new) == 1:  # one parameter: a bounded Brent search between the grid neighbours
            return _line(keys[0], [cands[i][names[0]] for i in order], cost)
        best_cost = costs[order[0]]
        cands = [cands[i] for i in order[:N_POLISH] if costs[i] <= POLISH_WITHIN * best_cost]
    best = None
    for c in cands:
        u0 = to_u(c)
        free = hi > lo
        if not np.any(free):
            r_cost = cost(c)
            if best is None or r_cost < best[1]:
                best = (c, r_cost)
            continue

        def fun(uf: np.ndarray) -> np.ndarray:
            u = u0.copy()
            u[free] = uf
            return resid(to_p(u))

        res = least_squares(fun, u0[free], bounds=(0.0, 1.0), diff_step=1e-3, x_scale=1.0,
                            max_nfev=max_nfev or (8 if polish_only else 10 + 6 * int(free.sum())))
        u = u0.copy()
        u[free] = res.x
        p = to_p(u)
        cp = float(2.0 * res.cost)
        if best is None or cp < best[1]:
            best = (p, cp)
    p = best[0]
    ub = to_u(p)
    at_bound = [k for k, v, a, b in zip(names, ub, lo, hi) if b > a and pinned(k, float(v), float(a))]
    return p, at_bound


def _line(key: tuple[str, float, float], ranked: list[float], cost: Callable[[dict[str, float]], float]
          ) -> tuple[dict[str, float], list[str]]:
    """One shape parameter: Brent's bounded minimisation of the cost between the grid neighbours of each of the
    ``N_POLISH`` best grid values (``ranked``: the grid values, best first), in log scale for a parameter gridded
    geometrically; the lowest cost wins."""
    from scipy.optimize import minimize_scalar

    name, lo, hi = key
    grid = sorted(set(ranked))
    logs = name.split(".", 1)[1] in _LOG and grid[0] >= 0
    fwd = (lambda v: math.log(v)) if logs else (lambda v: v)  # noqa: E731
    inv = (lambda w: math.exp(w)) if logs else (lambda w: w)  # noqa: E731
    best = (ranked[0], cost({name: ranked[0]}))
    pos = [g for g in grid if g > 0]
    for b in ranked[:N_POLISH]:
        if logs:  # neighbours among the positive grid values (a zero start searches below the first one)
            if not pos:
                continue
            j = pos.index(b) if b > 0 else -1
            a = pos[j - 1] if j > 0 else pos[0] * 1e-3
            c = pos[j + 1] if 0 <= j < len(pos) - 1 else (pos[0] if j < 0 else pos[-1])
        else:
            i = grid.index(b)
            a, c = grid[max(i - 1, 0)], grid[min(i + 1, len(grid) - 1)]
        if c <= a:
            continue
        r = minimize_scalar(lambda w: cost({name: float(inv(w))}), bounds=(fwd(a), fwd(c)), method="bounded",
                            options={"xatol": 1e-6 * (abs(fwd(c) - fwd(a)) + 1e-12), "maxiter": 40})
        if r.fun < best[1]:
            best = (float(inv(r.x)), float(r.fun))
    v = best[0]
    span = hi - lo if hi > lo else 1.0
    u = (v - lo) / span
    at = [name] if hi > lo and pinned(name, u, lo) else []
    return {name: v}, at


def _grid(keys: Sequence[tuple[str, float, float]], base: dict[str, float | None], f_band: float
          ) -> list[dict[str, float]]:
    """Grid combinations: the new parameters (no start) over their grids, the others at their starts."""
    axes = []
    for k, a, b in keys:
        axes.append([base[k]] if base[k] is not None else grid_values(k, a, b, f_band))
    combos = list(itertools.product(*axes))
    if len(combos) > MAX_GRID:
        step = len(combos) / MAX_GRID
        combos = [combos[int(i * step)] for i in range(MAX_GRID)]
    return [dict(zip([k for k, _, _ in keys], c)) for c in combos]
