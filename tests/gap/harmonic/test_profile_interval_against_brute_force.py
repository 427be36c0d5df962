"""The harmonic route's profile-likelihood interval of a sensor delay against a sharp friction, checked against a
brute-force profile: the delay on a 0.25 ms grid (1/25 of the fastest test's sample interval), every other
parameter polished at each point from two starts (the friction fitted alone, and the grid neighbour's optimum), the
lower kept.  With friction's switch between samples the χ² steps in the delay, so a polish from the full fit cannot
move it, and the resampling's percentile interval alone is far too narrow."""
from __future__ import annotations

import numpy as np
import pytest

import recovery_cases as rc
from chainid.gap.core.profile import level, problem_hooks, profile_interval

NAMES = ["friction", "sensor_delay"]
TAU = "sensor_delay.tau"


@pytest.fixture(scope="module")
def fitted():
    return rc.chain_friction_delay_problem()


def brute_force(prob, c1, grid):
    """χ² at every delay of ``grid``, the others polished from c1 and from the previous point; the best point."""
    chi, best, prev = [], None, None
    for v in grid:
        tries = [prob.fit(NAMES, start=dict(c1.params), polish_only=True, fix={TAU: float(v)}).params]
        if prev is not None:
            tries.append(prob.fit(NAMES, start=prev, polish_only=True, fix={TAU: float(v)}).params)
        prev = min(tries, key=lambda q: prob.train_chi2(NAMES, q)[0])
        chi.append(prob.train_chi2(NAMES, prev)[0])
        if best is None or chi[-1] < prob.train_chi2(NAMES, best)[0]:
            best = dict(prev)
    return np.array(chi), best


def test_fix_holds_the_parameter_and_refits_the_others(fitted):
    prob, c1 = fitted
    c = prob.fit(NAMES, start=c1.params)
    v = c.params[TAU] * 1.02
    held = prob.fit(NAMES, start=c.params, polish_only=True, fix={TAU: v}).params
    assert held[TAU] == v
    assert prob.train_chi2(NAMES, held)[0] <= prob.train_chi2(NAMES, dict(c.params) | {TAU: v})[0] + 1e-9


def test_fix_of_a_parameter_that_is_not_fitted_is_refused(fitted):
    prob, c1 = fitted
    with pytest.raises(ValueError, match=r"fix: \['sensor_delay.nope'\] are not fitted parameters"):
        prob.fit(NAMES, start=c1.params, polish_only=True, fix={"sensor_delay.nope": 1.0})


def test_delay_interval_matches_the_brute_force_profile(fitted):
    prob, c1 = fitted
    grid = np.linspace(0.0375 - 0.006, 0.0375 + 0.006, 49)  # 0.25 ms: the ω = 4 rad/s tests are sampled every 6.1 ms
    chi, best = brute_force(prob, c1, grid)
    cand = prob.fit(NAMES, start=best, polish_only=True)
    h = problem_hooks(prob, cand)
    ours = profile_interval(TAU, dict(cand.params), h["bounds"][TAU], 1e-5, h["chi2"], h["refit"], h["n"], h["p"])
    cmin = min(chi.min(), ours["chi2_min"])
    inside = grid[chi - cmin <= level(cmin, h["n"], h["p"])]
    assert inside.size >= 3 and grid[0] < inside.min() and inside.max() < grid[-1]  # the grid spans the interval
    step = grid[1] - grid[0]
    lo, hi = ours["ci90"]
    assert abs(lo - inside.min()) <= step and abs(hi - inside.max()) <= step
    assert hi - lo >= 2 * step  # not the resampling's width of a plateau
    assert lo <= 0.0375 <= hi
