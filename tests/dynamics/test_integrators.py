"""The integrators (chainid.dynamics.integrators): the external resistance and tensioner forces, the implicit
update and its Newton iterations, by hand.  Units mm, N, s, kg."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.dynamics import ChainLine, Drive, simulate
from chainid.dynamics.integrators import _external, _resist


def test_external_resistance_viscous_below_eps_coulomb_above():
    """R = 10 N, ε = 1 mm/s: v = 0.5 → −5 N (viscous branch), 2 → −10 N, −3 → +10 N (saturated), 0 → 0.
    Bugs caught: either clip bound changed or dropped, the sign, v/ε made v·ε."""
    v = np.array([0.0, 0.5, 2.0, -3.0, -0.25])
    u = np.zeros(5)
    res = np.array([0.0, 10.0, 10.0, 10.0, 10.0])
    fe = np.zeros(5)
    none_i, none_f = np.zeros(0, dtype=np.int64), np.zeros(0)
    _external(0.0, u, v, res, 1.0, none_i, none_f, none_f, False, 0.0, 0.0, fe, True)
    np.testing.assert_allclose(fe, [0.0, -5.0, -10.0, 10.0, 2.5], rtol=0, atol=1e-12)
    _external(0.0, u, v, res, 2.0, none_i, none_f, none_f, False, 0.0, 0.0, fe, True)  # ε = 2 mm/s
    np.testing.assert_allclose(fe, [0.0, -2.5, -10.0, 10.0, 1.25], rtol=0, atol=1e-12)


def test_external_tensioner_and_load_steps():
    """Tensioner: −(F_t + k_t·u_N) on the last node; a load step acts from t_on on (t >= t_on).
    Bugs caught: k_t dropped, the load's switch-on made strict or inverted."""
    u = np.array([0.0, 0.0, 2.0])
    v = np.zeros(3)
    fe = np.zeros(3)
    _external(0.1, u, v, np.zeros(3), 1.0, np.array([1], dtype=np.int64), np.array([50.0]), np.array([0.1]),
              True, 300.0, 40.0, fe, True)
    np.testing.assert_allclose(fe, [0.0, -50.0, -(300.0 + 40.0 * 2.0)], atol=1e-12)
    _external(0.0999, u, v, np.zeros(3), 1.0, np.array([1], dtype=np.int64), np.array([50.0]), np.array([0.1]),
              True, 300.0, 0.0, fe, True)
    np.testing.assert_allclose(fe, [0.0, 0.0, -300.0], atol=1e-12)


def test_resist_closed_form_update():
    """α = dt·1e3·R/m = 1e-4·1e3·1/2 = 0.05 mm/s.  v* = 0.2: w = 0.2/(1 + 0.05/1) (viscous);
    v* = 5: w = 4.95 (Coulomb); v* = −0.1: w = −0.1/1.05.  The returned work is ½·m·(w² − v*²)·1e-3 summed.
    Node 0 (the drive) is left alone.  Bugs caught: the branch test, α's factors, the sign of the saturated
    step, the node range."""
    v = np.array([7.0, 0.2, 5.0, -0.1])
    m = np.array([1.0, 2.0, 2.0, 2.0])
    res = np.array([1.0, 1.0, 1.0, 1.0])
    w_expect = np.array([7.0, 0.2 / 1.05, 4.95, -0.1 / 1.05])
    dW = _resist(v, m, res, 1.0, 1e-4, 3)
    np.testing.assert_allclose(v, w_expect, rtol=1e-14)
    expect = sum(0.5e-3 * mm * (w * w - vs * vs) for mm, w, vs in zip(m[1:], w_expect[1:], [0.2, 5.0, -0.1]))
    assert dW == pytest.approx(expect, rel=1e-12)
    v2 = np.array([0.0, -5.0])
    _resist(v2, np.array([1.0, 2.0]), np.array([0.0, 1.0]), 1.0, 1e-4, 1)
    assert v2[1] == pytest.approx(-4.95, rel=1e-14)


def test_implicit_scheme_creeps_viscously_near_standstill():
    """The implicit scheme uses _external: a free node creeping at |v| < ε decays as exp(−t/τ), τ = ε·m/(1e3·R).
    Bug caught: the viscous branch of _external (only the explicit scheme's _resist was covered)."""
    line = ChainLine(n_links=10, n_masses=1, pretension_N=0.0, far_end="tensioner", tail_mass_kg=2.0,
                     resistance_N=3.0, resistance_v_eps=1.0)
    m1 = line.node_masses()[1]
    tau = m1 / (1e3 * 3.0)
    res = simulate(line, Drive("none"), 2 * tau, dt=tau / 2000, scheme="implicit", initial_u=np.array([0.0, 5.0]),
                   initial_v=np.array([0.0, 0.8]), n_out=100)
    np.testing.assert_allclose(res.v[:, 1], 0.8 * np.exp(-res.t / tau), rtol=2e-3)


def test_implicit_newton_on_the_exact_tangent_needs_a_few_iterations_and_no_halving():
    """A taut chain (8 segments at 5 kN, tensioner 200 N/mm; a 0.02 mm 20 Hz drive keeps every tension within
    5 kN ± 25 N) at 20 × the explicit stable step: Newton's method on the exact tridiagonal tangent converges
    quadratically, so every step is accepted whole (no rejected or halved sub-step) within a handful of iterations
    (the module's "2-4 iterations"; at most 6 allowed here).  A wrong tangent (a dropped off-diagonal coupling
    term) converges linearly at best: steps are rejected and halved.
    Bug caught: the super-diagonal's spring term taken only beyond the last segment (`i >= N`)."""
    from chainid.dynamics import stable_step
    from chainid.dynamics.integrators import run
    from chainid.dynamics.simulation import core_arguments

    line = ChainLine(n_links=40, n_masses=8, pretension_N=5_000.0, tensioner_stiffness=200.0)
    dt = 20 * stable_step(line)
    drive = Drive("sine", A=0.02, omega=2 * math.pi * 20)
    args, outs = core_arguments(line, drive, dt, 400, 4)
    status, _ = run(True, *args, *outs)
    stats = outs[-1]
    assert status == 0 and outs[1].min() > 4_950.0 and outs[1].max() < 5_050.0  # taut throughout
    assert (stats[0], stats[1]) == (400, 0) and stats[3] == 1.0  # 400 whole steps accepted, none rejected
    assert 1 <= stats[2] <= 6  # the largest Newton iteration count of any step
    with pytest.warns(RuntimeWarning, match=r"not resolved .* \(17\.78 steps per period; valid >= 20\)"):
        res = simulate(line, drive, 400 * dt, dt=dt, scheme="implicit", n_out=100)
    assert res.rejected == 0 and res.substeps == res.n_steps


@pytest.mark.parametrize("far_end, drive", [("tensioner", Drive("ramp", v=500.0, t_ramp=0.05)),
                                             ("fixed", Drive("sine", A=0.5, omega=2 * math.pi * 50))])
def test_implicit_steps_that_all_fall_back_to_the_explicit_scheme_are_the_explicit_run_with_resistance(far_end, drive):
    """Newton allowed one iteration at a tolerance it cannot meet, no halving, and every sub-step short enough for
    the explicit scheme: every step of the implicit run is the explicit fallback, whose forces and accelerations
    (with the strand's resistance, 300 N) are recomputed for the next step and the resistance taken out again
    before the next Verlet step, which applies it itself.  The run is then the explicit scheme's at the same step,
    to rounding: node displacements, speeds and the work done, each within 1e-12 of its largest value (measured
    7e-16, 4e-14, 8e-15).  A resistance applied twice in either half-kick, its work counted twice, or one node's
    left out moves them by percents.  Both ends: with a tensioner the Verlet step writes the external forces
    itself; at a fixed end it does not, and the failed Newton attempt's must not be left in them."""
    from chainid.dynamics import stable_step
    from chainid.dynamics.integrators import run
    from chainid.dynamics.simulation import core_arguments

    line = ChainLine(n_links=40, n_masses=8, pretension_N=2000.0, resistance_N=300.0, far_end=far_end)
    dt = 0.5 * stable_step(line)
    a1, o1 = core_arguments(line, drive, dt, 400, 4)
    a2, o2 = core_arguments(line, drive, dt, 400, 4, levels=0, tol_abs=1e-12, tol_rel=1e-15, max_it=1,
                            dt_explicit=dt)
    assert run(False, *a1, *o1)[0] == 0 and run(True, *a2, *o2)[0] == 0
    assert o2[-1][4] == 400  # every step fell back
    for a, b in ((o1[3], o2[3]), (o1[4], o2[4]), (o1[5][:, 0], o2[5][:, 0])):  # u [mm], v [mm/s], W [N·mm]
        assert np.max(np.abs(b - a)) <= 1e-12 * np.max(np.abs(a))


def test_a_halved_implicit_sub_step_grows_back_so_every_step_is_tried_whole_again():
    """The taut chain of the Newton test at 20 × the stable step, Newton limited to 3 iterations: near-quadratic
    convergence needs about 4 on a whole step and 3 on a half.  After a halving the sub-step doubles back once
    accepted, so each step is tried whole again: nearly every step is rejected once and done in two halves, which
    makes the accepted sub-steps exactly the steps plus the rejections.  (A sub-step that stayed halved would be
    rejected once in the whole run.)"""
    from chainid.dynamics import stable_step
    from chainid.dynamics.integrators import run
    from chainid.dynamics.simulation import core_arguments

    line = ChainLine(n_links=40, n_masses=8, pretension_N=5_000.0, tensioner_stiffness=200.0)
    dt = 20 * stable_step(line)
    args, outs = core_arguments(line, Drive("sine", A=0.02, omega=2 * math.pi * 20), dt, 400, 4, max_it=3)
    assert run(True, *args, *outs)[0] == 0
    accepted, rejected, _, shortest = outs[-1][:4]
    assert rejected >= 0.9 * 400 and accepted == 400 + rejected and shortest == 0.5


def test_the_first_explicit_step_from_a_non_uniform_rest_state_moves_each_node_by_newtons_law():
    """Released at rest from unequal node displacements, the first Verlet step moves each free node by
    h²/2 · a_i with a_i = 1e3·(T_{i−1} − T_i)/m_i [mm/s²]: T_j solved by hand (brentq) from the segment's compliance
    x = c_lin·F + c_h·F^(2/3) at its extension e_j = e_pre,j + u_j − u_{j+1}, m_i the node masses."""
    from scipy.optimize import brentq

    line = ChainLine(n_links=60, n_masses=6, pretension_N=5_000.0, far_end="fixed")
    u0 = np.array([0.0, 0.05, -0.03, 0.08, 0.0, 0.02, 0.0])  # mm; node 0 the (still) drive, node 6 fixed
    res = simulate(line, Drive("none"), 4e-6, dt=1e-6, n_out=4, initial_u=u0)
    c_lin, c_h = line.segment_coefficients()
    e = line.pretension_elongation() + u0[:-1] - u0[1:]
    T = np.array([brentq(lambda F: c_lin[j] * F + c_h[j] * F ** (2 / 3) - e[j], 0.0, 1e7, xtol=1e-12, rtol=1e-14)
                  for j in range(e.size)])
    assert np.ptp(T) > 100.0  # N: the segments' tensions differ
    a = 1e3 * (T[:-1] - T[1:]) / line.node_masses()[1:-1]
    h = res.t[1]
    np.testing.assert_allclose(res.u[1, 1:-1] - u0[1:-1], 0.5 * h * h * a, rtol=1e-6)


def test_a_fallback_step_applies_the_moving_resistance_once():
    """A free tail mass sliding on a slack strand (no spring force) against a resistance R = 3 N above its creep
    speed decelerates at 1e3·R/m mm/s² whatever the scheme: 100 → 60 mm/s over 0.04 s for m = m_1 (node mass by
    hand from the line's mass per metre and the tail mass), also when every implicit step falls back to Verlet."""
    from chainid.dynamics.integrators import run
    from chainid.dynamics.simulation import core_arguments

    line = ChainLine(n_links=10, n_masses=1, pretension_N=0.0, far_end="tensioner", tail_mass_kg=2.0,
                     resistance_N=3.0, resistance_v_eps=0.01)
    m1 = 0.5 * line.chain.mass_per_m * 10 * line.chain.pitch * 1e-3 + 2.0  # kg
    want = 100.0 - 1e3 * 3.0 / m1 * 0.04
    for implicit, kw in ((False, {}), (True, dict(levels=0, max_it=0, dt_explicit=1e-4))):
        args, outs = core_arguments(line, Drive("none"), 1e-4, 400, 1, np.array([0.0, 5.0]), np.array([0.0, 100.0]),
                                    **kw)
        assert run(implicit, *args, *outs)[0] == 0
        assert not implicit or outs[-1][4] == 400  # every step fell back
        assert outs[4][-1, 1] == pytest.approx(want, rel=1e-9)
