"""Pins of the gap layer's signal helpers to closed forms and to other methods (issue 20 §5): residual harmonics,
energy slopes, the force-noise and quantum estimators, the band edge, the high-frequency floor, the low-pass and
kinematics, the broadband test, the leave-one-out law fit and the mechanism names.

Units: N, s, mm, Hz.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.gap.core import interpret
from chainid.gap.harmonic import law_choice
from chainid.gap.core import noise
from chainid.gap.harmonic.where import classify_slopes, energy_slopes, residual_harmonics


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


def test_force_noise_of_white_noise_on_a_parabola():
    """1.4826·MAD(Δ²F)/√6 is σ for white noise (Δ² of a parabola is a constant, removed by the median): σ = 2 N
    from 20000 samples within 3 %; too few samples are refused."""
    rng = np.random.default_rng(4)
    t = np.linspace(0.0, 1.0, 20000)
    F = 100 + 50 * t * t + 2.0 * rng.normal(size=t.size)
    assert noise.force_quantum(F) == 0.0
    assert noise.force_noise(F) == pytest.approx(2.0, rel=0.03)
    # by hand: second differences −3, −1, 1, 3 (repeated) have median 0 and MAD 2: σ = 1.4826·2/√6
    F = np.cumsum(np.cumsum(np.tile([-3.0, -1.0, 1.0, 3.0], 50)))
    assert noise.force_noise(np.concatenate([[0.0, 0.0], F])) == pytest.approx(1.4826 * 2 / math.sqrt(6), rel=1e-12)
    with pytest.raises(ValueError, match=">= 5 samples"):
        noise.force_noise(F[:4])


def test_force_quantum_and_quantised_noise():
    """A channel printing whole multiples of q = 0.8 N plus an offset 0.3 N: q is found exactly; the quantised
    white noise (σ = 2 N, q/σ = 0.4) still gives σ within 5 % (the rounding adds only q²/12)."""
    rng = np.random.default_rng(5)
    F = 0.3 + 0.8 * np.round((50 + 2.0 * rng.normal(size=20000)) / 0.8)
    assert noise.force_quantum(F) == pytest.approx(0.8, rel=1e-9)
    assert noise.force_noise(F) == pytest.approx(math.sqrt(4.0 + 0.8**2 / 12), rel=0.05)
    assert noise.force_quantum(np.array([1.0, 2.0, 3.5, 1.0, 2.0, 3.5, 1.0])) == 0.0  # gaps 1, 1.5: not a lattice


def test_sample_rate_band_and_floor():
    """500 Hz sampling; a 3 Hz sine has its band edge at 3 Hz (within one FFT bin, 500/10000 Hz); white noise
    of σ = 1.5 N has the high-frequency floor σ within 5 %; a decreasing clock is refused."""
    t = np.arange(10000) / 500.0
    assert noise.sample_rate(t) == pytest.approx(500.0, rel=1e-9)
    with pytest.raises(ValueError, match="increasing"):
        noise.sample_rate(t[::-1])
    assert noise.excitation_band(t, 2.0 + 0.5 * np.sin(2 * math.pi * 3.0 * t)) == pytest.approx(3.0, abs=0.06)
    rng = np.random.default_rng(6)
    assert noise.hf_floor(t, 1.5 * rng.normal(size=t.size), 3.0) == pytest.approx(1.5, rel=0.05)
    assert math.isnan(noise.hf_floor(t[:40], rng.normal(size=40), 60.0))  # fewer than 8 bins above 240 Hz


def test_lowpass_and_kinematics():
    """The zero-phase low-pass keeps a 1 Hz sine (gain 1 to 1e-3, no phase) and removes a 60 Hz one (4th order
    at 4 Hz: gain (4/60)^8 twice); kinematics give ẋ, ẍ of the sine within 1 % away from the ends; at/above
    0.45 fs or under 30 samples the filter is the identity."""
    fs = 500.0
    t = np.arange(5000) / fs
    slow = np.sin(2 * math.pi * t)
    y = noise.lowpass(slow + 0.5 * np.sin(2 * math.pi * 60 * t), fs, 4.0)
    mid = slice(500, -500)
    np.testing.assert_allclose(y[mid], slow[mid], atol=2e-3)
    xs, xd, xdd = noise.kinematics(t, 2.0 + slow, 1.0)
    w = 2 * math.pi
    np.testing.assert_allclose(xd[mid], w * np.cos(w * t[mid]), atol=0.01 * w)
    np.testing.assert_allclose(xdd[mid], -w * w * np.sin(w * t[mid]), atol=0.01 * w * w)
    z = np.arange(29.0)
    assert np.array_equal(noise.lowpass(z, fs, 4.0), z)
    assert np.array_equal(noise.lowpass(slow, fs, 0.45 * fs), slow)


def test_is_broadband():
    """One sine (even with a slow trend) is not broadband; band-limited noise is."""
    t = np.arange(8000) / 200.0
    assert noise.is_broadband(t, 0.01 * t + np.sin(2 * math.pi * 2.0 * t)) is False
    assert noise.is_broadband(t, np.random.default_rng(7).normal(size=t.size)) is True


def test_fit_loo_against_brute_force_refits():
    """Leave-one-out predictions by the leverage formula equal the refits without each test (another method)."""
    rng = np.random.default_rng(8)
    X = np.column_stack([np.ones(9), rng.uniform(1, 4, 9), rng.uniform(0.1, 0.5, 9)])
    c = X @ [1.0, 2.0, 3.0] + 0.1 * rng.normal(size=9)
    p, loo = law_choice.fit_loo(X, c)
    np.testing.assert_allclose(p, np.linalg.lstsq(X, c, rcond=None)[0], rtol=1e-12)
    for i in range(9):
        keep = np.arange(9) != i
        pi = np.linalg.lstsq(X[keep], c[keep], rcond=None)[0]
        assert loo[i] == pytest.approx(X[i] @ pi, rel=1e-9)
    assert law_choice.allowed(4) == [k for k in law_choice.allowed(99) if k != "polynomial"]
    assert law_choice.allowed(2) == ["viscous", "coulomb", "hysteretic"]  # 1 coefficient <= 2 − 1


def test_mechanism_names_and_separating_tests():
    assert interpret.mechanism("friction+backlash+slack", "") == "friction+play+displacement offset"
    assert interpret.mechanism("stiffness_level+contact_law", "") == "stiffness"
    assert interpret.mechanism("hysteresis", "Dahl friction (x_h << A)") == "friction"
    assert interpret.mechanism("hysteresis", "") == "hysteresis"
    assert interpret.mechanism("none", "") == "none" and interpret.mechanism("unexplained", "") == "unexplained"
    assert interpret.separating_test("hysteresis", "friction").startswith("a small-amplitude test")
    assert "frequency range" in interpret.separating_test("sensor_delay", "friction")
    assert "amplitude range" in interpret.separating_test("damping_law", "slack")
    assert "mean-load range" in interpret.separating_test("slack", "stiffness_level")


def test_benchmark_family_rates_by_hand():
    """Twelve hand-made cases, every rate counted by hand: singles scored from SNR_MIN (3) on, machine_compliance
    named stiffness_level is right; compounds: both named / exact / named-or-confounded / detectable; controls;
    outside cases (an error is a miss); the median shrinkage of the right verdicts; the misses."""
    from chainid.gap.benchmark.report import family_rates

    def row(family, truth, verdict, snr=5.0, shrinkage=None, **kw):
        return {"family": family, "truth": truth, "verdict": verdict, "snr": snr, "shrinkage": shrinkage,
                "seconds": 2.0, **kw}

    rows = [row("single", ["friction"], "friction", 5.0, 0.6), row("single", ["machine_compliance"],
            "stiffness_level", 4.0, 0.8), row("single", ["backlash"], "hysteresis", 10.0, 0.7),
            row("single", ["slack"], "none", 1.0),
            row("mismatch", ["stiffness_level"], "stiffness_level", 5.0, 0.5),
            row("mismatch+", ["stiffness_level", "friction"], "friction+stiffness_level", 6.0, 0.9),
            row("pair", ["friction", "sensor_delay"], "friction", 6.0, 0.4,
                confounded=[["friction", "friction+sensor_delay"]]),
            row("pair", ["hysteresis", "slack"], "hysteresis+slack+backlash", 8.0, 0.3, effect_snr=[2.0, 5.0]),
            row("control", [], "none", 0.5), row("control", [], "friction", 0.5),
            row("outside", ["drift"], "unexplained", truth_named=[]),
            row("outside", ["chatter"], "friction", truth_named=["friction"], chatter=True),
            row("outside", ["relaxation"], "error: ValueError: boom", truth_named=[])]
    r = family_rates(rows)
    assert (r["n_cases"], r["single_n"], r["single_n_all"], r["single_right_rate"]) == (13, 3, 4, 2 / 3)
    assert (r["mismatch_right_rate"], r["mismatch_n"]) == (1.0, 1)
    assert (r["compound_n"], r["compound_both_named_rate"], r["compound_exact_rate"]) == (3, 2 / 3, 1 / 3)
    assert r["compound_named_or_confounded_rate"] == 1.0
    assert (r["compound_detectable_n"], r["compound_detectable_both_named_rate"]) == (2, 0.5)
    assert (r["mismatch_plus_both_named_rate"], r["pair_both_named_rate"]) == (1.0, 0.5)
    assert (r["control_none_rate"], r["control_n"]) == (0.5, 2)
    assert (r["outside_not_named_rate"], r["outside_n"]) == (2 / 3, 3)
    assert r["outside_verdicts"] == {"error: ValueError: boom": 1, "friction": 1, "unexplained": 1}
    assert (r["chatter_reported_rate"], r["chatter_n"]) == (1.0, 1)
    assert [e["error"] for e in r["errors"]] == ["error: ValueError: boom"]
    assert r["median_shrinkage_when_right"] == pytest.approx(0.7)  # of 0.6, 0.8, 0.5, 0.9
    assert r["median_seconds"] == 2.0
    assert [(m["family"], m["verdict"]) for m in r["misses"]] == [
        ("single", "hysteresis"), ("pair", "friction"), ("pair", "hysteresis+slack+backlash"),
        ("control", "friction"), ("outside", "error: ValueError: boom")]
    assert r["confusion"]["backlash"]["hysteresis"] == 1 and r["confusion"]["none"] == {
        **{v: 0 for v in r["confusion"]["none"]}, "none": 1, "friction": 1}
    assert r["confusion"]["machine_compliance"]["stiffness_level"] == 1


def test_prepare_test_bins_and_noise_of_a_clean_record():
    """x = 2 + 0.3 sin(2π t + π/40) sampled 40 times a cycle over 12 cycles, F = 1000·(x − 0.5) + white noise σ = 2 N:
    ω = 2π, A = 0.3, x0 = 2; B = max(8, min(n_bins, 4·(40 // 8))) = 20 bins (8 with n_bins = 8) of equal counts;
    the bin means are F at the bins' mean x within the noise; σ = 2 N within 15 %."""
    from chainid.gap.harmonic.prepare import prepare_test
    from chainid.records.record import Record

    t = np.arange(12 * 40) / 40.0
    x = 2.0 + 0.3 * np.sin(2 * math.pi * t + math.pi / 40)  # samples half a step off the bin edges
    F = 1000.0 * (x - 0.5) + 2.0 * np.random.default_rng(9).normal(size=t.size)
    d = prepare_test(Record("P", t, x, F))
    assert d.test == "P" and d.counts.size == 20 and np.ptp(d.counts) == 0
    assert (d.omega, d.A, d.x0) == (pytest.approx(2 * math.pi, rel=1e-6), pytest.approx(0.3, rel=1e-6),
                                    pytest.approx(2.0, rel=1e-9))
    np.testing.assert_allclose(d.Fbar, 1000.0 * (d.binmean(d.x_meas) - 0.5), atol=4 * 2.0 / math.sqrt(d.counts[0]))
    assert d.sigma == pytest.approx(2.0, rel=0.15)
    assert d.t[0] >= 0 and np.all(np.diff(d.t) > 0)
    assert prepare_test(Record("P", t, x, F), n_bins=8).counts.size == 8
