"""The numba element and spring code of the chain line called directly, against hand values, closed forms, central
finite differences and numpy loop areas (chainid.dynamics.segments._element / _element_energy / _elastic,
chainid.dynamics.springs.deadband / deadband_energy / spring_energy).

_element(kind, state, e, Δe, ė, f, x, q, tabs) returns (state, force [N], loss [N·mm], dT/de [N/mm], dT/dė [N·s/mm]);
the step runs from e − Δe to e.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.dynamics.segments import _elastic, _element, _element_energy
from chainid.dynamics.springs import deadband, deadband_energy, spring_energy
from chainid.model.operators import bouc_wen_table

NO_Q, NO_TABS = np.zeros(3), np.zeros((0, 2, 2))


def _bw_tabs(n, r):
    _, xi, Z = bouc_wen_table(n, r)
    return np.stack([xi, Z])[None, :, :].copy()


def _cycle_loss(kind, f, x, A, q=NO_Q, tabs=NO_TABS, s0=0.0, v=1.0, m=400, cycles=3):
    """Run e = A·sin(2πt) (m steps a cycle); return the loss and the (e, force) points of the last cycle."""
    e_path = A * np.sin(2.0 * np.pi * np.arange(cycles * m + 1) / m)
    s, loss, forces = s0, 0.0, [0.0]
    for i in range(1, e_path.size):
        de = e_path[i] - e_path[i - 1]
        s, z, dq, _, _ = _element(kind, s, e_path[i], de, v if de >= 0.0 else -v, f, x, q, tabs)
        forces.append(z)
        if i > (cycles - 1) * m:
            loss += dq
    return loss, e_path[-m - 1:], np.array(forces[-m - 1:])


def _loop_area(e, F):
    """∮ F de of a closed polygon (trapezoids, numpy)."""
    return float(np.sum(0.5 * (F[1:] + F[:-1]) * np.diff(e)))


def test_jenkins_sticks_with_tangent_f_over_x_and_slips_with_force_f_and_zero_tangent():
    """Jenkins f = 100 N, x_s = 0.5 mm, slider at 0: at e = 0.2 it sticks (force 100·0.2/0.5 = 40 N, loss 0,
    dT/de = 200 N/mm); at e = 0.8 it slips to y = 0.3 (force 100 N, loss 100·0.3 = 30 N·mm, dT/de = 0); at
    e = −0.8 to y = −0.3 (force −100 N, loss 30 N·mm).  Both tangents equal a central difference of the force
    (h = 1e−6 mm, abs 1e−6).  No rate tangent (0)."""
    for e, y, F, loss, k in [(0.2, 0.0, 40.0, 0.0, 200.0), (0.8, 0.3, 100.0, 30.0, 0.0),
                             (-0.8, -0.3, -100.0, 30.0, 0.0)]:
        out = _element(0, 0.0, e, e, 1.0, 100.0, 0.5, NO_Q, NO_TABS)
        assert out == pytest.approx((y, F, loss, k, 0.0), abs=1e-12)
        h = 1e-6
        fd = (_element(0, 0.0, e + h, e + h, 1.0, 100.0, 0.5, NO_Q, NO_TABS)[1]
              - _element(0, 0.0, e - h, e - h, 1.0, 100.0, 0.5, NO_Q, NO_TABS)[1]) / (2 * h)
        assert out[3] == pytest.approx(fd, abs=1e-6)


@pytest.mark.parametrize("z0, de", [(0.0, 0.05), (30.0, 0.02), (30.0, -0.02), (-60.0, -0.1)])
def test_dahl_tangent_is_f_over_x_times_one_minus_sign_z_over_f_and_the_derivative_of_its_force(z0, de):
    """Dahl F_h = 80 N, x_h = 0.4 mm from z0 at e − Δe = 1 − Δe: z = sF + (z0 − sF)·exp(−|Δe|/x_h) (s = sgn Δe, the
    exact step) and dT/de = F_h/x_h·(1 − s·z/F_h), equal to a central difference of the force in e with the start
    held (h = 1e−7 mm, rel 1e−6)."""
    F, xh, e = 80.0, 0.4, 1.0
    s = 1.0 if de > 0 else -1.0
    z_hand = s * F + (z0 - s * F) * math.exp(-abs(de) / xh)
    st, z, _, k, c = _element(1, z0, e, de, 0.0, F, xh, NO_Q, NO_TABS)
    assert st == pytest.approx(z_hand, rel=1e-12) and z == pytest.approx(z_hand, rel=1e-12) and c == 0.0
    assert k == pytest.approx(F / xh * (1.0 - s * z_hand / F), rel=1e-12)
    h = 1e-7
    fd = (_element(1, z0, e + h, de + h, 0.0, F, xh, NO_Q, NO_TABS)[1]
          - _element(1, z0, e - h, de - h, 0.0, F, xh, NO_Q, NO_TABS)[1]) / (2 * h)
    assert k == pytest.approx(fd, rel=1e-6)


def test_stribeck_sticking_has_the_stick_stiffness_as_tangent_and_no_rate_tangent():
    """Stribeck F_c = 50 N, k = 1000 N/mm, ΔF_s = 30 N, v_s = 5 mm/s: at e = 0.01 mm the spring force 10 N is inside
    the band (±(50 + 30·e^(−0.04))), so the slider stays, force 10 N, loss 0, dT/de = 1000 N/mm, dT/dė = 0; a central
    difference in e (h = 1e−7 mm) gives the same slope (rel 1e−6)."""
    q = np.array([30.0, 5.0, 0.0])
    out = _element(2, 0.0, 0.01, 0.01, 1.0, 50.0, 1000.0, q, NO_TABS)
    assert out == pytest.approx((0.0, 10.0, 0.0, 1000.0, 0.0), abs=1e-9)
    h = 1e-7
    fd = (_element(2, 0.0, 0.01 + h, 0.01, 1.0, 50.0, 1000.0, q, NO_TABS)[1]
          - _element(2, 0.0, 0.01 - h, 0.01, 1.0, 50.0, 1000.0, q, NO_TABS)[1]) / (2 * h)
    assert fd == pytest.approx(1000.0, rel=1e-6)


@pytest.mark.parametrize("ev", [-2.0, -6.0])
def test_stribeck_sliding_backwards_has_the_mirrored_rate_tangent_and_no_stiffness(ev):
    """Sliding in −x (e = −10 mm from the slider at 0, ė = ev < 0, dF = 4 N): force −(F_c + ΔF_s·w − dF) with
    w = exp(−(ė/v_s)²), slider at e + (F_c + ΔF_s·w − dF)/k, dT/de = 0 and
    dT/dė = −ΔF_s·w·(−2ė/v_s²) = +2ė·ΔF_s·w/v_s² (< 0 for ė < 0), equal to a central difference in ė
    (h = 1e−5 mm/s, rel 1e−6)."""
    q = np.array([30.0, 5.0, 4.0])
    w = math.exp(-(ev / 5.0) ** 2)
    band = 50.0 + 30.0 * w - 4.0
    y, F, loss, k, c = _element(2, 0.0, -10.0, -10.0, ev, 50.0, 1000.0, q, NO_TABS)
    assert F == pytest.approx(-band, rel=1e-12) and y == pytest.approx(-10.0 + band / 1000.0, rel=1e-12)
    assert loss == pytest.approx(band * (10.0 - band / 1000.0), rel=1e-12)
    assert k == 0.0 and c == pytest.approx(2.0 * ev * 30.0 * w / 25.0, rel=1e-12)
    h = 1e-5
    fd = (_element(2, 0.0, -10.0, -10.0, ev + h, 50.0, 1000.0, q, NO_TABS)[1]
          - _element(2, 0.0, -10.0, -10.0, ev - h, 50.0, 1000.0, q, NO_TABS)[1]) / (2 * h)
    assert c == pytest.approx(fd, rel=1e-6)


@pytest.mark.parametrize("z0, de", [(0.3, 0.01), (0.6, -0.01), (-0.5, 0.01), (-0.5, -0.01)])
def test_bouc_wen_tangent_is_its_shape_law_times_the_initial_slope(z0, de):
    """Bouc–Wen F_y = 200 N, x_y = 0.5 mm, n = 2, r = 0.8 (loading, s·z > 0: h = 1 − z²; unloading, s·z < 0:
    h = 1 − (1 − 2r)·z² = 1 + 0.6·z²): dT/de = F_y/x_y·h(z) at the end state z (force F_y·z), and a central
    difference of the force in e with the start held (h = 1e−5 mm) agrees to rel 5e−3 (the travel table's linear
    interpolation over du = 0.0045 in atanh z)."""
    tabs, q = _bw_tabs(2.0, 0.8), np.array([0.0, 2.0, 0.8])
    F, xy, e = 200.0, 0.5, 1.0
    z, force, _, k, c = _element(3, z0, e, de, 0.0, F, xy, q, tabs)
    s = 1.0 if de > 0 else -1.0
    hz = 1.0 - z * z if s * z > 0 else 1.0 + 0.6 * z * z
    assert force == pytest.approx(F * z, rel=1e-12) and c == 0.0
    assert k == pytest.approx(F / xy * hz, rel=1e-12)
    h = 1e-5
    fd = (_element(3, z0, e + h, de + h, 0.0, F, xy, q, tabs)[1]
          - _element(3, z0, e - h, de - h, 0.0, F, xy, q, tabs)[1]) / (2 * h)
    assert k == pytest.approx(fd, rel=5e-3)


def test_a_play_element_step_follows_the_dead_band_and_carries_nothing():
    """Play of half-width b = 0.5 mm from output 0: e = 0.3 → 0 (inside the band); e = 1.0 → 0.5 (dragged);
    reversal to e = 0.2 → held at 0.5; e = −0.4 → −0.4 + 0.5 = 0.1 (engaged the other way); e = −0.2 → 0.1 (held).
    Force, loss and both tangents are 0 at every step."""
    y = 0.0
    for e, want in [(0.3, 0.0), (1.0, 0.5), (0.2, 0.5), (-0.4, 0.1), (-0.2, 0.1)]:
        out = _element(4, y, e, 0.1, 1.0, 0.0, 0.5, NO_Q, NO_TABS)
        assert out == pytest.approx((want, 0.0, 0.0, 0.0, 0.0), abs=1e-15)
        y = out[0]


def test_each_elements_stored_energy_by_hand():
    """Stored energy at e = 1.3 mm, state s, f = 60, x = 0.4: Jenkins (s = 1.1) 60/0.4·0.2²/2 = 3; Dahl (z = 24 N)
    24²·0.4/(2·60) = 1.92; Stribeck (k = x = 0.4, s = 1.1) 0.4·0.2²/2 = 0.008; Bouc–Wen (z = 0.5) 60·0.4·0.25/2 = 3;
    play 0 (rel 1e−12)."""
    assert _element_energy(0, 1.3, 1.1, 60.0, 0.4) == pytest.approx(3.0, rel=1e-12)
    assert _element_energy(1, 1.3, 24.0, 60.0, 0.4) == pytest.approx(1.92, rel=1e-12)
    assert _element_energy(2, 1.3, 1.1, 60.0, 0.4) == pytest.approx(0.008, rel=1e-12)
    assert _element_energy(3, 1.3, 0.5, 60.0, 0.4) == pytest.approx(3.0, rel=1e-12)
    assert _element_energy(4, 1.3, 1.1, 60.0, 0.4) == 0.0


def test_cycle_losses_equal_the_loop_areas_and_their_closed_forms():
    """Over a closed cycle e = A·sin (A = 1 mm, 400 steps, third cycle) the summed loss equals the numpy area of the
    (e, force) loop and the closed form (the trapezoid area rel 1e−3: the slip starts inside a step): Jenkins
    (f = 100 N, x_s = 0.25 mm) 4f(A − x_s) = 300 N·mm (loss rel 1e−9); Dahl
    (F_h = 80 N, x_h = 0.3 mm) 4F_h(A − x_h·tanh(A/x_h)) (rel 1e−9 for the loss, 1e−3 for the trapezoid area);
    Bouc–Wen with n = 1, r = 1 is Dahl (F_y = 80 N, x_y = 0.3 mm; rel 2e−3); Stribeck at a fixed |ė| = 5 mm/s
    (F_c = 50, ΔF_s = 30, v_s = 5, k = 1000: slip force f = 50 + 30/e) is a Jenkins of travel f/k: 4f(A − f/k)
    (loss rel 1e−9)."""
    A = 1.0
    loss, e, F = _cycle_loss(0, 100.0, 0.25, A)
    assert loss == pytest.approx(300.0, rel=1e-9) and _loop_area(e, F) == pytest.approx(300.0, rel=1e-3)
    dahl = 4.0 * 80.0 * (A - 0.3 * math.tanh(A / 0.3))
    loss, e, F = _cycle_loss(1, 80.0, 0.3, A)
    assert loss == pytest.approx(dahl, rel=1e-9) and _loop_area(e, F) == pytest.approx(dahl, rel=1e-3)
    loss, e, F = _cycle_loss(3, 80.0, 0.3, A, q=np.array([0.0, 1.0, 1.0]), tabs=_bw_tabs(1.0, 1.0))
    assert loss == pytest.approx(dahl, rel=2e-3) and 80.0 * _loop_area(e, F / 80.0) == pytest.approx(dahl, rel=2e-3)
    f = 50.0 + 30.0 / math.e
    loss, e, F = _cycle_loss(2, 50.0, 1000.0, A, q=np.array([30.0, 5.0, 0.0]), v=5.0)
    assert loss == pytest.approx(4.0 * f * (A - f / 1000.0), rel=1e-9)
    assert _loop_area(e, F) == pytest.approx(4.0 * f * (A - f / 1000.0), rel=1e-3)


@pytest.mark.parametrize("u, F, k", [(0.1, 0.0, 0.0), (-0.1, 0.0, 0.0), (0.5, 300.0 * 0.3 ** 1.5, 450.0 * 0.3 ** 0.5),
                                     (-0.6, -300.0 * 0.4 ** 1.5, 450.0 * 0.4 ** 0.5)])
def test_deadband_force_tangent_and_potential_by_hand(u, F, k):
    """Dead band k_d = 300 N/mm^p, g = 0.2 mm, p = 1.5: force k_d·sgn(u)·(|u| − g)^p, tangent k_d·p·(|u| − g)^(p−1),
    potential k_d·(|u| − g)^(p+1)/(p+1), all 0 inside |u| <= g (rel 1e−12); the potential's central difference
    (h = 1e−6 mm) is the force (rel 1e−6), the force's is the tangent; k_d = 0 switches it off."""
    f, kt = deadband(u, 300.0, 0.2, 1.5)
    assert f == pytest.approx(F, rel=1e-12) and kt == pytest.approx(k, rel=1e-12)
    pen = max(abs(u) - 0.2, 0.0)
    assert deadband_energy(u, 300.0, 0.2, 1.5) == pytest.approx(300.0 * pen ** 2.5 / 2.5, rel=1e-12)
    h = 1e-6
    dU = (deadband_energy(u + h, 300.0, 0.2, 1.5) - deadband_energy(u - h, 300.0, 0.2, 1.5)) / (2 * h)
    dF = (deadband(u + h, 300.0, 0.2, 1.5)[0] - deadband(u - h, 300.0, 0.2, 1.5)[0]) / (2 * h)
    assert dU == pytest.approx(F, rel=1e-6, abs=1e-9) and dF == pytest.approx(k, rel=1e-6, abs=1e-9)
    assert deadband(u, 0.0, 0.2, 1.5) == (0.0, 0.0) and deadband_energy(u, 0.0, 0.2, 1.5) == 0.0


def test_a_linear_contact_springs_energy_is_half_a_squared_over_its_compliance():
    """β = 1: x(F) = (c_lin + c_h)·F is linear, so U(a) = a²/(2(c_lin + c_h)): c_lin = 0.01, c_h = 0.02 mm/N,
    a = 0.3 mm → 1.5 N·mm (rel 1e−12); 0 when slack; β = 0.5: U' = F by central difference (rel 1e−6)."""
    assert spring_energy(0.3, 0.01, 0.02, 1.0) == pytest.approx(1.5, rel=1e-12)
    assert spring_energy(-0.3, 0.01, 0.02, 1.0) == 0.0
    # β = 0.5: F solves c_lin·F + c_h·√F = a, √F = (−c_h + √(c_h² + 4c_lin·a))/(2c_lin)
    a, h = 0.3, 1e-6
    r = (-0.02 + math.sqrt(0.02 ** 2 + 4 * 0.01 * a)) / 0.02
    dU = (spring_energy(a + h, 0.01, 0.02, 0.5) - spring_energy(a - h, 0.01, 0.02, 0.5)) / (2 * h)
    assert dU == pytest.approx(r * r, rel=1e-6)


def _play_line(ys0):
    """One segment: a linear contact spring (β = 1, compliance 0.01 + 0.02 mm/N, F = (a)/0.03), slack s = 0.1 mm, no
    dead band, a play of half-width 0.4 mm in column 0 from output ys0, a Jenkins element in column 1."""
    sp = np.array([[1.0, 0.1, 0.0, 0.0, 1.0, 0.0]])
    cl, ch = np.array([0.01]), np.array([0.02])
    hx, hd = np.array([[0.4, 0.1]]), np.array([[4, 0]])
    ys, y = np.array([[ys0, 0.0]]), np.zeros((1, 2))
    return sp, cl, ch, hx, hd, ys, y


def test_a_held_play_keeps_the_springs_argument_and_books_its_force_times_the_travel_as_loss():
    """Play output 1.0 mm held (e moves 1.2 → 1.1, inside ±0.4): a = 1.0 − 0.1 = 0.9 mm, F = 0.9/0.03 = 30 N, the
    column is taken (first element column 1), no spring tangent (the argument did not move), loss F·Δe = 30·(−0.1)
    = −3 N·mm (rel 1e−12)."""
    sp, cl, ch, hx, hd, ys, y = _play_line(1.0)
    f, a, fd, kf, kdb, loss, first = _elastic(0, 1.1, -0.1, ys, y, cl, ch, hx, hd, sp, True)
    assert (a, f, fd, kf, kdb, first) == pytest.approx((0.9, 30.0, 0.0, 0.0, 0.0, 1), rel=1e-12)
    assert y[0, 0] == 1.0 and loss == pytest.approx(-3.0, rel=1e-12)


def test_an_engaging_play_drags_the_argument_and_books_the_held_part_of_the_step():
    """Play output 1.0 mm, e moves 1.2 → 1.6 (Δe = 0.4): the output is dragged to 1.6 − 0.4 = 1.2 mm, a = 1.1 mm,
    F = 1.1/0.03 N, tangent 1/0.03 N/mm; of the step, Δe − Δoutput = 0.2 mm was held at the start's force
    (1.0 − 0.1)/0.03 = 30 N: loss 6 N·mm; an engaged step (1.2 → 1.5 from output 0.8 = 1.2 − 0.4) has no loss and,
    without ``tangent``, no spring tangent (rel 1e−12)."""
    sp, cl, ch, hx, hd, ys, y = _play_line(1.0)
    f, a, fd, kf, kdb, loss, first = _elastic(0, 1.6, 0.4, ys, y, cl, ch, hx, hd, sp, True)
    assert (a, f, kf, first) == pytest.approx((1.1, 1.1 / 0.03, 1.0 / 0.03, 1), rel=1e-12)
    assert y[0, 0] == pytest.approx(1.2, rel=1e-15) and loss == pytest.approx(6.0, rel=1e-12)
    sp, cl, ch, hx, hd, ys, y = _play_line(0.8)
    f, a, fd, kf, kdb, loss, first = _elastic(0, 1.5, 0.3, ys, y, cl, ch, hx, hd, sp, False)
    assert (a, f, kf) == pytest.approx((1.0, 1.0 / 0.03, 0.0), rel=1e-12) and abs(loss) < 1e-12
