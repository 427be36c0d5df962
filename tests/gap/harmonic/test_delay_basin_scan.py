"""A delay added to a sharp friction on the harmonic route reaches the basin of its optimum.

Reference: friction F_c = 150 N and a 37.5 ms sensor delay on the paper's chain, nine tests at ω = 1, 2, 4 rad/s,
256 samples per cycle, force noise 20 N.  The brute-force optimum (the delay on a 0.25 ms grid, the others
polished at each point: tests/gap/harmonic/test_profile_interval_against_brute_force.py) has χ² ≈ 324 on 448
bin residuals; without the scan the fit stops at τ = 32.0 ms, χ² = 2299.
"""
from __future__ import annotations

import math

import pytest

import recovery_cases as rc
from chainid.gap.core.delayscan import needs_scan

NAMES = ["friction", "sensor_delay"]
TAU = "sensor_delay.tau"


@pytest.fixture(scope="module")
def fitted():
    return rc.chain_friction_delay_problem()


def test_a_friction_with_a_delay_fits_in_the_delays_basin(fitted):
    prob, c1 = fitted
    c = prob.fit(NAMES, start=c1.params)
    chi, n, p = prob.train_chi2(NAMES, c.params)
    assert abs(c.params[TAU] - 0.0375) < 0.002
    assert abs(c.params["friction.F_c"] - 150.0) < 3.0
    assert not needs_scan(chi, n, p)  # at the noise floor: 1 + 5·√(2/437) = 1.34 > χ²/(n − p) ≈ 0.74


def test_a_fit_without_a_delay_is_not_scanned(fitted):
    prob, c1 = fitted
    again = prob.fit(["friction"])
    assert again.params == pytest.approx(c1.params)


@pytest.mark.parametrize("dof, ratio, expected", [(200, 1.0, False), (200, 1.49, False), (200, 1.51, True),
                                                  (50, 1.99, False), (50, 2.01, True), (0, 5.0, False)])
def test_scan_only_above_the_noise_by_five_sd(dof, ratio, expected):
    # χ²/(n − p) > 1 + 5·√(2/(n − p)): 1.5 at 200 degrees of freedom, 2.0 at 50
    assert 1 + 5 * math.sqrt(2 / 200) == pytest.approx(1.5) and 1 + 5 * math.sqrt(2 / 50) == pytest.approx(2.0)
    assert needs_scan(ratio * max(dof, 1), dof + 3, 3) is expected
