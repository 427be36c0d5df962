"""Where the harmonic residual sits (chainid.gap.harmonic.where): residual harmonics, energy slopes, a force-channel
delay, level, branch and energy per cycle, by hand.  Units N, mm, s."""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from chainid.gap.harmonic.where import classify_slopes, energy_slopes, residual_harmonics

from stand_ins import localise_viscous_excess


def test_residual_harmonics_of_a_known_series():
    """r = 3 + 2 sin ψ + 1.5 cos ψ + 0.5 sin(3ψ + 0.4) on 64 bin centres: mean 3, first harmonic 2 in phase with x
    and 1.5 with ẋ (amplitude 2.5, phase atan2(1.5, 2)), third 0.5 at phase 0.4, none at 2, 4, 5."""
    psi = (np.arange(64) + 0.5) * 2 * math.pi / 64
    h = residual_harmonics(3 + 2 * np.sin(psi) + 1.5 * np.cos(psi) + 0.5 * np.sin(3 * psi + 0.4))
    assert h["mean"] == pytest.approx(3.0, rel=1e-12)
    assert (h["h1_x"], h["h1_xdot"], h["h1"]) == (pytest.approx(2.0), pytest.approx(1.5), pytest.approx(2.5))
    assert h["phase1"] == pytest.approx(math.atan2(1.5, 2.0), rel=1e-12)
    assert (h["h3"], h["phase3"]) == (pytest.approx(0.5, rel=1e-12), pytest.approx(0.4, rel=1e-12))
    assert max(h["h2"], h["h4"], h["h5"]) < 1e-12


def test_energy_slopes_and_their_forms():
    """W = 5·A²·ω exactly gives slopes (2, 1): viscous; W ∝ A gives (1, 0): Coulomb; fewer than 3 positive W: nan."""
    w = np.array([1.0, 2.0, 4.0, 1.0, 2.0, 4.0])
    A = np.array([0.1, 0.1, 0.1, 0.3, 0.3, 0.3])
    s = energy_slopes(w, A, 5 * A**2 * w)
    assert (s["slope_A"], s["slope_omega"]) == (pytest.approx(2.0, abs=1e-9), pytest.approx(1.0, abs=1e-9))
    s = energy_slopes(w, A, 7 * A)
    assert (s["slope_A"], s["slope_omega"]) == (pytest.approx(1.0, abs=1e-9), pytest.approx(0.0, abs=1e-9))
    assert math.isnan(energy_slopes(w, A, np.array([1.0, 1.0, 0.0, 0.0, -1.0, 0.0]))["slope_A"])
    assert [classify_slopes(*p) for p in ((2.1, 0.9), (1.9, 0.2), (1.1, -0.1), (2.8, 0.0), (float("nan"), 1.0))] == [
        "viscous", "hysteretic", "Coulomb", "micro-slip", "undetermined"]


# ---------------------------------------------------------------- where the baseline misses
def test_localise_energy_error_per_cycle_is_the_loop_integral():
    """r = C cos ψ over x = x0 + A sin ψ: the residual's work per cycle ∮ r dx = ∫ C cos ψ · A cos ψ dψ = π·A·C
    (C = 30 N, A = 0.2/0.3/0.4 mm: 18.85/28.27/37.70 N·mm).  Bugs caught: a factor lost (the code had π·A·mean,
    half the integral), A dropped."""
    data, found = localise_viscous_excess()
    per_test = {f["test"]: f["energy_error_Nmm"] for f in found if f.get("kind") == "test"}
    for d in data:
        assert per_test[d.test] == pytest.approx(math.pi * d.A * 30.0, rel=1e-9)


def test_localise_multi_valued_residual_by_hand():
    """At ψ and π − ψ x is the same and ẋ opposite: r − r(mirror) = 2C cos ψ, RMS/2 = C/√2 = 21.21 N.
    Bug caught: the difference not squared."""
    _, found = localise_viscous_excess()
    surf = [f for f in found if f.get("kind") == "surface"]
    assert len(surf) == 1 and surf[0]["multi_valued_N"] == pytest.approx(30.0 / math.sqrt(2), rel=1e-9)


def test_delay_signature_reads_a_pure_lag():
    """The data are the model's force delayed by τ = 2 ms: harmonic k turns by −kωτ, so δ_k/k against ω has slope
    −τ through the origin: τ read back exactly (harmonics 2 and 3, ω = 10, 20, 30 rad/s).
    Bug caught: the harmonic's phase grid k·ψ garbled."""
    from chainid.gap.harmonic.where import delay_signature

    B, tau = 64, 0.002
    psi = (np.arange(B) + 0.5) * 2 * math.pi / B

    def force(shift):
        return 500 * np.sin(psi - shift) + 100 * np.sin(2 * (psi - shift)) + 50 * np.cos(3 * (psi - shift))

    data, model = [], {}
    for i, w in enumerate((10.0, 20.0, 30.0)):
        data.append(SimpleNamespace(test=f"T{i}", omega=w, sigma=0.1, counts=np.full(B, 10.0),
                                    Fbar=force(w * tau)))
        model[f"T{i}"] = force(0.0)
    sig = delay_signature(data, model)
    assert sig["n_points"] == 6
    assert sig["tau_harmonics_s"] == pytest.approx(tau, rel=1e-9)
    assert sig["phase1_slope_s"] == pytest.approx(-tau, rel=1e-9)


def test_delay_signature_fundamental_phase_line_and_its_r2_by_hand():
    """The fundamental's phase of F against x, φ₁ = atan2(b, a) of F = a sin ψ + b cos ψ + …: a lag τ = 2 ms and a
    damping part q cos ψ give a = 500 cos ωτ, b = q − 500 sin ωτ.  The straight line through (ω, φ₁) and its
    R² = 1 − SS_res/SS_tot are a least-squares fit by hand (phases small, SS_tot < 1 rad²)."""
    from chainid.gap.harmonic.where import delay_signature

    B, tau = 64, 0.002
    psi = (np.arange(B) + 0.5) * 2 * math.pi / B
    ws, qs = (10.0, 20.0, 30.0, 40.0), (5.0, 0.0, 8.0, 2.0)
    data, model = [], {}
    for i, (w, q) in enumerate(zip(ws, qs)):
        F = 500 * np.sin(psi - w * tau) + 100 * np.sin(2 * (psi - w * tau)) + q * np.cos(psi)
        data.append(SimpleNamespace(test=f"T{i}", omega=w, sigma=0.1, counts=np.full(B, 10.0), Fbar=F))
        model[f"T{i}"] = 500 * np.sin(psi) + 100 * np.sin(2 * psi)
    w = np.array(ws)
    p1 = np.arctan2(np.array(qs) - 500 * np.sin(w * tau), 500 * np.cos(w * tau))
    X = np.column_stack([w, np.ones(4)])
    (s, c0), *_ = np.linalg.lstsq(X, p1, rcond=None)
    ss = float(np.sum((p1 - p1.mean()) ** 2))
    r2 = 1 - float(np.sum((p1 - X @ [s, c0]) ** 2)) / ss
    assert ss < 1 and 0.5 < r2 < 0.99
    sig = delay_signature(data, model)
    assert sig["phase1_slope_s"] == pytest.approx(s, rel=1e-9)
    assert sig["phase1_intercept_rad"] == pytest.approx(c0, rel=1e-9, abs=1e-12)
    assert sig["phase1_r2"] == pytest.approx(r2, rel=1e-9)
    assert sig["n_points"] == 4 and sig["tau_harmonics_s"] == pytest.approx(tau, rel=1e-9)  # harmonic 2 only
    # two distinct frequencies: no line (nan), no harmonic reading either below two frequencies
    two = delay_signature(data[:2] + [SimpleNamespace(**(vars(data[1]) | {"test": "T9"}))], model | {"T9": model["T1"]})
    assert math.isnan(two["phase1_slope_s"]) and math.isnan(two["phase1_r2"])


def test_localise_names_a_residual_harmonic_above_twice_the_noise_floor():
    """Bin-mean noise floor σ/√n = 1/√10 = 0.316 N: a residual r = C·cos ψ of C = 3 N (above 2 × 0.316 N) is named
    as the fundamental in phase with ẋ with RMS over tests 3 N; C = 0.5 N (below) is not."""
    def found(C):
        return [f for f in localise_viscous_excess(C)[1] if f.get("kind") == "harmonic"]

    named = found(3.0)
    assert [f["component"] for f in named] == ["h1_xdot"] and named[0]["amplitude_N"] == pytest.approx(3.0)
    assert named[0]["finding"] == "residual fundamental in phase with ẋ (damping): RMS over tests 3 N"
    assert found(0.5) == []


def _localise(C=30.0, tau=0.0):
    from chainid.gap.harmonic.where import localise

    B = 64
    psi = (np.arange(B) + 0.5) * 2 * math.pi / B
    data = [SimpleNamespace(test=f"T{i}", sigma=1.0, counts=np.full(B, 10.0), omega=w, A=A, x0=2.0,
                            Fbar=1000.0 + 500.0 * np.sin(psi - w * tau) + C * np.cos(psi))
            for i, (w, A) in enumerate([(10.0, 0.2), (20.0, 0.3), (30.0, 0.4)])]
    base = {"res": {d.test: C * np.cos(psi) for d in data}, "per_test": {d.test: 0.1 * (i + 1) for i, d in
                                                                          enumerate(data)},
            "c_e": {d.test: 1.0 for d in data}}
    prob = SimpleNamespace(data=data, hold=data[:1], train=data[1:], sigma_raw=1.0, ke={d.test: 5000.0 for d in data})
    return {f["kind"]: f for f in localise(prob, base)}, localise(prob, base)


def test_localise_level_branch_and_energy_by_hand():
    """Residual C·cos ψ (C = 30 N) in every test: RMS C/√2 = 21.21 N against a cycle-mean floor σ/√10 = 0.316 N
    (36.5 dB); the loading branch (cos ψ > 0) averages +2C/π, the unloading −2C/π: a difference of 4C/π =
    +38.2 N; c_e = 1 everywhere makes W = π·c_e·ω·A², slopes (2, 1): viscous; no delay (the phase of F is the
    same at every ω)."""
    kinds, found = _localise()
    lv = kinds["level"]
    assert lv["rms_N"] == pytest.approx(30 / math.sqrt(2), rel=1e-9)
    assert lv["noise_floor_N"] == pytest.approx(1 / math.sqrt(10), rel=1e-12)
    assert lv["finding"] == ("baseline residual RMS 21.21 N, 36.5 dB over the cycle-averaged noise floor 0.316 N "
                             "(noise σ = 1 N from cycle-to-cycle scatter)")
    br = kinds["branch"]
    assert br["difference_N"] == pytest.approx(4 * 30 / math.pi, rel=1e-3)
    assert br["finding"].startswith("loading vs unloading branch: mean residual differs by +38.2 N")
    en = kinds["energy"]
    assert (en["slope_A"], en["slope_omega"]) == (pytest.approx(2.0, abs=1e-9), pytest.approx(1.0, abs=1e-9))
    assert "(closest form: viscous;" in en["finding"]
    assert "delay" not in kinds
    tests = [f for f in found if f["kind"] == "test"]
    assert [f["test"] for f in tests] == ["T0", "T1", "T2"]  # all equal RMS: the data's order
    assert tests[0]["finding"].startswith("test T0 (held-out; ω=10 rad/s, A=0.2 mm, x0=2 mm): NRMSE 0.1, residual "
                                          "RMS 21.2 N, signed energy error")
    assert tests[1]["finding"].startswith("test T1 (training;")
    # the energy error per cycle ∮ r dx = π·A·C (a viscous excess dissipates)
    assert [f["energy_error_Nmm"] for f in tests] == pytest.approx([math.pi * A * 30 for A in (0.2, 0.3, 0.4)],
                                                                   rel=1e-9)
    assert [f["score"] for f in found] == sorted((f["score"] for f in found), reverse=True)


def test_localise_names_a_force_channel_lag():
    """F(ψ − ωτ) with τ = 5 ms: the fundamental's phase falls as −ωτ over ω = 10 … 30 rad/s (R² = 1, ωτ_max =
    0.15 >= 0.05): a delay finding with slope −5 ms."""
    kinds, _ = _localise(C=0.0, tau=0.005)
    dl = kinds["delay"]
    assert dl["tau_s"] == pytest.approx(0.005, rel=1e-9) and dl["phase1_r2"] == pytest.approx(1.0, abs=1e-6)
    assert dl["finding"].startswith("delay signature: the phase of F against x falls linearly with ω across tests "
                                    "(slope -5 ms, R² 1.000")
    assert "delay" not in _localise(C=0.0, tau=0.0015)[0]  # ωτ_max = 0.045 < 0.05
    assert "delay" in _localise(C=0.0, tau=0.0017)[0]  # 0.051
