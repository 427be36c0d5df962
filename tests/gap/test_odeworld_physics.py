"""The ODE world's devices against closed forms: a mass–spring–damper's exact frequency response, the loop areas of
Dahl, Bouc–Wen and Jenkins friction under a slow sine, the play's plateau, the Stribeck law at steady sliding, the
end stops and the cubic spring, and the force and displacement drives agreeing on one device."""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from chainid.gap.benchmark import odeshapes as sh
from chainid.gap.benchmark.odedevice import Device, run_displacement, run_force

A = 0.2  # mm, amplitude of the slow sines
F_SINE = 0.5  # Hz


def _slow_sine_loop(effects: dict, k: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """x, F over the last full cycle of a 0.5 Hz sine of amplitude A on a linear base (no mass, no damping)."""
    s = sh.harmonic(500.0, 5000, F_SINE)
    dev = Device("linear", k=k, m=0.0, c=0.0, effects=effects)
    tr = run_displacement(dev, s.t, A * s.y, A * s.yd, A * s.ydd, 1.0 / s.fs)
    per = int(round(s.fs * s.over / F_SINE))
    return tr.x[-per - 1:], tr.F[-per - 1:]


def _area(x: np.ndarray, F: np.ndarray) -> float:
    """∮F dx [N·mm] by the trapezoid rule (counter-clockwise positive: energy taken from the drive)."""
    return float(np.sum(0.5 * (F[1:] + F[:-1]) * np.diff(x)))


def test_mass_spring_damper_under_a_multisine_follows_its_exact_frequency_response():
    rng = np.random.default_rng(3)
    fs, n, periods = 2000.0, 8000, 4
    s = sh.multisine(fs, n, 20.0, 100.0, periods, rng, pre_periods=3)
    m, k, c = 2.0, 200.0, 0.06  # kg, N/mm, N·s/mm: f_n = 50 Hz, ζ ≈ 0.03, inside the band
    dev = Device("linear", k=k, x_ref=1.0, m=m, c=c)
    tr = run_force(dev, s.t, 500.0 + 100.0 * s.y, 100.0 * s.yd, 1.0 / fs)
    idx = s.record_index
    P = n // periods
    X, F = np.fft.rfft(tr.x[idx][-P:]), np.fft.rfft(tr.F[idx][-P:])
    lines = np.round(np.array(s.info["lines_hz"]) * P / fs).astype(int)
    w = 2 * np.pi * lines * fs / P
    H = 1.0 / (k - m * w * w * 1e-3 + 1j * c * w)  # mm/N, m·ẍ·1e-3 = N
    assert np.max(np.abs(X[lines] / F[lines] - H) / np.abs(H)) < 1e-5
    assert float(np.mean(tr.x[idx])) == pytest.approx(1.0 + 500.0 / k, abs=1e-6)  # static preload 2.5 mm


def test_dahl_loop_area_under_a_slow_sine_is_4_F_h_times_A_minus_x_h_tanh():
    F_h, x_h = 30.0, 0.05
    x, F = _slow_sine_loop({"hysteresis": {"F_h": F_h, "x_h": x_h}})
    ref = 4 * F_h * (A - x_h * math.tanh(A / x_h))  # closed form of the steady Dahl loop
    assert _area(x, F) == pytest.approx(ref, rel=1e-4)
    assert F.max() == pytest.approx(F_h * math.tanh(A / x_h), rel=1e-5)


@pytest.mark.parametrize("n", [1.0, 3.0])
def test_bouc_wen_loop_area_matches_the_quadrature_of_its_branch(n):
    """r = 1: on the rising branch dx = x_y·dz/(1 − sgn(z)|z|^n); the travel 2A fixes the peak z_m and the loop
    area is 2·F_y·∫ z dx over the branch (scipy quad, independent of the ODE)."""
    F_y, x_y = 30.0, 0.05

    def g(z: float) -> float:
        return x_y / (1.0 - math.copysign(abs(z) ** n, z))
    def integral(f, zm: float) -> float:  # split at the kink z = 0
        return quad(f, -zm, 0.0, epsabs=1e-13, limit=200)[0] + quad(f, 0.0, zm, epsabs=1e-13, limit=200)[0]
    z_m = brentq(lambda zm: integral(g, zm) - 2 * A, 1e-6, 1 - 1e-12, xtol=1e-14)
    ref = 2 * F_y * integral(lambda z: z * g(z), z_m)
    x, F = _slow_sine_loop({"bouc_wen": {"F_y": F_y, "x_y": x_y, "n": n, "r": 1.0}})
    assert _area(x, F) == pytest.approx(ref, rel=1e-4)
    assert F.max() == pytest.approx(F_y * z_m, rel=1e-4)


def test_jenkins_friction_loop_energy_is_4_F_c_A_and_its_plateaus_carry_the_asymmetry():
    F_c, dF, x_s = 50.0, 10.0, 2e-4  # N, N, mm: a stick travel of 1e-3 A
    x, F = _slow_sine_loop({"friction": {"F_c": F_c, "dF": dF, "x_s": x_s}})
    # parallelogram: height (F_c + dF) + (F_c − dF) = 2 F_c, sloped sides 2·x_s wide
    assert _area(x, F) == pytest.approx(4 * F_c * (A - x_s), rel=2e-4)
    assert _area(x, F) == pytest.approx(4 * F_c * A, rel=2e-3)
    assert F.max() == pytest.approx(F_c + dF, rel=1e-6)
    assert F.min() == pytest.approx(-(F_c - dF), rel=1e-6)


def test_play_holds_the_force_over_the_dead_band():
    k, b = 100.0, 0.05
    x, F = _slow_sine_loop({"backlash": {"b": b}}, k=k)
    assert F.max() == pytest.approx(k * (A - b / 2), rel=1e-4)  # the spring sees x − b/2 at the top
    # where the force crosses zero the branches are b apart: u = x − b/2 rising, x + b/2 falling
    i = np.flatnonzero(np.diff(np.sign(F)) != 0)
    xz = x[i] - F[i] * (x[i + 1] - x[i]) / (F[i + 1] - F[i])
    rising = np.diff(x)[i] > 0
    assert float(xz[rising].mean() - xz[~rising].mean()) == pytest.approx(b, rel=1e-4)
    # loop: u = x − b/2 rising, x + b/2 falling: ∮k·u dx = −k·b·2(A − b/2)
    assert _area(x, F) == pytest.approx(-2 * k * b * (A - b / 2), rel=1e-3)


def test_stribeck_force_at_steady_sliding_follows_the_law():
    F_c, F_s, dF, v_s, c = 40.0, 80.0, 5.0, 2.0, 0.5
    dev = Device("linear", k=0.0, m=0.0, c=c, effects={"stribeck": {"F_c": F_c, "F_s": F_s, "dF": dF, "v_s": v_s,
                                                                     "v_e": 0.01}})
    t = np.linspace(0.0, 1.0, 1001)
    for v0 in (0.5, 2.0, -3.0):
        tr = run_displacement(dev, t, v0 * t, np.full_like(t, v0), np.zeros_like(t), 0.01)
        law = math.copysign(F_c + (F_s - F_c) * math.exp(-(v0 / v_s) ** 2), v0) + dF + c * v0
        assert tr.F[-1] == pytest.approx(law, rel=1e-9)


def test_end_stops_and_cubic_spring_at_hand_computed_points():
    dev = Device("linear", k=10.0, x_ref=1.0, m=0.0, c=0.0,
                 effects={"deadband": {"k_d": 50.0, "g": 0.3, "p": 2.0, "x_c": 2.0},
                          "hardening": {"k3": 4.0, "k2": 1.5, "x_m": 2.0}})
    x = np.array([1.5, 2.0, 2.2, 2.5, 3.0])
    tr = run_displacement(dev, np.linspace(0, 1, 5), x, np.zeros(5), np.zeros(5), 0.1)
    u = x - 2.0
    ref = 10.0 * (x - 1.0) + 50.0 * np.sign(u) * np.maximum(np.abs(u) - 0.3, 0) ** 2 + 4.0 * u ** 3 + 1.5 * u ** 2
    # by hand at x = 1.5: 5 + 50·(−1)·0.2² + 4·(−0.125) + 1.5·0.25 = 5 − 2 − 0.5 + 0.375
    assert ref[0] == pytest.approx(2.875)
    np.testing.assert_allclose(tr.F, ref, rtol=1e-12)


def test_force_and_displacement_drives_agree_on_one_hysteretic_resonator():
    """x(t) of the force-driven device, fed to the displacement drive (its states integrated again from the
    interpolated motion), gives back the drive force."""
    rng = np.random.default_rng(7)
    s = sh.filtered_noise(2000.0, 4000, 15.0, 90.0, 0.2, rng, rest=0.05)
    dev = Device("linear", k=150.0, x_ref=0.0, m=1.5, c=0.05,
                 effects={"hysteresis": {"F_h": 8.0, "x_h": 0.1}, "friction": {"F_c": 5.0, "x_s": 0.01}})
    tr = run_force(dev, s.t, 200.0 + 60.0 * s.y, 60.0 * s.yd, 1.0 / 2000.0)
    back = run_displacement(dev, tr.t, tr.x, tr.v, tr.a, 1.0 / 2000.0)
    assert float(np.max(np.abs(back.F - tr.F))) < 1e-3 * float(np.ptp(tr.F))
    assert float(np.ptp(tr.x)) > 0.5  # it moved (mm)


def test_a_chain_base_is_refused_by_the_force_drive():
    from chainid.chain.spec import default_chain

    dev = Device("chain", chain=default_chain(), c=1.0)
    t = np.linspace(0, 1, 11)
    with pytest.raises(ValueError, match="run_force needs a linear base"):
        run_force(dev, t, np.ones(11), np.zeros(11), 0.1)


def test_bad_friction_parameters_are_refused_with_the_field():
    with pytest.raises(ValueError, match=r"friction .*valid F_c > 0 N, x_s > 0 mm"):
        Device("linear", k=1.0, effects={"friction": {"F_c": 5.0, "dF": 6.0, "x_s": 0.01}})
    with pytest.raises(ValueError, match=r"Device.base = 'rubber' is invalid; valid: chain, linear"):
        Device("rubber")
    with pytest.raises(ValueError, match=r"bouc_wen.n = 9.0 is out of range; valid range >= 0.5 and <= 8"):
        Device("linear", k=1.0, effects={"bouc_wen": {"F_y": 1.0, "x_y": 0.1, "n": 9.0, "r": 0.5}})
    with pytest.raises(ValueError, match=r"backlash.b = 0.0 is out of range; valid range > 0"):
        Device("linear", k=1.0, effects={"backlash": {"b": 0.0}})
    with pytest.raises(ValueError, match=r"stribeck.F_s = 1.0 is out of range; valid range >= F_c = 2.0 N"):
        Device("linear", k=1.0, effects={"stribeck": {"F_c": 2.0, "F_s": 1.0, "v_s": 1.0, "v_e": 0.01}})


@pytest.mark.parametrize("f_hi, fs", [(20.0, 1000.0), (60.0, 1000.0)])
def test_outside_mechanisms_by_hand(f_hi, fs):
    """The ODE world's chatter is a stick-slip contact on a structure of stiffness k tuned 3–5 times above the band
    top (at most fs/5), 2 % damped: ω_s² = k_s/m_s (N/mm → N/m: ×1e3) and ζ = c_s/(2√(k_s·m_s)) (c_s N·s/mm);
    static friction twice the sliding one, F_c = 0.05·level·S; relaxation k_m = 0.2·level·k; drift 0.1·level·S."""
    from chainid.gap.benchmark.odecases import outside_params

    sc = {"S": 400.0, "k": 2000.0, "v": 30.0, "f_hi": f_hi, "fs": fs}
    p = outside_params("chatter", 1.5, sc, np.random.default_rng(4))
    assert min(3.0 * f_hi, fs / 5.0) <= p["f_s"] <= min(5.0 * f_hi, fs / 5.0)
    assert math.sqrt(p["k_s"] * 1e3 / p["m_s"]) == pytest.approx(2 * math.pi * p["f_s"], rel=1e-12)
    assert p["c_s"] * 1e3 / (2 * math.sqrt(p["k_s"] * 1e3 * p["m_s"])) == pytest.approx(0.02, rel=1e-12)
    assert p["F_c"] == pytest.approx(0.05 * 1.5 * 400.0) and p["F_s"] == pytest.approx(2 * p["F_c"])
    assert p["v_s"] == pytest.approx(0.2 * 30.0) and p["v_e"] == pytest.approx(p["v_s"] / 50.0)
    assert outside_params("relaxation", 0.5, sc, np.random.default_rng(0))["k_m"] == pytest.approx(200.0)
    assert outside_params("drift", 2.0, sc, np.random.default_rng(0)) == {"total": pytest.approx(80.0)}
    with pytest.raises(ValueError, match="valid: relaxation, drift, chatter"):
        outside_params("creep", 1.0, sc, np.random.default_rng(0))


def test_relaxation_is_a_maxwell_element_whose_loop_area_is_its_loss_modulus():
    """Outside mechanism ``relaxation``: a spring k_m in series with a dashpot of time constant τ_m (Maxwell:
    Ḟ = k_m·ẋ − F/τ_m).  Under x = A·sin ωt its steady stiffness is k_m·iωτ/(1 + iωτ), so one cycle takes
    π·A²·k_m·ωτ/(1 + (ωτ)²) from the drive and the force peaks at A·k_m·ωτ/√(1 + (ωτ)²)."""
    k_m, tau = 50.0, 0.3
    s = sh.harmonic(500.0, 5000, F_SINE)
    dev = Device("linear", k=0.0, m=0.0, c=0.0, outside={"relaxation": {"k_m": k_m, "tau_m": tau}})
    tr = run_displacement(dev, s.t, A * s.y, A * s.yd, A * s.ydd, 1.0 / s.fs)
    per = int(round(s.fs * s.over / F_SINE))
    x, F = tr.x[-per - 1:], tr.F[-per - 1:]
    wt = 2 * math.pi * F_SINE * tau
    assert _area(x, F) == pytest.approx(math.pi * A * A * k_m * wt / (1 + wt * wt), rel=1e-4)
    assert F.max() == pytest.approx(A * k_m * wt / math.sqrt(1 + wt * wt), rel=1e-4)


def test_every_state_and_parameter_slot_of_a_device_is_its_own():
    """The device's parameter vector holds each effect's numbers and each state's index in its own slot: two names
    on one slot would make one effect's state the other's."""
    from chainid.gap.benchmark import odedevice as od

    names = [n for n in dir(od) if n.isupper() and isinstance(getattr(od, n), int) and n != "N_P"]
    slots = sorted(getattr(od, n) for n in names)
    assert slots == list(range(od.N_P)), sorted(zip(slots, names))  # every slot once, none past the vector


def test_internal_force_reads_each_state_from_its_own_slot_with_chatter_after_friction():
    """With friction and a chatter slider on one device, the slider's states follow the friction's (slots 0 | 1, 2);
    the internal force is z + k_s·(x − y_s) + c_s·(ẋ − ẏ_s) + c·ẋ by hand, on the state vector alone (offset 0) and
    after x, ẋ (offset 2), with distinct numbers in every slot so a state read from another slot shows."""
    from chainid.gap.benchmark import odedevice as od

    ch = {"k_s": 50.0, "c_s": 0.3, "m_s": 0.1, "F_c": 5.0, "F_s": 6.0, "v_s": 1.0, "v_e": 0.01}
    dev = Device("linear", k=10.0, m=0.0, c=0.2, effects={"friction": {"F_c": 4.0, "x_s": 0.01}},
                 outside={"chatter": ch})
    P = dev.P
    assert (P[od.I_ZF], P[od.I_YS]) == (0, 1)
    x, v, z, ys, vs = 0.7, 3.0, 1.5, 0.2, -4.0
    want = z + 50.0 * (x - ys) + 0.3 * (v - vs) + 0.2 * v
    F, _ = od._forces(np.array([x]), np.array([v]), np.array([[z, ys, vs]]), 0, P)
    assert F[0] == pytest.approx(want, rel=1e-12)
    assert od._internal(x, v, np.array([x, v, z, ys, vs]), 2, P) == pytest.approx(want, rel=1e-12)
