"""The time route's dashpot law over record features is passive on every record, and is the best passive law.

Independent references: the corners of the feature box evaluated directly (a linear law's least value on a box is
at a corner), a non-negative least squares (scipy's ``nnls``) for the claim that every passive law has passive
coordinates, and a brute-force active-set search over the four corner inequalities for the constrained optimum.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import nnls

from chainid.gap.timedomain.design import MIN_FEATURE_SPAN, law_features
from chainid.gap.timedomain.lsq import solve, solve_held
from chainid.gap.timedomain.passivity import LAW_AMPS, corner_minimum, law_map, lifted, passive_solve

BOX = {"w_lo": 6.0, "w_hi": 30.0, "A_lo": 0.4, "A_hi": 2.5}
REFS = {"w_ref": 14.0, "A_ref": 1.1}
AMPS = ["spring.k", *LAW_AMPS, "friction.F_c"]
LO = np.array([0.0, 0.0, -np.inf, -np.inf, 0.0])
HI = np.full(5, np.inf)


def _corners(a: np.ndarray) -> np.ndarray:
    c, bw, bA = a[1:4]
    return np.array([c + bw * (w - REFS["w_ref"]) + bA * (A - REFS["A_ref"])
                     for w in (BOX["w_lo"], BOX["w_hi"]) for A in (BOX["A_lo"], BOX["A_hi"])])


def test_every_passive_coordinate_gives_a_law_passive_at_the_box_corners() -> None:
    L, zlo, _ = law_map(AMPS, LO, HI, REFS, BOX)
    rng = np.random.default_rng(3)
    for _ in range(200):
        z = np.where(np.isfinite(zlo), 0.0, -5.0) + rng.exponential(2.0, L.shape[1])
        a = L @ z
        assert _corners(a).min() >= -1e-12 * np.abs(a).max()
        assert corner_minimum(*a[1:4], REFS, BOX) == pytest.approx(_corners(a).min(), abs=1e-12)


def test_every_law_passive_on_the_box_has_passive_coordinates() -> None:
    L, _, _ = law_map(AMPS, LO, HI, REFS, BOX)
    rng = np.random.default_rng(4)
    Llaw = L[1:4][:, 2:]  # the law's rows on its four coordinates
    found = 0
    for _ in range(400):
        a = np.array([0.0, rng.uniform(0, 5), rng.normal(0, 0.3), rng.normal(0, 3.0), 0.0])
        if _corners(a).min() < 0:
            continue
        found += 1
        z, resid = nnls(Llaw, a[1:4])
        assert resid <= 1e-9 * np.linalg.norm(a[1:4])
    assert found > 50


def test_a_feature_shared_by_every_record_has_no_slope() -> None:
    box = BOX | {"A_hi": BOX["A_lo"]}
    L, zlo, _ = law_map(AMPS, LO, HI, REFS, box)
    assert L.shape[1] == 2 + 2  # spring and friction, then one feature's two shares
    assert np.all(L[AMPS.index("damping_law.b_A")] == 0.0)
    L0, _, _ = law_map(AMPS, LO, HI, REFS, box | {"w_hi": BOX["w_lo"]})
    assert L0.shape[1] == 2 + 1 and np.all(L0[1:4, 2:] == [[1.0], [0.0], [0.0]])


def test_the_passive_fit_is_the_constrained_least_squares_optimum() -> None:
    """Columns of a spring, a dashpot with its law and a friction, fitted to a truth whose damping falls steeply with
    amplitude (negative at the large-amplitude corners, :func:`_friction_problem`): the unconstrained solve is not
    passive, the bounded solve on the passive coordinates is, and it reaches the brute-force optimum over the
    corner inequalities."""
    G, h = _friction_problem(5)
    free = solve(G, h, LO, HI)
    assert _corners(free).min() < 0
    L, zlo, zhi = law_map(AMPS, LO, HI, REFS, BOX)
    a = L @ solve(L.T @ G @ L, L.T @ h, zlo, zhi)
    assert _corners(a).min() >= -1e-9

    def f(x):
        return float(x @ G @ x - 2 * h @ x)

    assert f(a) == pytest.approx(_active_set_optimum(G, h, f), rel=1e-9)
    assert a[4] > 1.0  # the friction stays in the fit


def _active_set_optimum(G: np.ndarray, h: np.ndarray, f, held: dict[int, float] | None = None) -> float:
    """The least f over the passive laws by brute force: every subset of the four corner inequalities and the two
    bounds (spring, friction >= 0) held as equalities (the KKT system of that equality-constrained least squares),
    the feasible solutions compared; ``held``: amplitudes (by index) held at a value, always equalities."""
    C = np.array([[0.0, 1.0, w - REFS["w_ref"], A - REFS["A_ref"], 0.0]
                  for w in (BOX["w_lo"], BOX["w_hi"]) for A in (BOX["A_lo"], BOX["A_hi"])]
                 + [[1.0, 0, 0, 0, 0], [0, 0, 0, 0, 1.0]])
    Eq = np.array([np.eye(5)[i] for i in (held or {})]).reshape(-1, 5)
    eq = np.array(list((held or {}).values()), float)
    best = np.inf
    for mask in range(64):
        S = np.vstack([C[[i for i in range(6) if mask >> i & 1]], Eq])
        rhs = np.concatenate([np.zeros(len(S) - len(eq)), eq])
        K = np.block([[2 * G, S.T], [S, np.zeros((len(S), len(S)))]])
        sol = np.linalg.lstsq(K, np.concatenate([2 * h, rhs]), rcond=None)[0]
        x = sol[:5]
        if np.all(C @ x >= -1e-9) and np.allclose(Eq @ x, eq, rtol=1e-9, atol=1e-12):
            best = min(best, f(x))
    return best


def _friction_problem(seed: int) -> tuple[np.ndarray, np.ndarray]:
    """The Gram matrix and projection of a least-squares problem on the box: 400 samples of a spring, a dashpot
    with its slopes over ω and A, and a friction; the truth's damping 0.8 − 1.2·(A − A_ref) is negative at the
    large-amplitude corners, its friction 8."""
    rng = np.random.default_rng(seed)
    n = 400
    w = rng.uniform(BOX["w_lo"], BOX["w_hi"], n)
    A = rng.uniform(BOX["A_lo"], BOX["A_hi"], n)
    w[:2], A[:2] = (BOX["w_lo"], BOX["w_hi"]), (BOX["A_lo"], BOX["A_hi"])
    xd = rng.normal(0, 10.0, n)
    Phi = np.column_stack([rng.normal(0, 1, n), xd, (w - REFS["w_ref"]) * xd, (A - REFS["A_ref"]) * xd,
                           np.sign(xd)])
    y = Phi @ np.array([3.0, 0.8, 0.0, -1.2, 8.0]) + rng.normal(0, 0.5, n)
    return Phi.T @ Phi, Phi.T @ y


def test_a_held_law_amplitude_keeps_its_value_and_the_rest_is_the_passive_optimum() -> None:
    """A profile's point holds b_A steeper than the fit's: the refit keeps it exactly, stays passive, and reaches the
    brute-force optimum with b_A held (to the weighting method's 1e-6)."""
    G, h = _friction_problem(6)
    for b_A in (-0.9, -1.5):
        fix = {"damping_law.b_A": b_A}
        a = passive_solve(G, h, LO, HI, AMPS, REFS, BOX, solve_held(G, h, LO, HI, AMPS, fix), fix)
        assert a[3] == b_A
        assert corner_minimum(*a[1:4], REFS, BOX) >= 0.0

        def f(x):
            return float(x @ G @ x - 2 * h @ x)

        assert f(a) == pytest.approx(_active_set_optimum(G, h, f, {3: b_A}), rel=1e-6)


def test_a_law_on_the_passive_boundary_is_not_negative_by_round_off() -> None:
    """Twenty problems whose best passive law touches zero at a corner: its least corner value is >= 0 exactly (a
    negative dashpot by 1e-15 is refused downstream)."""
    touched = 0
    for seed in range(20):
        G, h = _friction_problem(100 + seed)
        a = passive_solve(G, h, LO, HI, AMPS, REFS, BOX, solve_held(G, h, LO, HI, AMPS))
        m = corner_minimum(*a[1:4], REFS, BOX)
        assert m >= 0.0
        touched += m <= 1e-9 * a[1]
    assert touched == 20


@pytest.mark.parametrize("omegas, amps, feats", [
    ([10.0, 10.001, 9.999, 10.0005], [2.0005, 2.0004, 2.0, 2.0002], ()),   # repeats of one test: no law
    ([5.0, 10.0, 20.0], [1.0, 1.0001, 1.0002], ("w",)),                    # one amplitude, three bands
    ([10.0, 10.0, 10.0], [0.5, 1.0, 2.0], ("A",)),
    ([5.0, 10.0, 20.0], [0.5, 1.0, 2.0], ("w", "A")),
    ([10.0, 10.0 * (1 - MIN_FEATURE_SPAN) - 1e-9], [1.0, 1.0 * (1 - MIN_FEATURE_SPAN) + 1e-9], ("w",)),
])
def test_a_feature_carries_a_slope_only_where_the_records_spread_it(omegas, amps, feats) -> None:
    assert law_features(omegas, amps) == feats


def test_repeats_of_one_motion_give_the_base_one_dashpot() -> None:
    """Five records of one random motion (the noise alone differs): no feature spreads, so the base keeps one c (a
    law over a 1e-6 spread would be one c per record, extrapolated without bound)."""
    import warnings

    import sim_devices as sd
    from chainid.gap.timedomain.route import build_problem

    t = sd.sample_times(2000, 200.0)
    x, xd, _ = sd.random_motions(1, 2000, 200.0, 0.5, 4.0, 1.0, 0.0, 7)[0](t)
    recs = [sd.noisy(f"r{i}", t, x, 10.0 * x + 2.0 * xd, 1e-6, 0.1, i) for i in range(5)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        prob = build_problem(recs, ["r4"], 0, None, None)
    assert prob.base.law_features == () and not prob.base.law and prob.law == "viscous"
    assert "damping_law" not in prob.applicable()


def test_the_lift_off_the_passive_boundary_leaves_no_negative_corner_by_round_off() -> None:
    """Random negative laws lifted by :func:`lifted`: every corner value as computed is >= 0, and the lift is the
    exact shortfall (rational arithmetic on the same floats) to the sum's round-off.  Subtracting the computed
    shortfall once leaves a corner below 0 on many of them (counted: the check is not vacuous)."""
    from fractions import Fraction

    rng = np.random.default_rng(11)
    once_short = 0
    for _ in range(400):
        box = {"w_lo": rng.uniform(1, 10), "A_lo": rng.uniform(0.1, 1)}
        box |= {"w_hi": box["w_lo"] * rng.uniform(1.1, 5), "A_hi": box["A_lo"] * rng.uniform(1.1, 5)}
        refs = {"w_ref": rng.uniform(box["w_lo"], box["w_hi"]), "A_ref": rng.uniform(box["A_lo"], box["A_hi"])}
        c, b_w, b_A = (float(rng.normal() * 10 ** rng.uniform(-3, 3)) for _ in range(3))
        exact = min(Fraction(c) + Fraction(b_w) * (Fraction(w) - Fraction(refs["w_ref"]))
                    + Fraction(b_A) * (Fraction(A) - Fraction(refs["A_ref"]))
                    for w in (box["w_lo"], box["w_hi"]) for A in (box["A_lo"], box["A_hi"]))
        if exact >= 0:
            continue
        once_short += corner_minimum(c - corner_minimum(c, b_w, b_A, refs, box), b_w, b_A, refs, box) < 0.0
        got = lifted(c, b_w, b_A, refs, box)
        assert corner_minimum(got, b_w, b_A, refs, box) >= 0.0
        scale = abs(c) + abs(b_w) * (box["w_hi"] - box["w_lo"]) + abs(b_A) * (box["A_hi"] - box["A_lo"])
        assert abs(float(Fraction(got) - Fraction(c) + exact)) <= 16 * np.finfo(float).eps * scale
    assert once_short >= 20
