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
