"""Causal state operators (chainid.model.operators) against closed forms: loop areas of the Jenkins, Dahl and Iwan
elements, the play output, sampling invariance, the Coulomb sign rule.  Units mm, N; energies N·mm."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.model import operators as ops
from chainid.model.operators import coulomb_sign


def cycles(A: float, n: int = 4, per: int = 2000, x0: float = 0.0) -> np.ndarray:
    """n triangle cycles of amplitude A starting at x0 = 0 going up (turning points sampled exactly)."""
    up = np.linspace(-A, A, per + 1)
    one = np.concatenate([up[per // 2:], up[::-1][1:], up[1:per // 2 + 1]])  # 0 → A → −A → 0
    return x0 + np.concatenate([one] + [one[1:]] * (n - 1))


def last_cycle_energy(dE: np.ndarray, per_cycle: int) -> float:
    return float(np.sum(dE[-per_cycle:]))


@pytest.mark.parametrize("A,x_s", [(1.0, 0.2), (2.5, 0.5), (0.8, 0.01)])
def test_jenkins_loop_area_is_4Fc_A_minus_xs(A, x_s):
    F_c = 120.0
    x = cycles(A)
    F, dE = ops.jenkins(x, F_c, x_s)
    per = 2 * 2000
    # closed form 4·F_c·(A − x_s), independent of the code: exact for a sampled triangle path
    assert last_cycle_energy(dE, per) == pytest.approx(4 * F_c * (A - x_s), rel=1e-12)
    # the loop area ∮F dx (trapezoid over the last cycle) agrees to the discretisation error
    xl, Fl = x[-per - 1:], F[-per - 1:]
    area = float(np.sum(0.5 * (Fl[1:] + Fl[:-1]) * np.diff(xl)))
    assert area == pytest.approx(4 * F_c * (A - x_s), rel=2e-3)
    assert np.max(F) == pytest.approx(F_c, rel=1e-12) and np.min(F) == pytest.approx(-F_c, rel=1e-12)


def test_jenkins_below_stick_travel_is_elastic_and_lossless():
    F, dE = ops.jenkins(cycles(0.1), 50.0, 0.2)
    assert np.sum(dE) == 0.0
    assert np.allclose(F, 50.0 / 0.2 * cycles(0.1), atol=1e-12)


@pytest.mark.parametrize("A,x_h", [(1.0, 0.3), (0.5, 1.0), (3.0, 0.05)])
def test_dahl_energy_per_cycle_closed_form(A, x_h):
    F_h = 80.0
    x = cycles(A, n=15)  # transient decays as e^{−4A/x_h} per cycle
    z, dE = ops.dahl(x, F_h, x_h)
    per = 2 * 2000
    W = 4 * F_h * (A - x_h * math.tanh(A / x_h))  # closed form of the steady loop
    assert last_cycle_energy(dE, per) == pytest.approx(W, rel=1e-6)
    assert np.all(dE >= -1e-12)
    # steady tip force F_h·tanh(A/x_h)
    assert np.max(z[-per:]) == pytest.approx(F_h * math.tanh(A / x_h), rel=1e-9)


def test_play_output_by_hand():
    x = np.array([0.0, 1.0, 0.4, -1.0, -0.9, 0.2])
    # half width 0.25, y0 = x0: moves only when x leaves y ± 0.25
    assert ops.play(x, 0.25).tolist() == pytest.approx([0.0, 0.75, 0.65, -0.75, -0.75, -0.05], abs=1e-15)
    assert ops.play(x, 0.25, y0=0.2).tolist() == pytest.approx([0.2, 0.75, 0.65, -0.75, -0.75, -0.05])
    # the scalar step agrees with the runner
    y, out = 0.0, []
    for xi in x:
        y = ops.play_step(y, xi, 0.25)
        out.append(y)
    assert out == pytest.approx(ops.play(x, 0.25).tolist(), abs=0)


def test_non_uniform_sampling_gives_the_uniform_result_at_the_same_x():
    rng = np.random.default_rng(3)
    turns = np.array([0.0, 1.2, -0.7, 0.9, -1.1, 0.3])
    tu = np.linspace(0, turns.size - 1, 5001)  # uniform, every turning point on the grid (step 1/1000)
    xu = np.interp(tu, np.arange(turns.size), turns)
    # non-uniform: a random subset of the uniform samples (gaps of 1 to ~60 steps) plus every turning point
    keep = np.unique(np.concatenate([rng.choice(tu.size, 300, replace=False), np.arange(turns.size) * 1000]))
    tn, xn = tu[keep], xu[keep]
    assert np.ptp(np.diff(tn)) > 10 * np.min(np.diff(tn))
    for run in (lambda x: ops.dahl(x, 50.0, 0.2), lambda x: ops.jenkins(x, 30.0, 0.1),
                lambda x: (ops.play(x, 0.15), np.zeros_like(x)), lambda x: ops.iwan(x, [10.0, 20.0], [0.05, 0.4])):
        (Fu, Eu), (Fn, En) = run(xu), run(xn)
        # rate independence: the output at a sample depends only on the path of x, not on the sampling
        assert np.max(np.abs(Fn - Fu[keep])) < 1e-10 * (1 + np.max(np.abs(Fu)))
        assert np.sum(En) == pytest.approx(np.sum(Eu), rel=1e-10, abs=1e-12)
    # Jenkins dissipation over the whole path, by hand: F_c·(slider travel) per monotone leg
    legs = [1.2 - 0.1, 1.9 - 0.2, 1.6 - 0.2, 2.0 - 0.2, 1.4 - 0.2]
    assert np.sum(ops.jenkins(xn, 30.0, 0.1)[1]) == pytest.approx(30.0 * sum(legs), rel=1e-12)


def test_zero_amplitude_dissipates_nothing():
    x = np.full(100, 0.7)
    assert np.sum(ops.dahl(x, 10.0, 0.1)[1]) == 0.0
    assert np.sum(ops.jenkins(x, 10.0, 0.1)[1]) == 0.0
    assert np.sum(ops.iwan(x, *ops.iwan_for_loss(5.0, 1.0))[1]) == 0.0


def test_iwan_for_loss_gives_structural_damping_energy():
    eta_k, x_max, n = 40.0, 2.0, 16
    Fc, xs = ops.iwan_for_loss(eta_k, x_max, n)
    for j in (4, 9, 16):  # A at element boundaries: exact
        A = j * x_max / n
        F, dE = ops.iwan(cycles(A), Fc, xs)
        assert last_cycle_energy(dE, 4000) == pytest.approx(math.pi * eta_k * A * A, rel=1e-12)
    # the scalar step reproduces the runner
    x = cycles(1.0, n=1, per=50)
    y = np.full(n, x[0])
    steps = [ops.iwan_step(y, xi, Fc, xs) for xi in x]
    F, dE = ops.iwan(x, Fc, xs)
    assert np.allclose([s[0] for s in steps], F, rtol=0, atol=1e-12)


def test_dahl_step_energy_balance():
    # work in = dissipated + stored: Σ z dx (exact branch) − Δ(z²/2k₀) over one step = returned dE
    z, dE = ops.dahl_step(0.0, 0.0, 0.3, 10.0, 0.1)
    assert z == pytest.approx(10.0 * (1 - math.exp(-3.0)), rel=1e-14)
    work = 10.0 * 0.3 - 10.0 * 0.1 * (1 - math.exp(-3.0))  # ∫₀^0.3 10(1 − e^{−u/0.1}) du
    assert dE == pytest.approx(work - z * z * 0.1 / 20.0, rel=1e-12)


def test_bad_inputs_name_the_field():
    with pytest.raises(ValueError, match="x_h"):
        ops.dahl([0.0, 1.0], 1.0, 0.0)
    with pytest.raises(ValueError, match="F_c"):
        ops.jenkins([0.0, 1.0], -1.0, 0.1)
    with pytest.raises(ValueError, match="NaN"):
        ops.play([0.0, float("nan")], 0.1)
    with pytest.raises(ValueError, match="same number"):
        ops.iwan([0.0], [1.0, 2.0], [0.1])


# ---------------------------------------------------------------- Coulomb sign at a turning point
@pytest.mark.parametrize("periodic", [False, True])
def test_coulomb_sign_is_the_instant_sign_but_on_a_turning_point(periodic):
    """sgn(ẋ) however near a reversal the instant falls; 0 only where |ẋ| is at round-off (1e-12) of the largest
    |ẋ| (an instant on the turning point).  Hand: [2, 1, 0.4, −1, −2] → [1, 1, 1, −1, −1] (0.4: a third of a step
    from the turning point, still moving); 2e-13 → 0 (1e-13 of 2), 2e-11 → 1.  Bugs caught: the old third-of-a-step
    midpoint rule, <= made <, the largest |ẋ| made the smallest, a rule that depends on the wrap."""
    def cs(v):
        return coulomb_sign(v, periodic=periodic).tolist()

    assert cs([2, 1, 0.4, -1, -2]) == [1, 1, 1, -1, -1]
    assert cs([0.1, 1, 2, -1]) == [1, 1, 1, -1]
    assert cs([2, 1, 2e-13, -1, -2]) == [1, 1, 0, -1, -1]
    assert cs([2, 1, 2e-12, -1, -2]) == [1, 1, 0, -1, -1]  # exactly 1e-12 of the largest: on it (<=)
    assert cs([2, 1, 2e-11, -1, -2]) == [1, 1, 1, -1, -1]
    assert cs([2, 1, -0.0, -1, -2]) == [1, 1, 0, -1, -1]
    assert cs([1e-13, 1e-13]) == [1, 1]  # a slow record: round-off is relative to its own largest speed
    assert cs([0.0, 0.0]) == [0, 0]  # at rest


# ---------------------------------------------------------------- own-seed 804 survivors
def test_dahl_cycle_energy_closed_form_against_the_operator_loop():
    """4·F_h·(A − x_h·tanh(A/x_h)) against the loop area ∮F dx of the Dahl operator's steady cycle on ±A (another
    method: numerical integration): F_h = 50 N, x_h = 0.2 mm, A = 0.5 mm."""
    from chainid.model.operators import dahl_cycle_energy

    want = 4 * 50.0 * (0.5 - 0.2 * math.tanh(0.5 / 0.2))
    assert dahl_cycle_energy(50.0, 0.2, 0.5) == pytest.approx(want, rel=1e-14)
    psi = np.linspace(0.0, 2 * math.pi, 20001)
    x = 0.5 * np.sin(psi)
    from chainid.model.effects import dahl_operator

    F = dahl_operator(x, 50.0, 0.2, periodic=True)
    loop = abs(float(np.sum(0.5 * (F[1:] + F[:-1]) * np.diff(x))))
    assert loop == pytest.approx(want, rel=2e-3)


@pytest.mark.parametrize("bad", [np.zeros((3, 4)), np.zeros(0), np.zeros((0, 2))])
def test_operators_refuse_a_non_series(bad):
    """The operators take one non-empty 1-D series (documented); a 2-D array is refused, not flattened.
    Bug caught: `x.ndim != 1 or x.size == 0` → `and`."""
    from chainid.model.operators import dahl, play

    with pytest.raises(ValueError, match="non-empty 1-D"):
        play(bad, 0.1)
    with pytest.raises(ValueError, match="non-empty 1-D"):
        dahl(bad, 1.0, 0.1)
