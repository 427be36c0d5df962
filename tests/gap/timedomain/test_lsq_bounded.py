"""The bounded amplitude fit of the time-domain route (:func:`chainid.gap.timedomain.lsq.solve`).

The bounded minimiser of aᵀGa − 2hᵀa (the same point as ½aᵀGa − hᵀa) is checked against an exact enumeration of the
active sets, and differs from the clipped solution when two amplitudes trade off (a dashpot against a friction force
that mimics it); the leave-one-block-out and resampled fits are this solve on sums of block Gram matrices.
"""
from __future__ import annotations

import itertools

import numpy as np
import pytest

from chainid.gap.timedomain.lsq import solve as leave_out_step


def _enumerate_active_sets(A, g, lo, hi):
    """Exact box-constrained minimiser of ½dᵀAd − gᵀd by enumeration: every coordinate at its lower bound, its
    upper bound or free (the free ones solve the reduced normal equations); the best feasible point."""
    n = g.size
    best, best_f = None, np.inf
    for combo in itertools.product((0, 1, 2), repeat=n):
        d = np.zeros(n)
        fixed = np.array([c != 2 for c in combo])
        if any(c == 0 and not np.isfinite(lo[i]) or c == 1 and not np.isfinite(hi[i]) for i, c in enumerate(combo)):
            continue
        d[fixed] = [lo[i] if combo[i] == 0 else hi[i] for i in np.flatnonzero(fixed)]
        fr = ~fixed
        if fr.any():
            d[fr] = np.linalg.solve(A[np.ix_(fr, fr)], g[fr] - A[np.ix_(fr, fixed)] @ d[fixed])
        if np.all(d >= lo - 1e-12) and np.all(d <= hi + 1e-12):
            val = 0.5 * d @ A @ d - g @ d
            if val < best_f:
                best, best_f = d, val
    return best


def _quadratic(A, g):
    return lambda d: 0.5 * d @ A @ d - g @ d, lambda d: A @ d - g


@pytest.mark.parametrize("seed", range(6))
def test_bounded_step_is_the_box_minimiser(seed):
    rng = np.random.default_rng(seed)
    n = 4
    J = rng.normal(size=(50, n))
    # a strongly coupled pair (0, 3): the lag acts as a negative dashpot
    J[:, 3] = -J[:, 0] + 0.1 * rng.normal(size=50)
    A = J.T @ J
    d_free = rng.normal(size=n) * 2.0
    g = A @ d_free
    lo, hi = -np.full(n, 0.5), np.full(n, 0.5)
    lo[-1] = -np.inf  # the dashpot has no upper bound on c (θ − Δ, c >= 0 gives only Δ <= c)
    got = leave_out_step(A, g, lo, hi)
    f, _ = _quadratic(A, g)
    ref = _enumerate_active_sets(A, g, lo, hi)
    assert np.all(got >= lo - 1e-9) and np.all(got <= hi + 1e-9)
    assert f(got) == pytest.approx(f(ref), rel=1e-9, abs=1e-12)
    assert np.allclose(got, ref, atol=1e-6)


def test_inside_the_box_the_step_is_the_newton_step():
    A = np.array([[4.0, 1.0], [1.0, 3.0]])
    g = np.array([0.1, -0.2])
    assert np.allclose(leave_out_step(A, g, -np.ones(2), np.ones(2)), np.linalg.solve(A, g), atol=1e-12)


def test_clipping_a_coupled_pair_is_not_the_refit():
    # τ (unit box) and c trade off: A nearly singular along (1, 1); the free step leaves the box in τ only
    A = np.array([[1.0, 0.999], [0.999, 1.0]])
    g = A @ np.array([0.8, -0.7])
    lo, hi = np.array([-0.2, -np.inf]), np.array([0.2, np.inf])
    got = leave_out_step(A, g, lo, hi)
    f, _ = _quadratic(A, g)
    clipped = np.clip(np.linalg.solve(A, g), lo, hi)
    assert got[0] == pytest.approx(0.2, abs=1e-9)
    # with τ at its bound the dashpot moves to the conditional optimum c = (g₁ − A₁₀·τ)/A₁₁
    assert got[1] == pytest.approx((g[1] - A[1, 0] * 0.2) / A[1, 1], rel=1e-6)
    assert f(got) < f(clipped) - 1e-3


def test_leave_out_step_box_constrained_quadratic_by_hand():
    """``solve`` minimises ½ΔᵀAΔ − gᵀΔ in lo <= Δ <= hi.  A = [[2, 1], [1, 2]]: g = (0.3, 0) gives the free
    minimum A⁻¹g = (0.2, −0.1) inside the box; g = (3, 0) gives (2, −1) outside the box ±0.5, where the KKT point is
    Δ1 = 0.5 (gradient 2Δ1 + Δ2 − 3 = −2.25 < 0 pushes it up) and Δ2 = −Δ1/2 = −0.25 (not the clipped (0.5, −0.5));
    a matrix with no positive curvature (A = −I) gives no step."""
    from chainid.gap.timedomain.lsq import solve as leave_out_step

    A = np.array([[2.0, 1.0], [1.0, 2.0]])
    lo, hi = np.full(2, -0.5), np.full(2, 0.5)
    np.testing.assert_allclose(leave_out_step(A, np.array([0.3, 0.0]), lo, hi), [0.2, -0.1], atol=1e-12)
    np.testing.assert_allclose(leave_out_step(A, np.array([3.0, 0.0]), lo, hi), [0.5, -0.25], atol=1e-9)
    np.testing.assert_allclose(leave_out_step(A, np.array([0.0, -3.0]), lo, hi), [0.25, -0.5], atol=1e-9)
    np.testing.assert_array_equal(leave_out_step(-np.eye(2), np.array([1.0, 0.0]), lo, hi), [0.0, 0.0])


