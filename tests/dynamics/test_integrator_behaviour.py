"""The two schemes of chainid.dynamics.integrators against their exact discrete solutions on linear lines, and the
bookkeeping of a run (work of the drive, the take-up, load steps and the resistance; kinetic and stored energy;
the work count and its budget), by hand.  Units mm, N, s, kg; energies N·mm.

A contact exponent β = 1 makes a taut segment exactly linear: x = (c_lin + c_h)·F, so T = e/(c_lin + c_h).  On such
a line the schemes' recurrences have closed forms (Ω = ω·h):

* velocity Verlet (central difference): u_n = u0·cos(nθ) from rest, cos θ = 1 − Ω²/2, and v_n = (u_{n+1} − u_{n−1})/2h;
* Newmark's average acceleration (trapezoidal rule): u_n = u0·cos(nθ) with cos θ = (1 − Ω²/4)/(1 + Ω²/4), and
  v_n = −u0·ω·sin(nθ) (from u_{n+1} − u_n = h/2·(v_n + v_{n+1}) and tan(θ/2) = Ω/2).
"""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from chainid.dynamics import ChainLine, Drive, LoadStep, simulate
from chainid.dynamics.integrators import run
from chainid.dynamics.simulation import core_arguments

P, KT, TAIL = 1_000.0, 300.0, 1.0  # N, N/mm, kg


def _linear_line(**kw):
    """One segment of 4 links with β = 1 (linear when taut), tensioner end with a take-up spring and a 1 kg tail."""
    return ChainLine(n_links=4, n_masses=1, pretension_N=P, contact_exponent=1.0, tensioner_stiffness=KT,
                     tail_mass_kg=TAIL, **kw)


def _omega(line):
    """ω [rad/s] of the tail node: 1e3·(1/(c_lin + c_h) + k_t)/m_1, m_1 = half the segment (4 × 50 mm at the chain's
    kg/m) plus the tail, by hand."""
    cl, ch = line.segment_coefficients()
    m1 = 0.5 * 4 * 50.0 * line.chain.mass_per_m * 1e-3 + TAIL
    return math.sqrt(1e3 * (1.0 / (cl[0] + ch[0]) + KT) / m1)


def _quiet(*args, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # the coarse steps' balance is not under test
        return simulate(*args, **kw)


def _free_run(scheme, Om, u0, n=40):
    line = _linear_line()
    w = _omega(line)
    h = Om / w
    res = _quiet(line, Drive("none"), n * h, dt=h, scheme=scheme, n_out=n, initial_u=np.array([0.0, u0]),
                 peak_force=P)
    assert res.n_steps == n and res.dt == pytest.approx(h, rel=1e-12)
    return res, w, h


def test_verlet_on_a_linear_tail_node_is_the_central_difference_recurrence():
    """Ω = 1.2 (below the Gershgorin bound √2 of this node), released from u0 = 0.01 mm at rest: u_n = u0·cos(nθ),
    cos θ = 1 − Ω²/2 (not the exact cos(ωt): 2 u0 apart within 40 steps), and v_n = −u0·sin(nθ)·sin θ/h
    (rel 1e-9 of u0 and of u0·sin θ/h).
    Bugs caught: a half-kick's ½ (either), the drift's h, the inverse mass, the take-up spring's k_t·u."""
    u0, Om = 0.01, 1.2
    res, w, h = _free_run("explicit", Om, u0)
    th = math.acos(1.0 - Om * Om / 2.0)
    n = np.arange(41)
    np.testing.assert_allclose(res.u[:, 1], u0 * np.cos(n * th), rtol=0, atol=1e-9 * u0)
    vmax = u0 * math.sin(th) / h
    np.testing.assert_allclose(res.v[:, 1], -vmax * np.sin(n * th), rtol=0, atol=1e-9 * vmax)
    assert np.max(np.abs(res.u[:, 1] - u0 * np.cos(w * res.t))) > 0.5 * u0  # the recurrence, not the exact motion


def test_newmark_on_a_linear_tail_node_is_the_trapezoidal_recurrence():
    """Ω = 3 (the explicit scheme would blow up), u0 = 0.002 mm (every Newton iterate stays taut): u_n = u0·cos(nθ)
    with cos θ = (1 − Ω²/4)/(1 + Ω²/4) and v_n = −u0·ω·sin(nθ) (rel 1e-9).
    Bugs caught: Newmark's ¼·h² or ½·h (the update or the tangent), the sign of the take-up spring's force."""
    u0, Om = 0.002, 3.0
    res, w, h = _free_run("implicit", Om, u0)
    th = math.acos((1.0 - Om * Om / 4.0) / (1.0 + Om * Om / 4.0))
    n = np.arange(41)
    np.testing.assert_allclose(res.u[:, 1], u0 * np.cos(n * th), rtol=0, atol=1e-9 * u0)
    np.testing.assert_allclose(res.v[:, 1], -u0 * w * np.sin(n * th), rtol=0, atol=1e-9 * u0 * w)


def test_newton_on_a_linear_line_converges_after_one_solve_and_the_work_counts_each_iteration():
    """On a linear line the exact tangent (segment 1/(c_lin + c_h) and take-up k_t) makes one Newton solve exact:
    every step takes 2 iterations (the solve and the check).  SimResult.work counts free nodes × iterations ×
    ITERATION_COST = 2 (measured cost of an iteration in explicit node-steps): 1 × 2 × 2 = 4 per step, 160 for 40
    steps; no step rejected.  Bugs caught: the take-up spring left out of the tangent (``kt if tens``), the iteration
    cost or the node count of the work."""
    res, _, _ = _free_run("implicit", 3.0, 0.002)
    assert res.rejected == 0 and res.substeps == 40
    assert res.work == 160.0


@pytest.mark.parametrize("scheme, Om, u0", [("explicit", 1.2, 0.01), ("implicit", 3.0, 0.002)])
def test_the_take_up_work_is_minus_its_constant_force_and_spring_potential(scheme, Om, u0):
    """Without a drive the only work in is the tensioner's, −(F_t + k_t·u) on the tail node: its trapezoidal work is
    exact for a force linear in u, W_n = −F_t·(u_n − u0) − k_t·(u_n² − u0²)/2 (F_t = the pretension), rel 1e-9 of
    F_t·u0.  Bugs caught: the trapezoid's sum made a difference, the external work's sign, k_t dropped."""
    res, _, _ = _free_run(scheme, Om, u0)
    u = res.u[:, 1]
    want = -P * (u - u0) - KT * (u * u - u0 * u0) / 2.0
    np.testing.assert_allclose(res.work_in, want, rtol=0, atol=1e-9 * P * u0)
    assert np.ptp(res.work_in) > 0.5 * P * u0


@pytest.mark.parametrize("scheme", ["explicit", "implicit"])
def test_recorded_kinetic_and_stored_energies_by_hand(scheme):
    """Sine drive (A = 0.005 mm at 300 Hz) on the linear line: the kinetic energy recorded is ½·1e-3·Σ m_i·v_i² over
    every node, the drive node included (m_0 = ½ × 4 links × 50 mm × 4 kg/m = 0.4 kg; at t = 0 only it moves, at
    Aω: ½·1e-3·m_0·(Aω)²), and the stored energy ½·e²/(c_lin + c_h) of the segment's elongation
    e = e_pre + u_0 − u_1, e_pre = F_t·(c_lin + c_h) (rel 1e-10).
    Bugs caught: the drive node left out of E_kin, its ½·1e-3, the energies' columns swapped."""
    line = _linear_line()
    cl, ch = line.segment_coefficients()
    c = cl[0] + ch[0]
    ms = 4 * 50.0 * line.chain.mass_per_m * 1e-3
    m = np.array([0.5 * ms, 0.5 * ms + TAIL])
    A, w = 0.005, 2 * math.pi * 300
    res = _quiet(line, Drive("sine", A=A, omega=w), 0.01, dt=2e-6, scheme=scheme, n_out=100, peak_force=P)
    assert m[0] == pytest.approx(0.4, rel=1e-12)
    assert res.kinetic[0] == pytest.approx(0.5e-3 * 0.4 * (A * w) ** 2, rel=1e-12)
    kin = 0.5e-3 * (m[None, :] * res.v ** 2).sum(axis=1)
    np.testing.assert_allclose(res.kinetic, kin, rtol=1e-10, atol=0)
    e = P * c + res.u[:, 0] - res.u[:, 1]
    np.testing.assert_allclose(res.elastic, 0.5 * e * e / c, rtol=1e-10, atol=0)


@pytest.mark.parametrize("scheme", ["explicit", "implicit"])
def test_the_drive_work_is_the_stored_energy_plus_the_drive_nodes_kinetic_energy(scheme):
    """One linear segment with a fixed far end (no free node): the drive does all the work, W = ∫T du_0 + Δ(½ m_0
    v_0²); T = (e_pre + u_0)/(c_lin + c_h) is linear in u_0, so the trapezoid is exact and
    W_n = ((e_pre + u_0)² − e_pre²)/(2(c_lin + c_h)) + ½·1e-3·m_0·(Aω cos ωt_n)², u_0 = A sin ωt_n (rel 1e-9 of
    the largest).  Bugs caught: the trapezoid's ½·(T_s + T), the kinetic term's ½·1e-3 or its v² − v_s²."""
    line = ChainLine(n_links=4, n_masses=1, pretension_N=P, contact_exponent=1.0, far_end="fixed")
    cl, ch = line.segment_coefficients()
    c = cl[0] + ch[0]
    m0 = 0.5 * 4 * 50.0 * line.chain.mass_per_m * 1e-3
    A, w = 0.01, 2 * math.pi * 1000
    res = _quiet(line, Drive("sine", A=A, omega=w), 0.005, dt=5e-6, scheme=scheme, n_out=50)
    u0, v0 = A * np.sin(w * res.t), A * w * np.cos(w * res.t)
    e_pre = P * c
    want = ((e_pre + u0) ** 2 - e_pre ** 2) / (2 * c) + 0.5e-3 * m0 * (v0 ** 2 - (A * w) ** 2)
    np.testing.assert_allclose(res.work_in, want, rtol=0, atol=1e-9 * np.abs(want).max())
    assert 0.5e-3 * m0 * (A * w) ** 2 > 0.01 * np.abs(want).max()  # the kinetic term counts


def _two_segment_line(loads):
    return ChainLine(n_links=4, n_masses=2, pretension_N=P, contact_exponent=1.0, far_end="fixed", loads=loads)


@pytest.mark.parametrize("k_on", [0, 5])
def test_a_load_step_on_a_linear_node_follows_the_verlet_recurrence_from_its_switch_on(k_on):
    """Two linear segments (fixed end), load F = 20 N on node 1 from t_on: with K = k_1 + k_2 = Σ 1/(c_lin + c_h), the
    node's static shift is −F/K, Ω = 0.3 and cos θ = 1 − Ω²/2.  From t_on = 0 (the load in the initial state)
    u_n = −(F/K)(1 − cos nθ); from t_on = 4.5 h the load acts from the grid time 5h on and the central difference gives
    u_{5+m} = −(F/K)(1 − cos((m + ½)θ)/cos(θ/2)) (0 before).  The load's work is −F·u_n exactly (constant force,
    no motion in the switching step).  Rel 1e-9 of F/K.
    Bugs caught: the load's sign, the switch-on test, the load dropped from the initial state or from a line without
    a tensioner (``tens or load steps``), its work's trapezoid."""
    F = 20.0
    line = _two_segment_line(())
    cl, ch = line.segment_coefficients()
    K = float(np.sum(1.0 / (cl + ch)))
    m1 = 0.5 * (2 * 50.0 + 2 * 50.0) * line.chain.mass_per_m * 1e-3
    h = 0.3 / math.sqrt(1e3 * K / m1)
    line = _two_segment_line((LoadStep(node=1, force_N=F, t_on=4.5 * h if k_on else 0.0),))
    res = _quiet(line, Drive("none"), 40 * h, dt=h, n_out=40)
    th = math.acos(1.0 - 0.09 / 2.0)
    n = np.arange(41)
    m = n - k_on
    if k_on:
        want = np.where(m >= 0, -(F / K) * (1.0 - np.cos((m + 0.5) * th) / math.cos(th / 2)), 0.0)
    else:
        want = -(F / K) * (1.0 - np.cos(n * th))
    np.testing.assert_allclose(res.u[:, 1], want, rtol=0, atol=1e-9 * F / K)
    np.testing.assert_allclose(res.work_in, -F * res.u[:, 1], rtol=0, atol=1e-9 * F * F / K)


def _sliding(scheme, veps=0.01, v0=100.0, t_end=0.04, h=1e-4):
    """A 3 kg tail node (half of 10 links at 4 kg/m + 2 kg) sliding away from the drive on a slack segment (u_1 = 5 mm,
    no pretension, no take-up force) against R = 3 N: deceleration 1e3·R/m = 1000 mm/s² while |v| > ε."""
    line = ChainLine(n_links=10, n_masses=1, pretension_N=0.0, tail_mass_kg=2.0, resistance_N=3.0,
                     resistance_v_eps=veps)
    m1 = 0.5 * 10 * 50.0 * line.chain.mass_per_m * 1e-3 + 2.0
    res = _quiet(line, Drive("none"), t_end, dt=h, scheme=scheme, n_out=round(t_end / h),
                 initial_u=np.array([0.0, 5.0]), initial_v=np.array([0.0, v0]))
    return res, m1


@pytest.mark.parametrize("scheme", ["explicit", "implicit"])
def test_the_moving_resistance_does_the_work_of_the_kinetic_energy_it_removes(scheme):
    """Sliding at 100 mm/s against R = 3 N for 40 ms: v_n = v0 − 1e3·R·t_n/m (both schemes: a constant deceleration),
    the work in W_n = ½·1e-3·m·(v_n² − v0²) (negative: the resistance takes energy out), and the travel: the
    trapezoidal rule's exact u0 + v0·t − ½·a·t², Verlet's u0 + h·Σ_{j<n} v_j (the resistance is applied after the
    drift); rel 1e-9.  Bugs caught: the sign or the ½·1e-3 of the resistance's work, its velocity update, the
    implicit scheme's trapezoidal work of the external forces."""
    res, m1 = _sliding(scheme)
    a = 1e3 * 3.0 / m1
    t = res.t
    v = 100.0 - a * t
    assert res.tension.max() == 0.0
    np.testing.assert_allclose(res.v[:, 1], v, rtol=1e-9)
    np.testing.assert_allclose(res.work_in, 0.5e-3 * m1 * (v * v - 1e4), rtol=1e-9, atol=1e-12)
    if scheme == "implicit":
        u = 5.0 + 100.0 * t - 0.5 * a * t * t
    else:
        u = 5.0 + np.concatenate([[0.0], np.cumsum(res.dt * v[:-1])])
    np.testing.assert_allclose(res.u[:, 1], u, rtol=1e-9)


def test_implicit_viscous_creep_is_the_trapezoidal_decay_after_one_newton_solve_a_step():
    """Creeping below ε = 2 mm/s the resistance is viscous, R·v/ε: v' = −v/τ, τ = ε·m/(1e3·R) = 2 ms.  The trapezoidal
    rule decays by (1 − h/2τ)/(1 + h/2τ) a step (h = τ/20), and Newton on the exact tangent (with the resistance's
    R/ε) solves this linear step at once: 2 iterations a step, work 2 × 2 × 1 node per step.
    Bugs caught: the resistance's tangent R/ε (made R·ε, or taken above ε instead of below)."""
    res, m1 = _sliding("implicit", veps=2.0, v0=1.5, t_end=4e-3, h=1e-4)
    tau = 2.0 * m1 / (1e3 * 3.0)
    r = (1 - 1e-4 / (2 * tau)) / (1 + 1e-4 / (2 * tau))
    np.testing.assert_allclose(res.v[:, 1], 1.5 * r ** np.arange(41), rtol=1e-9)
    assert res.work == 4.0 * 40


@pytest.mark.parametrize("n_masses, far_end, per_step", [(2, "fixed", 1.0), (1, "fixed", 1.0), (2, "tensioner", 2.0)])
def test_the_explicit_work_counts_free_nodes_per_step_and_at_least_one(n_masses, far_end, per_step):
    """SimResult.work of an explicit run: free nodes × steps, one per step even with no free node (fixed end, one
    segment); two segments: 1 free node at a fixed end, 2 at a tensioner.  Bug caught: the floor ``max(last, 1)``."""
    line = ChainLine(n_links=4, n_masses=n_masses, pretension_N=P, far_end=far_end)
    res = _quiet(line, Drive("sine", A=0.001, omega=100.0), 1e-3, dt=1e-5, n_out=10)
    assert res.n_steps == 100 and res.work == per_step * 100


@pytest.mark.parametrize("budget, status, done", [(10.0, 0, 10), (9.5, 3, 9), (0.0, 0, 10)])
def test_the_budget_stops_a_run_whose_work_exceeds_it(budget, status, done):
    """run's ``budget`` [node-steps]: 10 explicit steps of one free node cost 10; a budget of 10 is not exceeded (the
    run completes), 9.5 is exceeded by the 10th step (status 3 after 9 whole steps, the work counted 10), 0 means no
    limit.  Bugs caught: ``work > budget`` made ``>=``, the ``budget > 0`` switch made ``>= 0``."""
    line = ChainLine(n_links=4, n_masses=2, pretension_N=P, far_end="fixed")
    args, outs = core_arguments(line, Drive("sine", A=0.001, omega=100.0), 1e-5, 10, 1)
    st, _ = run(False, *args, *outs, budget=budget)
    stats = outs[-1]
    assert st == status and stats[7] == done and stats[6] == 10.0


@pytest.mark.parametrize("kw", [dict(hysteresis=((2_000.0, 100.0),)), dict(coulomb_N=50.0),
                                dict(dahl=((30.0, 0.2),)), dict(stribeck=((80.0, 60.0, 2.0, 15.0),)),
                                dict(bouc_wen=((150.0, 0.04, 2.5, 0.6),)), dict(backlash_mm=0.08)])
@pytest.mark.parametrize("scheme", ["explicit", "implicit"])
def test_memory_elements_start_unstressed_so_a_pretensioned_line_stays_at_rest(kw, scheme):
    """At t = 0 every element is unstressed (a slider or a play's output at the elongation, a Dahl or Bouc–Wen state
    at 0): a line at its pretension (1 kN, the take-up pulling with it), no drive, stays at rest with every tension
    1 kN (rel 1e-9), whatever element it carries.
    Bugs caught: the kinds started at the elongation (Jenkins/Coulomb 0, Stribeck 2, play 4) garbled."""
    line = ChainLine(n_links=40, n_masses=4, pretension_N=1_000.0, **kw)
    res = _quiet(line, Drive("none"), 0.01, scheme=scheme, n_out=20)
    assert np.max(np.abs(res.u)) < 1e-9
    np.testing.assert_allclose(res.tension, 1_000.0, rtol=1e-9)


def test_newton_on_a_damped_two_mass_linear_line_converges_after_one_solve():
    """Two free nodes joined by a damped linear segment that stays taut (c = 5 N·s/mm, a few µm of motion: the
    damper's force stays far below the 1 kN pretension, so no tension is clipped at 0): the residual is linear in
    (u, v), so with the exact tridiagonal tangent (the segment's c·h/2 and k·h²/4 in both off-diagonals) one Newton
    solve is exact and every step takes 2 iterations: work = 2 nodes × 2 iterations × ITERATION_COST 2 = 8 per
    step, 320 for 40.  Bugs caught: a wrong damping or stiffness term in the tangent's lower or upper diagonal
    (Newton then needs more iterations to the same answer)."""
    line = ChainLine(n_links=8, n_masses=2, pretension_N=P, contact_exponent=1.0, tensioner_stiffness=KT,
                     tail_mass_kg=TAIL, damping=5.0)
    h = 2e-4
    res = _quiet(line, Drive("none"), 40 * h, dt=h, scheme="implicit", n_out=40,
                 initial_u=np.array([0.0, 0.001, 0.003]), peak_force=P)
    assert res.n_steps == 40 and res.rejected == 0
    assert res.tension.min() > 0.5 * P  # taut throughout: the law is linear
    assert np.ptp(res.u[:, 1]) > 5e-4  # the nodes move: the damper's tangent terms are exercised
    assert res.work == 320.0
