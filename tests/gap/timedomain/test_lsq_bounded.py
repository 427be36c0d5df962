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




# ---------------------------------------------------------------- block statistics (Blocks, sse_at, solve_held)
def _blocks_by_hand(Phi, y, block, n_blocks, weight):
    """The statistics of each block summed sample by sample (numpy on the rows of the block, no sorting)."""
    G = np.array([weight * Phi[block == b].T @ Phi[block == b] for b in range(n_blocks)])
    h = np.array([weight * Phi[block == b].T @ y[block == b] for b in range(n_blocks)])
    s = np.array([weight * float(y[block == b] @ y[block == b]) for b in range(n_blocks)])
    return G, h, s, np.array([float(np.sum(block == b)) for b in range(n_blocks)])


@pytest.mark.parametrize("block", [[0, 0, 0, 1, 1, 2, 2, 2, 2], [2, 0, 1, 0, 2, 1, 0, 2, 2], [1, 0]])
def test_block_statistics_are_the_weighted_sums_over_each_blocks_samples(block):
    """G_b = wΦ_bᵀΦ_b, h_b = wΦ_bᵀy_b, s_b = w·y_bᵀy_b and the sample count, for blocks in order, interleaved, and two
    samples in reverse order (not contiguous: summed by block index, not by position), to 1e-12."""
    from chainid.gap.timedomain.lsq import Blocks

    block = np.array(block)
    rng = np.random.default_rng(1)
    Phi, y = rng.normal(size=(block.size, 2)), rng.normal(size=block.size)
    nb = int(block.max()) + 1
    bl = Blocks.from_columns(Phi, y, block, nb, 0.25)
    G, h, s, n = _blocks_by_hand(Phi, y, block, nb, 0.25)
    np.testing.assert_allclose(bl.G, G, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(bl.h, h, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(bl.s, s, rtol=1e-12, atol=1e-14)
    np.testing.assert_array_equal(bl.n, n)
    np.testing.assert_array_equal(bl.w, np.full(nb, 0.25))


def test_stacked_blocks_total_with_multiplicities():
    """Two records stacked (3 + 2 blocks, weights 1 and 4): ``total`` with counts m is Σ m_b·G_b, Σ m_b·h_b, here
    written out term by term; the stack keeps the records' order and weights."""
    from chainid.gap.timedomain.lsq import Blocks

    rng = np.random.default_rng(2)
    a = Blocks.from_columns(rng.normal(size=(6, 2)), rng.normal(size=6), np.array([0, 0, 1, 1, 2, 2]), 3, 1.0)
    b = Blocks.from_columns(rng.normal(size=(4, 2)), rng.normal(size=4), np.array([0, 0, 1, 1]), 2, 4.0)
    st = Blocks.stack([a, b])
    np.testing.assert_array_equal(st.w, [1.0, 1.0, 1.0, 4.0, 4.0])
    np.testing.assert_array_equal(st.G[3], b.G[0])
    m = np.array([2.0, 0.0, 1.0, 3.0, 0.0])
    G, h = st.total(m)
    np.testing.assert_allclose(G, 2 * a.G[0] + a.G[2] + 3 * b.G[0], rtol=1e-12)
    np.testing.assert_allclose(h, 2 * a.h[0] + a.h[2] + 3 * b.h[0], rtol=1e-12)


def test_sse_at_is_each_blocks_weighted_sum_of_squared_residuals():
    """s_b − 2aᵀh_b + aᵀG_b a is w·Σ(y − Φa)² over the block's samples (computed directly); a block that the
    amplitudes fit exactly has 0 (to rounding, not a floor above it)."""
    from chainid.gap.timedomain.lsq import Blocks, sse_at

    rng = np.random.default_rng(3)
    Phi = rng.normal(size=(8, 2))
    a = np.array([0.7, -1.3])
    y = Phi @ a
    y[4:] += rng.normal(size=4)  # block 1 is off the model, block 0 exact
    block = np.array([0, 0, 0, 0, 1, 1, 1, 1])
    got = sse_at(Blocks.from_columns(Phi, y, block, 2, 2.0), a)
    assert got[0] == pytest.approx(0.0, abs=1e-12)
    assert got[1] == pytest.approx(2.0 * float(np.sum((y[4:] - Phi[4:] @ a) ** 2)), rel=1e-10)


def test_solve_held_keeps_the_held_amplitude_and_fits_the_rest_conditionally():
    """G = [[2, 1], [1, 2]], h = (3, 0), a₀ held at 0.5: a₁ minimises 2a₁² + 2·a₀a₁ − 0 → a₁ = −a₀/2 = −0.25
    (the conditional normal equation (h₁ − G₁₀a₀)/G₁₁); without a held amplitude it is :func:`solve`."""
    from chainid.gap.timedomain.lsq import solve_held

    G, h = np.array([[2.0, 1.0], [1.0, 2.0]]), np.array([3.0, 0.0])
    lo, hi = np.full(2, -10.0), np.full(2, 10.0)
    np.testing.assert_allclose(solve_held(G, h, lo, hi, ["p.a", "p.b"], {"p.a": 0.5}), [0.5, -0.25], atol=1e-12)
    np.testing.assert_allclose(solve_held(G, h, lo, hi, ["p.a", "p.b"], {"p.b": 1.0}), [1.0, 1.0], atol=1e-12)
    np.testing.assert_allclose(solve_held(G, h, lo, hi, ["p.a", "p.b"]), np.linalg.solve(G, h), atol=1e-12)


def test_solve_leaves_an_empty_column_at_zero_and_splits_a_duplicated_one():
    """A column of zeros (zero diagonal: scaled by 1, not 0) leaves its amplitude at 0 while the others fit exactly;
    two identical columns for y = 2u get the minimum-norm split (1, 1); no amplitude at all gives an empty vector."""
    from chainid.gap.timedomain.lsq import solve

    u = np.linspace(-1.0, 1.0, 11)
    Phi = np.column_stack([u, np.zeros_like(u), u ** 2])
    y = 3.0 * u - 0.5 * u ** 2
    big = np.full(3, 1e9)
    np.testing.assert_allclose(solve(Phi.T @ Phi, Phi.T @ y, -big, big), [3.0, 0.0, -0.5], atol=1e-9)
    Phi2 = np.column_stack([u, u])
    np.testing.assert_allclose(solve(Phi2.T @ Phi2, Phi2.T @ (2.0 * u), -big[:2], big[:2]), [1.0, 1.0], atol=1e-9)
    assert solve(np.zeros((0, 0)), np.zeros(0), np.zeros(0), np.zeros(0)).shape == (0,)
