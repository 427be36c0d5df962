"""A delay's basin on the harmonic route: a scan of its profile around the fit.

A delay τ shifts every switch of a sharp friction, a play or a contact in time.  The data are samples, so the χ²
steps each time a switch crosses a sample: flat between, with no gradient for the polish to follow.  The fit's
start grid puts τ within half a grid spacing Δ = (τ_max − τ_min)/``DELAY_GRID`` of some point (1/40 of the shortest
period), but the polish from there stays on the plateau it starts on, and the other parameters adapt to the wrong
delay (a friction's stick travel grows to mimic a lag).  On nine tests of the paper's chain with friction and a
37.5 ms delay, the fit stopped at τ = 27.6 ms with χ² = 2120 against 422 at the truth's basin
(tests/gap/harmonic/test_delay_basin_scan.py).

So when a full fit adds a delay and leaves the training χ² above its noise (χ²/(n − p) > 1 + 5·√(2/(n − p)), the
same one-sided 5 sd test as the noise floor), the delay's profile is scanned around the fit: τ held at τ̂ ± k·Δ/4,
k = 1 … 4, the others polished from the start values the fit was given (the previous step's, before they adapted),
then ±k·Δ/16 around the best point; the free polish from the lowest point is kept when its χ² is lower.  Sixteen
polishes at most.

Units: s for τ; χ² dimensionless.
"""

from __future__ import annotations

import math
from typing import Any

from chainid.gap.core.fitgrid import DELAY_GRID

__all__ = ["COARSE", "FINE", "needs_scan", "refine_delay"]

#: points per side of the coarse pass (at Δ/4) and of the fine pass (at Δ/16)
COARSE = 4
FINE = 4


def needs_scan(chi2: float, n: int, p: int) -> bool:
    """Whether a fit's training χ² is above its noise: χ²/(n − p) > 1 + 5·√(2/(n − p))."""
    dof = n - p
    return dof > 0 and chi2 / dof > 1.0 + 5.0 * math.sqrt(2.0 / dof)


def _held(prob: Any, names: list[str], key: str, v: float, start: dict[str, float], fix: dict[str, float]
          ) -> tuple[float, dict[str, float]]:
    q = prob.fit(names, start=start, polish_only=True, fix=fix | {key: v}).params
    return prob.train_chi2(names, q)[0], dict(q)


def refine_delay(prob: Any, names: list[str], cand: Any, start: dict[str, float], fix: dict[str, float]) -> Any:
    """``cand`` or a better fit of ``names`` found by scanning a newly added delay's profile (module docstring).

    Parameters
    ----------
    prob : the harmonic problem (``fit``, ``train_chi2``, ``param_bounds``)
    names : the effect set
    cand : its full fit
    start, fix : the start values and the held parameters the fit was given
    """
    bounds = prob.param_bounds(names)
    keys = [k for k in bounds if k.endswith(".tau") and k not in start and k not in fix]
    if len(keys) != 1 or keys[0] not in cand.params:
        return cand
    key = keys[0]
    chi, n, p = prob.train_chi2(names, cand.params)
    if not needs_scan(chi, n, p):
        return cand
    lo, hi = bounds[key]
    step = (hi - lo) / DELAY_GRID / 4
    base = dict(start) or {k: v for k, v in cand.params.items() if k != key}
    best = (chi, dict(cand.params))
    for centre, h, m in ((cand.params[key], step, COARSE), (None, step / 4, FINE)):
        c0 = best[1][key] if centre is None else centre
        for k in (*range(-m, 0), *range(1, m + 1)):
            got = _held(prob, names, key, min(max(c0 + k * h, lo), hi), base, fix)
            if got[0] < best[0]:
                best = got
    if best[0] >= chi:
        return cand
    out = prob.fit(names, start=best[1], polish_only=True, fix=fix or None)
    return out if prob.train_chi2(names, out.params)[0] < chi else cand
