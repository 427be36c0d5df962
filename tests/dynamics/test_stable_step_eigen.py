"""The explicit stable step (chainid.dynamics.simulation.stable_step) against the true highest natural frequency:
the eigenvalues of the free nodes' M⁻¹K, built here from the segments' compliances and the node masses.  For the
undamped central-difference scheme the exact limit is dt = 2/ω_max; the step's Gershgorin bound must be safe
(dt·ω_max/2 <= 1) and not waste more than the bound's worst case (ω_max² >= the largest diagonal entry of M⁻¹K,
half the Gershgorin row sum: dt·ω_max/2 >= 1/√2).  Units mm, N, kg, s; K [N/mm]·1e3/M [kg] = 1/s²."""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.linalg import eigh

from chainid.dynamics import ChainLine, stable_step


def _tangent(c_lin: np.ndarray, c_h: np.ndarray, F: float | None) -> np.ndarray:
    """Segment tangent stiffness [N/mm]: 1/c_lin without a load; at F, 1/(dx/dF) of x = c_lin·F + c_h·F^(2/3) by a
    central difference (an independent route to the closed form)."""
    if F is None:
        return 1.0 / c_lin
    h = 1e-4 * F
    dx = (c_lin * (F + h) + c_h * (F + h) ** (2 / 3) - c_lin * (F - h) - c_h * (F - h) ** (2 / 3)) / (2 * h)
    return 1.0 / dx


def _omega_max(line: ChainLine, F: float | None) -> float:
    """√ of the largest generalised eigenvalue of K v = λ M v over the free nodes 1 … N (tensioner end: a grounded
    spring k_t at node N) or 1 … N−1 (fixed far end); node 0 is driven."""
    k = _tangent(*line.segment_coefficients(), F)
    m = line.node_masses()
    N = line.n_masses
    free = N if line.far_end == "tensioner" else N - 1
    K = np.zeros((free, free))
    for j in range(N):  # segment j joins node j and node j + 1
        for a in (j, j + 1):
            for b in (j, j + 1):
                if 1 <= a <= free and 1 <= b <= free:
                    K[a - 1, b - 1] += k[j] if a == b else -k[j]
    if line.far_end == "tensioner":
        K[-1, -1] += line.tensioner_stiffness
    lam = eigh(K * 1e3, np.diag(m[1:free + 1]), eigvals_only=True)
    return math.sqrt(lam.max())


CASES = [
    ("uniform, tensioner end", dict(n_links=100, n_masses=10), None),
    ("uneven segments (47 links on 5 masses)", dict(n_links=47, n_masses=5), None),
    ("fixed far end", dict(n_links=60, n_masses=12, far_end="fixed"), None),
    ("tensioner spring, tangent at 5 kN", dict(n_links=40, n_masses=8, tensioner_stiffness=80_000.0), 5_000.0),
    ("two masses, tangent at 20 kN", dict(n_links=4, n_masses=2), 20_000.0),
]


@pytest.mark.parametrize("what, kw, F", CASES, ids=[c[0] for c in CASES])
def test_the_stable_step_is_safe_and_within_root_two_of_the_true_limit(what, kw, F):
    line = ChainLine(pretension_N=1_000.0, **kw)
    ratio = stable_step(line, F) * _omega_max(line, F) / 2.0
    assert 1 / math.sqrt(2) - 1e-9 <= ratio <= 1.0 + 1e-12, (what, ratio)


def test_on_a_long_uniform_chain_the_bound_is_nearly_the_true_limit():
    """200 equal masses with a free far end: ω_max → 2√(1e3·k/m) as N grows (the chain's cut-off frequency), which
    the Gershgorin bound equals; the true limit is within 0.1 % of the step."""
    line = ChainLine(n_links=400, n_masses=200, pretension_N=1_000.0)
    ratio = stable_step(line) * _omega_max(line, None) / 2.0
    assert ratio == pytest.approx(1.0, abs=1e-3) and ratio <= 1.0


def test_the_dead_bands_tangent_at_a_force_is_the_derivative_where_it_carries_that_force():
    """The stable step's dead-band term: where the band carries F = k_d·pen^p, its tangent is dF/dpen; by a central
    difference of the force at pen = (F/k_d)^(1/p) (segment values, n_ref = 16 links against 8-link segments:
    k_d·2^p), for p = 1.5 and 3, F = 2 kN."""
    from chainid.dynamics.line_tables import deadband_stiffness

    F = 2_000.0
    for p in (1.5, 3.0):
        line = ChainLine(n_links=16, n_masses=2, pretension_N=1_000.0, deadband=(400.0, 0.05, p, 0.0),
                         damping_ref_links=16)
        kd_seg = 400.0 * 2.0**p  # the specimen's 16 links over a segment of 8
        pen = (F / kd_seg) ** (1.0 / p)
        h = 1e-6 * pen
        want = (kd_seg * (pen + h) ** p - kd_seg * (pen - h) ** p) / (2 * h)
        np.testing.assert_allclose(deadband_stiffness(line, F), want, rtol=1e-7)
