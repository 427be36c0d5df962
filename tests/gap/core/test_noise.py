"""Noise floors of the diagnosis (chainid.gap.core.noise) against closed forms and Monte Carlo: force noise and
quantum, the band and sample rate, the low-pass and the kinematics, a velocity that is 0 at rest.  Units N, mm, s, Hz."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.gap.core import noise, noise as nz


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


@pytest.mark.parametrize("q_over_sigma", [0.0, 0.5, 1.0, 2.0])
def test_noise_floor_of_a_quantised_force(q_over_sigma):
    # a sine of 1 kN plus white noise σ = 10 N, written in steps q: the reference is the standard deviation of
    # what was added (noise + quantisation error), computed here from the known signal
    from chainid.gap.core.noise import force_noise, force_quantum

    rng = np.random.default_rng(5)
    t = np.arange(20000) / 200.0
    sig = 1000.0 * np.sin(2 * np.pi * 0.5 * t)
    F = sig + rng.normal(0.0, 10.0, t.size)
    q = 10.0 * q_over_sigma
    if q:
        F = q * np.round(F / q)
    assert force_quantum(F) == pytest.approx(q, rel=1e-9)
    assert force_noise(F) == pytest.approx(float(np.std(F - sig)), rel=0.06)


def test_force_noise_takes_five_samples_and_refuses_four():
    """``force_noise`` needs >= 5 samples (docstring).  F = (0, 1, 3, 2, 7) N: Δ²F = (1, −3, 6), median 1,
    |Δ²F − 1| = (0, 4, 5), MAD 4, σ = 1.4826·4/√6 (5 distinct values: no quantum)."""
    from chainid.gap.core.noise import force_noise

    assert force_noise(np.array([0.0, 1.0, 3.0, 2.0, 7.0])) == pytest.approx(1.4826 * 4 / math.sqrt(6), rel=1e-12)
    with pytest.raises(ValueError, match=r"force_noise needs >= 5 samples; got 4"):
        force_noise(np.array([0.0, 1.0, 3.0, 2.0]))


@pytest.mark.parametrize("fs,fb", [(200.0, 2.0), (1000.0, 3.0), (100.0, 8.0)])
def test_velocity_noise_matches_a_monte_carlo_of_the_pipeline(fs: float, fb: float) -> None:
    """σ_v from the filter's response against the standard deviation of ẋ of 400 000 samples of pure white
    noise σ_x = 0.01 mm through the same low-pass and central difference (sampling error of that sd below
    1 % for the correlated samples; measured agreement 0.1–0.8 %; 3 % allowed)."""
    rng = np.random.default_rng(7)
    t = np.arange(400000) / fs
    x = 0.01 * rng.normal(size=t.size)
    xs = nz.lowpass(x, fs, nz.CUT_FACTOR * fb)
    v = np.gradient(xs, t)[500:-500]
    assert nz.velocity_noise(x, xs, fs, nz.CUT_FACTOR * fb) == pytest.approx(float(np.std(v)), rel=0.03)


def test_no_displacement_noise_or_no_smoothing_gives_no_floor() -> None:
    t = np.arange(2000) / 200.0
    x = np.sin(2 * np.pi * t)
    assert nz.velocity_noise(x, x.copy(), 200.0, 8.0) == 0.0
    assert nz.velocity_noise(x + 0.01, x, 200.0, 95.0) == 0.0  # cut above 0.45 fs: not smoothed


def test_a_lead_in_at_rest_has_zero_velocity_and_the_motion_keeps_its_own() -> None:
    """2 s at rest, then 8 s of a 1 Hz sine of 0.3 mm; x noise 2e-4 mm.  The rest samples get ẋ = 0 exactly,
    away from the onset and from the record's first sample by the filter's reach (3/f_cut ≈ 0.55 s here: the
    odd extension about a noisy first sample is a step of twice its noise, which the filter turns into a
    ramp of ~10 σ_v); where the true speed exceeds 20 σ_v the smooth speed is within 2 % of it (the
    low-pass passes the 1 Hz line unchanged)."""
    fs = 200.0
    t = np.arange(int(10 * fs)) / fs
    on = t >= 2.0
    x = np.where(on, 0.3 * np.sin(2 * np.pi * (t - 2.0)), 0.0)
    v_true = np.where(on, 0.3 * 2 * np.pi * np.cos(2 * np.pi * (t - 2.0)), 0.0)
    xm = x + 2e-4 * np.random.default_rng(3).normal(size=t.size)
    fb = nz.excitation_band(t, xm)
    xs, xd, _ = nz.kinematics(t, xm, fb)
    rest = (t > 0.6) & (t < 1.4)
    assert np.all(xd[rest] == 0.0)
    v_n = nz.velocity_noise(xm, xs, fs, nz.CUT_FACTOR * fb)
    fast = (np.abs(v_true) > 20 * v_n) & (t > 2.6) & (t < 9.4)  # the filter's reach from onset and end
    assert fast.sum() > 1000
    np.testing.assert_allclose(xd[fast], v_true[fast], rtol=0.02)


def test_noise_edge_cases():
    """Fewer than 8 spectral lines or a displacement with no variation: the band is the Nyquist frequency and
    the record is not called broadband."""
    from chainid.gap.core import noise

    t = np.arange(12) / 100.0
    assert noise.excitation_band(t, np.sin(t)) == pytest.approx(50.0, rel=1e-9)  # 7 lines
    assert noise.is_broadband(t, np.sin(t)) is False
    t = np.arange(200) / 100.0
    assert noise.excitation_band(t, np.zeros(200)) == pytest.approx(50.0, rel=1e-9)  # no variation at all
    assert noise.force_quantum(np.array([1.0, 1.0, 2.0, 2.0, 3.0, 3.0])) == 1.0
    assert noise.force_quantum(np.array([1.0, 2.0, 3.0, 4.0])) == 0.0  # as many values as samples: not quantised
