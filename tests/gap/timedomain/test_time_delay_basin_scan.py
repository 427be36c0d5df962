"""A delay added to a sharp friction on the time route reaches the basin of its optimum
(:func:`chainid.gap.core.delayscan.refine_delay`, called by ``TimeProblem.fit``).

Reference: the project grid's sweep case 101028, the paper's chain with friction (F_c = 137 N) behind an 8.23 ms
lag of the force channel.  The friction fitted alone mimics the lag with a stick travel just above the resolved
floor; adding the delay from there stopped at τ = 2.7 ms, χ² = 24 480.  The reference optimum is a brute-force
profile (the delay held on a 0.25 ms grid from 5 to 11 ms, everything else fitted afresh at each point): χ² ≈
14 900 near 8.2 ms.
"""
from __future__ import annotations

import numpy as np
import pytest

from chainid.gap.benchmark.nonharmonic import records, time_grid
from chainid.gap.timedomain.route import build_problem

NAMES = ["friction", "sensor_delay"]
TAU = "sensor_delay.tau"


@pytest.fixture(scope="module")
def problem():
    case = next(c for c in time_grid() if c["seed"] == 101028)
    recs, dev = records(case)
    assert case["truth"] == NAMES and case["excitation"] == "sweep"
    return build_problem(recs, [case["hold"]], 0, dev["nominal"]), dev["true_params"]


def test_a_delay_added_to_a_friction_fits_in_the_delays_basin(problem):
    prob, truth = problem
    alone = prob.fit(["friction"])
    c = prob.fit(NAMES, start=dict(alone.params))
    grid = np.arange(0.005, 0.011 + 1e-9, 0.00025)
    brute = [prob.train_chi2(NAMES, prob.fit(NAMES, fix={TAU: float(tau)}).params)[0] for tau in grid]
    k = int(np.argmin(brute))
    chi = prob.train_chi2(NAMES, c.params)[0]
    assert abs(c.params[TAU] - grid[k]) <= 0.0005, (c.params[TAU], grid[k])
    assert chi <= 1.01 * brute[k], (chi, brute[k])
    assert abs(grid[k] - truth[TAU]) <= 0.0005  # the data's optimum is the truth's basin
    assert c.params["friction.F_c"] == pytest.approx(truth["friction.F_c"], rel=0.03)


def test_a_polish_or_a_held_delay_is_not_scanned(problem):
    prob, _ = problem
    alone = prob.fit(["friction"])
    held = prob.fit(NAMES, start=dict(alone.params), fix={TAU: 0.003})
    assert held.params[TAU] == 0.003
    pol = prob.fit(NAMES, start=dict(alone.params) | {TAU: 0.003}, polish_only=True)
    assert abs(pol.params[TAU] - 0.003) < 0.002  # a polish stays near its start (no scan moved it to 8 ms)
