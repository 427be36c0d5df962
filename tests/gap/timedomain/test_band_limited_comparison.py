"""The band in which a record's force is compared with the model (:mod:`chainid.gap.timedomain.bandlimit`).

* The filter's noise share ρ against the closed form of a 4th-order Butterworth run forward and backward, whose
  power gain is 1/(1 + (f/f_c)⁸)²: ∫₀^∞ df/(1 + (f/f_c)⁸)² = f_c·(1 − 1/8)·π/(8·sin(π/8)), and against white noise
  through the filter.
* The rule: a force-driven device whose motion has fast content the force lacks is compared below ẍ's cut; a
  displacement-driven record (a band-limited motion), a force with content above the cut, and a linear device
  driven by force are compared over the whole band.
* What it is for: a resonant device driven by force with stick–slip friction (the independent ODE world's
  smoothed Jenkins slider), where the whole-band comparison ranked a smooth Dahl hysteresis first; below the cut
  the friction is named, with its parameters and the device's mass within a few per cent of the simulator's.
"""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from chainid.gap.timedomain.bandlimit import band_limited, noise_share, residual_cut

RHO_8 = (1.0 - 1.0 / 8.0) * math.pi / (8.0 * math.sin(math.pi / 8.0))  # ∫₀^∞ dx/(1 + x⁸)²


def test_noise_share_is_the_butterworth_closed_form():
    fs, fc = 2000.0, 50.0
    assert noise_share(fs, fc) == pytest.approx(RHO_8 * fc / (0.5 * fs), rel=0.01)
    assert noise_share(fs, float("nan")) == 1.0


def test_filtered_white_noise_keeps_its_noise_share():
    rng = np.random.default_rng(3)
    fs, fc = 1000.0, 40.0
    e = rng.normal(0.0, 2.0, 200_000)
    got = float(np.var(band_limited(e, fs, fc)[1000:-1000])) / 4.0
    assert got == pytest.approx(noise_share(fs, fc), rel=0.03)


def test_each_run_of_a_view_is_filtered_on_its_own():
    fs, fc = 1000.0, 40.0
    y = np.concatenate([np.full(500, 1.0), np.full(500, -1.0)])
    idx = np.concatenate([np.arange(0, 500), np.arange(2000, 2500)])  # two windows, not adjacent in time
    out = band_limited(y, fs, fc, idx)
    assert np.allclose(out[:500], 1.0, atol=1e-9) and np.allclose(out[500:], -1.0, atol=1e-9)  # no smear across
    assert np.array_equal(band_limited(y, fs, float("nan")), y)


@pytest.mark.parametrize("cols", [(), (3,)])
def test_each_run_matches_scipy_sosfiltfilt_on_its_own(cols):
    """The filter's steady state is solved once per rate and cut, not per run: each run of a view must still be
    exactly (bit for bit) what ``scipy.signal.sosfiltfilt`` (default padding: 15 samples for the 4th-order
    Butterworth) gives it alone; a run of 15 or fewer passes as it is; 1-D and 2-D."""
    from scipy.signal import sosfiltfilt

    from chainid.gap.core.noise import lowpass_sos

    rng = np.random.default_rng(11)
    fs, fc = 1000.0, 40.0
    lengths, gap = [300, 700, 300, 300, 16, 15, 5], 37  # three of one length, the shortest filtered, two passed
    idx = np.concatenate([np.arange(i * 1000 + gap, i * 1000 + gap + n) for i, n in enumerate(lengths)])
    a = rng.normal(0.0, 50.0, (idx.size, *cols)) + 7.0
    out = band_limited(a, fs, fc, idx)
    sos = lowpass_sos(fs, fc, 1 << 12)  # the module's design (its docstring); the reference is scipy's filter
    edges = np.cumsum([0] + lengths)
    for n, i, j in zip(lengths, edges[:-1], edges[1:]):
        want = a[i:j] if n <= 15 else sosfiltfilt(sos, a[i:j], axis=0)
        assert np.array_equal(out[i:j], want), n


def _sines(t: np.ndarray, freqs, amps) -> np.ndarray:
    return sum(a * np.sin(2 * math.pi * f * t + 0.3 * i) for i, (f, a) in enumerate(zip(freqs, amps)))


def test_the_rule_needs_fast_motion_and_a_force_without_it():
    rng = np.random.default_rng(5)
    fs, n = 1000.0, 8192
    t = np.arange(n) / fs
    band = _sines(t, [3.0, 5.0, 8.0], [10.0, 8.0, 6.0])
    F_band = band + rng.normal(0.0, 0.05, n)
    F_fast = band + 3.0 * np.sign(np.sin(2 * math.pi * 5.0 * t)) + rng.normal(0.0, 0.05, n)  # switching friction
    assert residual_cut(F_band, fs, 20.0, 0.05, beyond_a=True) == 20.0
    assert math.isnan(residual_cut(F_band, fs, 20.0, 0.05, beyond_a=False))  # the motion has nothing above
    assert math.isnan(residual_cut(F_fast, fs, 20.0, 0.05, beyond_a=True))  # the force has: information
    assert math.isnan(residual_cut(F_band, fs, 480.0, 0.05, beyond_a=True))  # a cut at Nyquist: nothing to do


@pytest.fixture(scope="module")
def resonant_friction():
    from chainid.gap.benchmark.odeworld import build, world_cases

    case = next(c for c in world_cases() if c["label"] == "single/resonant/chirp/friction@2")
    return build(case)


def test_prepared_records_of_a_force_driven_friction_device_are_compared_below_the_cut(resonant_friction):
    from chainid.gap.timedomain.data import prepare_time

    recs, _, _ = resonant_friction
    for r in recs:
        d = prepare_time(r)
        assert d.f_res == pytest.approx(d.kin.f_cut_a) and 0.0 < d.rho < 1.0, r.test


def test_force_driven_stick_slip_is_named_friction_with_its_parameters(resonant_friction):
    from chainid.gap.diagnose import diagnose

    recs, hold, truth = resonant_friction
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = diagnose(recs, hold, None, quiet=True, effects=["friction", "hysteresis", "bouc_wen"], max_combo=1,
                       uncertainty=False)
    assert res["verdict"] == "friction", res["chain_text"]
    from chainid.gap.timedomain.data import prepare_time

    for r in recs:  # the JSON says in which band each record was compared, and the noise share kept
        d, row = prepare_time(r), res["noise"]["tests"][r.test]
        assert row["compared_below_Hz"] == pytest.approx(d.kin.f_cut_a, rel=1e-12), r.test
        assert row["noise_share"] == pytest.approx(noise_share(d.fs, d.kin.f_cut_a), rel=1e-12), r.test
    p = res["steps"][-1]["params"]
    fr, base = truth["effects"]["friction"], truth["base"]
    assert p["friction.F_c"] == pytest.approx(fr["F_c"], rel=0.02)
    assert p["friction.x_s"] == pytest.approx(fr["x_s"], rel=0.05)
    assert p["mass.m"] == pytest.approx(base["m"], rel=0.01)
    assert res["steps"][-1]["base"]["k"] == pytest.approx(base["k"], rel=0.01)


def _white(n: int, sd: float = 1.0, seed: int = 21) -> np.ndarray:
    return np.random.default_rng(seed).normal(0.0, sd, n)


def _ratio_by_hand(F: np.ndarray, fs: float, f_a: float, sigma: float) -> tuple[float, int]:
    """The docstring's R and N: the mean over the bins above f_a of |rfft(Hann·(F − linear fit))|² / (σ²·Σw²),
    with scipy's detrend for the trend (independent of the module's psd)."""
    from scipy.signal import detrend

    w = np.hanning(F.size)
    P = np.abs(np.fft.rfft(detrend(F, type="linear") * w)) ** 2 / (sigma ** 2 * float(np.sum(w ** 2)))
    above = np.fft.rfftfreq(F.size, 1.0 / fs) > f_a
    return float(np.mean(P[above])), int(above.sum())


@pytest.mark.parametrize("k, kept", [(4.6, True), (5.4, False)])
def test_the_force_is_band_limited_below_five_standard_deviations_of_the_noise_ratio(k, kept):
    """σ chosen so that the ratio R of the force's power above f_a to its white noise sits at 1 + k·√(1.5/N), by
    hand (:func:`_ratio_by_hand`): 4.6 is below the rule's 5 (the cut is f_a), 5.4 above it (the whole band)."""
    fs, f_a = 1000.0, 200.0
    F = _white(4096)
    r1, N = _ratio_by_hand(F, fs, f_a, 1.0)
    sigma = math.sqrt(r1 / (1.0 + k * math.sqrt(1.5 / N)))  # R ∝ 1/σ²
    assert _ratio_by_hand(F, fs, f_a, sigma)[0] == pytest.approx(1.0 + k * math.sqrt(1.5 / N), rel=1e-12)
    got = residual_cut(F, fs, f_a, sigma, beyond_a=True)
    assert (got == f_a) if kept else math.isnan(got)


def test_a_force_of_256_samples_is_judged_and_one_of_255_is_not():
    """White force noise of the stated σ (R ≈ 1): 256 samples at 1 kHz above f_a = 100 Hz are 103 bins, enough
    (>= 64), so the cut is f_a; 255 samples are too short a record for the test (NaN)."""
    F = _white(256)
    assert _ratio_by_hand(F, 1000.0, 100.0, 1.0)[1] == 103
    assert residual_cut(F, 1000.0, 100.0, 1.0, beyond_a=True) == 100.0
    assert math.isnan(residual_cut(F[:255], 1000.0, 100.0, 1.0, beyond_a=True))


def test_the_force_test_needs_64_bins_above_the_cut():
    """1024 samples at 1024 Hz have bins at every whole Hz up to 512: above 448 Hz lie 449 … 512, 64 bins (judged),
    above 449 Hz 63 (not judged: NaN); both cuts are below 0.45·fs = 460.8 Hz."""
    F = _white(1024)
    assert _ratio_by_hand(F, 1024.0, 448.0, 1.0)[1] == 64 and _ratio_by_hand(F, 1024.0, 449.0, 1.0)[1] == 63
    assert residual_cut(F, 1024.0, 448.0, 1.0, beyond_a=True) == 448.0
    assert math.isnan(residual_cut(F, 1024.0, 449.0, 1.0, beyond_a=True))


def test_no_cut_at_zero_at_045_fs_or_without_a_noise_level():
    """The cut must lie strictly inside (0, 0.45·fs) and σ must be positive: f_a = 0, f_a = 450 Hz at 1 kHz and
    σ = 0 all give NaN on a white force that f_a = 449 Hz with σ = 1 judges band-limited (σ = 0 without dividing
    by it: no warning)."""
    F = _white(8192)
    assert residual_cut(F, 1000.0, 449.0, 1.0, beyond_a=True) == 449.0
    assert math.isnan(residual_cut(F, 1000.0, 450.0, 1.0, beyond_a=True))
    assert math.isnan(residual_cut(F, 1000.0, 0.0, 1.0, beyond_a=True))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert math.isnan(residual_cut(F, 1000.0, 100.0, 0.0, beyond_a=True))
