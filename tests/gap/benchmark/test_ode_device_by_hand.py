"""The ODE world's device (chainid.gap.benchmark.odedevice) at single states, by hand: every state's time
derivative from the module docstring's equations, the cubic Hermite interpolant, the per-state tolerances, the
static equilibrium of a force-driven device, the relaxed initial states and the parameter range checks.
Units mm, N, s, kg."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.gap.benchmark import odedevice as od
from chainid.gap.benchmark.odedevice import Device

CHATTER = {"k_s": 50.0, "c_s": 0.3, "m_s": 0.1, "F_c": 5.0, "F_s": 6.0, "v_s": 1.0, "v_e": 0.01}


def _all_states_device() -> Device:
    """Friction (F_+ 5, F_− 3, k_t 400), Dahl, Bouc–Wen, play (h 0.2), Maxwell and a chatter slider: 7 states."""
    return Device("linear", k=10.0, m=0.0, c=0.0,
                  effects={"friction": {"F_c": 4.0, "dF": 1.0, "x_s": 0.01}, "hysteresis": {"F_h": 2.0, "x_h": 0.05},
                           "bouc_wen": {"F_y": 3.0, "x_y": 0.1, "n": 2.0, "r": 0.7}, "backlash": {"b": 0.4}},
                  outside={"relaxation": {"k_m": 20.0, "tau_m": 0.5}, "chatter": CHATTER})


def _hand_rates(x: float, v: float, s: list[float]) -> list[float]:
    """Rates of (z_f, z_h, z_b, w, q, y_s, ẏ_s) of :func:`_all_states_device` from the docstring's equations."""
    zf, zh, zb, w, q, ys, vs = s
    slip = 5.0 if v > 0 else 3.0
    out = [400.0 * v * (1 - (abs(zf) / slip) ** 25 if v * zf > 0 else 1.0),
           (v - abs(v) * zh) / 0.05,
           (v - 0.7 * abs(v) * math.copysign(1, zb) * abs(zb) ** 2 - 0.3 * v * abs(zb) ** 2) / 0.1,
           v / 0.2 * (1 - abs(w) ** 25 if v * w > 0 else 1.0),
           20.0 * v - q / 0.5, vs]
    fric = math.tanh(vs / 0.01) * (5.0 + 1.0 * math.exp(-(vs / 1.0) ** 2))
    out.append((50.0 * (x - ys) + 0.3 * (v - vs) - fric) / (0.1 * 1e-3))
    return out


@pytest.mark.parametrize("x, v, s", [
    (0.7, 3.0, [4.9, 0.4, -0.6, 0.9, 1.5, 0.2, -4.0]),  # sliding +x near F_+, the play at its stop
    (-0.3, -2.0, [-2.9, -0.5, 0.8, -0.95, -0.7, 0.1, 0.5]),  # sliding −x near F_−
    (0.1, 1.5, [-3.5, 0.2, 0.3, -0.6, 0.0, -0.2, 0.05]),  # reversal: v·z_f < 0 and v·w < 0 stick fully
])
@pytest.mark.parametrize("off", [0, 2])
def test_every_state_rate_matches_its_equation_at_one_state(x, v, s, off):
    """Chatter by hand at the first point: 50·0.5 + 0.3·7 = 27.1 N spring-dashpot, friction −5 N at ẏ_s = −4:
    ÿ_s = 32.1 / 1e-4 = 3.21e5 mm/s².  Offsets 0 (displacement drive) and 2 (after x, ẋ of the force drive)."""
    dev = _all_states_device()
    assert dev.n_states == 7
    full = np.array([x, v] * (off // 2) + s, dtype=float)
    out = np.zeros(full.size)
    od._rates(x, v, full, off, dev.P, out)
    want = _hand_rates(x, v, s)
    if off == 0 and x == 0.7:
        assert want[6] == pytest.approx(3.21e5, rel=1e-6)
    np.testing.assert_allclose(out[off:], want, rtol=1e-12, atol=1e-12)
    assert np.all(out[:off] == 0.0)


def test_displacement_rhs_reads_the_slider_after_friction_at_offset_zero():
    """Friction then the chatter slider (slots 0 | 1, 2) under a still drive x = 0.4, ẋ = 0: ż_f = 0, ẏ_s = ṡ[1] =
    the slider speed 2, ÿ_s = (50·(0.4 − 0.1) + 0.3·(0 − 2) − tanh(200)·(5 + e^−4)) / 1e-4."""
    dev = Device("linear", k=10.0, m=0.0, c=0.0, effects={"friction": {"F_c": 4.0, "x_s": 0.01}},
                 outside={"chatter": CHATTER})
    t = np.linspace(0.0, 1.0, 11)
    x, v, a = np.full(11, 0.4), np.zeros(11), np.zeros(11)
    out = od._rhs_displacement(np.array([1.0, 0.1, 2.0]), 0.35, 0.0, 0.1, x, v, a, dev.P)
    acc = (15.0 - 0.6 - math.tanh(200.0) * (5.0 + math.exp(-4.0))) / 1e-4
    np.testing.assert_allclose(out, [0.0, 2.0, acc], rtol=1e-12)


def test_force_rhs_is_newton_on_the_play_spring_and_the_states():
    """Linear base k 100, x_ref 0.5, m 2 kg + m_f 0.5 kg, c 0.2, play h = 0.1 at w = 0.5, Maxwell q = 3:
    u = 1.2 − 0.05 = 1.15, F_int = 100·0.65 + 0.2·4 + 3 = 68.8 N; drive 80 N: ẍ = 11.2 / 2.5e-3 = 4480 mm/s²."""
    dev = Device("linear", k=100.0, x_ref=0.5, m=2.0, c=0.2,
                 effects={"backlash": {"b": 0.2}, "fixture_mass": {"m_f": 0.5}},
                 outside={"relaxation": {"k_m": 30.0, "tau_m": 0.25}})
    Fd, Fdd = np.full(5, 80.0), np.zeros(5)
    out = od._rhs_force(np.array([1.2, 4.0, 0.5, 3.0]), 0.1, 0.0, 0.1, Fd, Fdd, dev.P)
    assert out[0] == pytest.approx(4.0, rel=1e-12)
    assert out[1] == pytest.approx(4480.0, rel=1e-12)
    assert out[2] == pytest.approx(4.0 / 0.1 * (1 - 0.5 ** 25), rel=1e-12)  # v·w > 0: play closing
    assert out[3] == pytest.approx(30.0 * 4.0 - 3.0 / 0.25, rel=1e-12)


def test_hermite_interpolant_is_exact_on_a_cubic_and_held_at_the_ends():
    """y = 1 + 2t − t² + 0.5t³ with its exact ẏ on the grid −0.5 + 0.25·i (10 points): a cubic Hermite reproduces it
    between the nodes (to 1e-12), and holds y[0] before the grid and y[-1] from the last node on."""
    t0, h, n = -0.5, 0.25, 10
    tg = t0 + h * np.arange(n)
    y = 1 + 2 * tg - tg ** 2 + 0.5 * tg ** 3
    yd = 2 - 2 * tg + 1.5 * tg ** 2
    for t in (-0.5, -0.3731, 0.0, 0.6234, 1.4999, 1.749):
        assert od._hermite(t, t0, h, y, yd) == pytest.approx(1 + 2 * t - t ** 2 + 0.5 * t ** 3, abs=1e-12)
    assert od._hermite(-0.6, t0, h, y, yd) == y[0]
    assert od._hermite(tg[-1], t0, h, y, yd) == y[-1]
    assert od._hermite(3.0, t0, h, y, yd) == y[-1]


def test_tolerances_per_state_follow_the_force_and_length_scales():
    """States z_f, z_h, q, y_s, ẏ_s: 1e-7·F, 1e-8, 1e-7·F, 1e-9·X and 1e-6·X (X per second, ×1e3)."""
    dev = Device("linear", k=1.0, effects={"friction": {"F_c": 4.0, "x_s": 0.01}, "hysteresis": {"F_h": 1.0,
                 "x_h": 0.1}}, outside={"relaxation": {"k_m": 2.0, "tau_m": 1.0}, "chatter": CHATTER})
    np.testing.assert_allclose(od._atol(dev, 300.0, 2.0), [3e-5, 1e-8, 3e-5, 2e-9, 2e-6], rtol=1e-12)
    plain = Device("linear", k=1.0, effects={"backlash": {"b": 0.1}})
    np.testing.assert_array_equal(od._atol(plain, 300.0, 2.0), [1e-8])


def test_initial_states_put_the_slider_at_the_start_after_the_other_states():
    dev = Device("linear", k=1.0, effects={"friction": {"F_c": 4.0, "x_s": 0.01}}, outside={"chatter": CHATTER})
    assert dev.n_states == 3
    np.testing.assert_array_equal(dev.initial_states(1.75), [0.0, 1.75, 0.0])
    assert Device("linear", k=1.0).n_states == 0
    alone = Device("linear", k=1.0, outside={"chatter": CHATTER})
    np.testing.assert_array_equal(alone.initial_states(-0.5), [-0.5, 0.0])


@pytest.mark.parametrize("F", [-45.0, 0.0, 60.0])
def test_equilibrium_solves_the_static_spring_with_the_cubic(F):
    """k = 10, x_ref = 1, cubic 2·u³ + 0.5·u² about x_m = 1: the real root of 2u³ + 0.5u² + 10u − F (numpy.roots),
    x = 1 + u; the bracket grows from ±1 mm to reach it (−45 N: u = −2.31, x ≈ −1.31)."""
    dev = Device("linear", k=10.0, x_ref=1.0, m=1.0, effects={"hardening": {"k3": 2.0, "k2": 0.5, "x_m": 1.0}})
    r = np.roots([2.0, 0.5, 10.0, -F])
    u = float(r[np.abs(r.imag) < 1e-9].real[0])
    assert od.equilibrium(dev, F) == pytest.approx(1.0 + u, abs=1e-10)


def test_run_force_refuses_a_massless_device_and_a_chatter_slider():
    t = np.linspace(0, 1, 11)
    with pytest.raises(ValueError, match=r"linear base with a moving mass > 0 kg \(got base 'linear', mass 0 kg\)"):
        od.run_force(Device("linear", k=1.0, m=0.0), t, np.ones(11), np.zeros(11), 0.1)
    with pytest.raises(ValueError, match="the chatter slider is a displacement-driven mechanism"):
        od.run_force(Device("linear", k=1.0, m=1.0, outside={"chatter": CHATTER}), t, np.ones(11), np.zeros(11), 0.1)


def test_parameter_vector_holds_the_slip_forces_the_half_play_and_the_total_mass():
    dev = Device("linear", k=3.0, x_ref=0.2, m=1.5, c=0.4,
                 effects={"friction": {"F_c": 4.0, "dF": -1.0, "x_s": 0.02}, "backlash": {"b": 0.3},
                          "fixture_mass": {"m_f": 0.25}})
    P = dev.P
    assert (P[od.FR_KT], P[od.FR_FP], P[od.FR_FM]) == pytest.approx((200.0, 3.0, 5.0), rel=1e-12)
    assert P[od.PL_H] == pytest.approx(0.15) and P[od.MASS] == pytest.approx(1.75)
    assert (P[od.K], P[od.XREF], P[od.C], P[od.LINEAR]) == (3.0, 0.2, 0.4, 1.0)


@pytest.mark.parametrize("effects, outside", [
    ({"hysteresis": {"F_h": 0.0, "x_h": 0.1}}, {}),
    ({"bouc_wen": {"F_y": 1.0, "x_y": 0.1, "n": 8.0, "r": 1.0}}, {}),
    ({"bouc_wen": {"F_y": 1.0, "x_y": 0.1, "n": 0.5, "r": 0.0}}, {}),
    ({"deadband": {"k_d": 0.0, "g": 0.0, "p": 4.0, "x_c": 0.0}}, {}),
    ({"deadband": {"k_d": 1.0, "g": 0.1, "p": 1.0, "x_c": 0.0}}, {}),
    ({"stribeck": {"F_c": 2.0, "F_s": 2.0, "v_s": 1.0, "v_e": 0.01}}, {}),
    ({}, {"chatter": {**CHATTER, "c_s": 0.0, "F_c": 0.0, "F_s": 0.0}}),
    ({}, {"relaxation": {"k_m": 0.0, "tau_m": 1e-6}}),
])
def test_parameters_on_the_edge_of_their_ranges_are_accepted(effects, outside):
    assert Device("linear", k=1.0, effects=effects, outside=outside).P[od.K] == 1.0


@pytest.mark.parametrize("effects, outside, msg", [
    ({"hysteresis": {"F_h": 1.0, "x_h": 0.0}}, {}, "hysteresis.x_h = 0.0 is out of range; valid range > 0"),
    ({"hysteresis": {"F_h": -1.0, "x_h": 0.1}}, {}, "hysteresis.F_h = -1.0 is out of range; valid range >= 0"),
    ({"bouc_wen": {"F_y": 1.0, "x_y": 0.1, "n": 2.0, "r": 1.5}}, {},
     r"bouc_wen.r = 1.5 is out of range; valid range >= 0 and <= 1$"),
    ({"deadband": {"k_d": 1.0, "g": 0.1, "p": 4.5, "x_c": 0.0}}, {},
     r"deadband.p = 4.5 is out of range; valid range >= 1 and <= 4$"),
    ({}, {"relaxation": {"k_m": 1.0, "tau_m": 0.0}}, "relaxation.tau_m = 0.0 is out of range; valid range > 0"),
    ({}, {"chatter": {**CHATTER, "m_s": 0.0}}, "chatter.m_s = 0.0 is out of range; valid range > 0"),
    ({}, {"chatter": {**CHATTER, "v_e": float("nan")}}, "chatter.v_e = nan is out of range; valid range > 0"),
    ({}, {"chatter": {**CHATTER, "k_s": float("inf")}}, "chatter.k_s = inf is out of range; valid range > 0"),
    ({"fixture_mass": {}}, {}, "fixture_mass.m_f = None is out of range; valid range >= 0"),
])
def test_parameters_past_their_ranges_are_refused_naming_field_value_and_range(effects, outside, msg):
    with pytest.raises(ValueError, match=msg):
        Device("linear", k=1.0, effects=effects, outside=outside)


def test_negative_or_nan_damping_is_refused():
    for c in (-0.1, float("nan"), float("inf")):
        with pytest.raises(ValueError, match=r"Device.c = .* N·s/mm is invalid; valid range >= 0"):
            Device("linear", k=1.0, c=c)
    assert Device("linear", k=1.0, c=0.0).P[od.C] == 0.0
