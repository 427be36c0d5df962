"""A delay's basin: a scan of its profile around the fit, for both routes.

A delay τ shifts every switch of a sharp friction, a play or a contact in time.  The data are samples, so the χ²
steps each time a switch crosses a sample: flat between, with no gradient for the polish to follow.  A route's
start grid puts τ within half a grid spacing Δ of some point (the harmonic route: Δ = (τ_max − τ_min)/``DELAY_GRID``,
1/40 of the shortest period; the time route: 1/16 of the band edge's period), but the polish from there stays on
the plateau it starts on, and the other parameters adapt to the wrong delay (a friction's stick travel grows, a
dashpot vanishes, to mimic a lag).

- Harmonic: nine tests of the paper's chain with friction and a 37.5 ms delay; the fit stops at τ = 32.0 ms with
  χ² = 2299 against 324 at the truth's basin (tests/gap/harmonic/test_delay_basin_scan.py).
- Time: a sweep of the paper's chain with friction and an 8.2 ms delay; the delay added to the friction stopped at
  τ = 2.7 ms with χ² = 24 480 against 14 893 at the truth's basin (tests/gap/timedomain/test_time_delay_basin_scan.py).

So when a full fit adds a delay and leaves the training χ² above its noise (χ²/(n − p) > 1 + 5·√(2/(n − p)), the
same one-sided 5 sd test as the noise floor), the delay's profile is scanned around the fit: τ held at τ̂ ± k·Δ/4,
k = 1 … 4, the others polished from the start values the fit was given (the previous step's, before they adapted),
then ±k·Δ/16 around the best point; the free polish from the lowest point is kept when its χ² is lower.  Sixteen
held points at most.  The time route also searches the other shape parameters afresh at each coarse point (a
friction that mimicked the lag had its stick travel just above the resolved floor, where the form is
discontinuous: the polish cannot cross to the pure Coulomb friction the delay's basin needs), and its fine pass
polishes from the best coarse point's fit.

Units: s for τ; χ² dimensionless.
"""

from __future__ import annotations

import math
from typing import Any, Callable

__all__ = ["COARSE", "FINE", "needs_scan", "refine_delay"]

#: points per side of the coarse pass (at Δ/4) and of the fine pass (at Δ/16)
COARSE = 4
FINE = 4


def needs_scan(chi2: float, n: int, p: int) -> bool:
    """Whether a fit's training χ² is above its noise: χ²/(n − p) > 1 + 5·√(2/(n − p))."""
    dof = n - p
    return dof > 0 and chi2 / dof > 1.0 + 5.0 * math.sqrt(2.0 / dof)


def _held(prob: Any, names: list[str], key: str, v: float, start: dict[str, float], fix: dict[str, float],
          regrid: bool) -> tuple[float, dict[str, float]]:
    """The best fit with the delay held at v: the polish from ``start``, or with ``regrid`` the better of it and a
    fresh search of the other shape parameters."""
    held = fix | {key: v}
    fits = [prob.fit(names, start=start, polish_only=True, fix=held).params]
    if regrid:
        fits.append(prob.fit(names, fix=held).params)
    return min(((prob.train_chi2(names, q)[0], dict(q)) for q in fits), key=lambda r: r[0])


def refine_delay(prob: Any, names: list[str], cand: Any, start: dict[str, float], fix: dict[str, float],
                 grid_step: Callable[[float, float], float], regrid: bool = False) -> Any:
    """``cand`` or a better fit of ``names`` found by scanning a newly added delay's profile (module docstring).

    Parameters
    ----------
    prob : a route's problem (``fit`` with ``polish_only`` and ``fix``, ``train_chi2``, ``param_bounds``)
    names : the effect set
    cand : its full fit
    start, fix : the start values and the held parameters the fit was given
    grid_step : the route's start-grid spacing Δ [s] of a delay fitted over (lo, hi) [s]
    regrid : each coarse point also searches the other shape parameters afresh (their start values adapted to the
        missing delay may sit across a discontinuity of the form from their basin: a friction's stick travel just
        above the resolved floor, where the Jenkins element switches on every wiggle of x̂); the fine pass then
        polishes from the best coarse point's fit
    """
    bounds = prob.param_bounds(names)
    keys = [k for k in bounds if k.endswith(".tau") and k not in start and k not in fix]
    if len(keys) != 1 or keys[0] not in cand.params:
        return cand
    key = keys[0]
    lo, hi = bounds[key]
    step = grid_step(lo, hi) / 4
    if not step > 0:
        return cand
    chi, n, p = prob.train_chi2(names, cand.params)
    if not needs_scan(chi, n, p):
        return cand
    best = (chi, dict(cand.params))

    def scan(centre: float, h: float, m: int, frm: dict[str, float], fresh: bool) -> None:
        nonlocal best
        for k in (*range(-m, 0), *range(1, m + 1)):
            got = _held(prob, names, key, min(max(centre + k * h, lo), hi), frm, fix, fresh)
            if got[0] < best[0]:
                best = got

    base = dict(start) or {k: v for k, v in cand.params.items() if k != key}
    scan(cand.params[key], step, COARSE, base, regrid)
    fine_from = {k: v for k, v in best[1].items() if k != key} if regrid else base
    scan(best[1][key], step / 4, FINE, fine_from, False)
    if best[0] >= chi:
        return cand
    out = prob.fit(names, start=best[1], polish_only=True, fix=fix or None)
    return out if prob.train_chi2(names, out.params)[0] < chi else cand
