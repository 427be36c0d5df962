"""The force noise read again from a fitted chain's residual (chainid.gap.timedomain.noisecheck): the filter's
share of the second difference's power against a Monte Carlo reference, the estimator on white and filtered
noise, the refutation rule, and a diagnosis where the first reading hid an effect.

The end-to-end case: the built-in chain under random motion (0.5–15 Hz, RMS 0.15 mm about 2 mm) sampled at 200 Hz,
13 samples per period of the band edge, with a 200 N friction (tanh at 1e-3 mm/s) and a cubic stiffening
3000·(x − 2)³ N (44 N RMS), 5 N of white force noise (:mod:`recovery_cases`).  Read from the force alone the noise
comes out 50–66 N: the friction's jumps at the reversals, a few samples apart, fill the second differences and its
harmonics the spectrum above the band.  On that reading the cubic (9 times the noise) was under it and the
diagnosis named friction alone (held-out NRMSE 0.036 against 0.012 with the cubic).
"""
from __future__ import annotations

import math
import warnings
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.signal import sosfiltfilt

import recovery_cases as rc
from chainid.gap.core.noise import lowpass_sos
from chainid.gap.timedomain import noisecheck
from chainid.gap.timedomain.bandlimit import difference_share

#: the robust (MAD) σ of n Gaussian second differences has a relative standard error of about 1.7/√n
REL_SE = 1.7


def test_difference_share_is_the_filtered_noise_second_difference_power_share():
    """Against white noise filtered by the same zero-phase Butterworth (2·10⁶ samples, so the Monte Carlo ratio is
    within 0.5 % of its expectation); 1 without a filter."""
    fs, f_cut = 200.0, 40.0
    rng = np.random.default_rng(1)
    e = rng.normal(0.0, 1.0, 2_000_000)
    y = sosfiltfilt(lowpass_sos(fs, f_cut, e.size), e)
    mc = np.var(np.diff(y, 2)) / np.var(np.diff(e, 2))
    assert difference_share(fs, f_cut) == pytest.approx(mc, rel=0.01)
    assert difference_share(fs, float("nan")) == 1.0


@pytest.mark.parametrize("f_res", [float("nan"), 60.0, 10.0])
def test_residual_sigma_of_white_and_filtered_noise_is_the_noise(f_res):
    """σ = 5 N of white noise, 8 000 samples, whole (NaN) or filtered at 60 or 10 Hz of 200 Hz as a record compared
    below a cut is: within 4 standard errors of 5 N (a filtered case with twice that margin for the correlated
    samples: at 10 Hz the filter keeps 3e-4 of the second difference's power)."""
    rng = np.random.default_rng(7)
    e = rng.normal(0.0, 5.0, 8000)
    r = e if not math.isfinite(f_res) else sosfiltfilt(lowpass_sos(200.0, f_res, e.size), e)
    got = noisecheck.residual_sigma(r, 200.0, f_res)
    assert abs(got / 5.0 - 1.0) <= 4 * REL_SE / math.sqrt(e.size) * (1 if not math.isfinite(f_res) else 2), got


def test_caps_refute_only_a_reading_over_twice_the_noise_power():
    """Residuals of pure 5 N noise: a record whose σ read is 5.5 N (10 % high) stands; one read at 8 N (2.56 times
    the power) is capped at the residual's σ."""
    rng = np.random.default_rng(3)
    res = {k: rng.normal(0.0, 5.0, 6000) for k in ("a", "b")}
    td = [SimpleNamespace(test="a", sigma=5.5, fs=500.0, f_res=float("nan")),
          SimpleNamespace(test="b", sigma=8.0, fs=500.0, f_res=float("nan"))]
    got = noisecheck.caps(td, res)
    assert set(got) == {"b"}
    assert got["b"] == pytest.approx(5.0, rel=4 * REL_SE / math.sqrt(6000))
    assert "b 8 → " in noisecheck.note(td, got)


def _friction_cubic(fs: float, k3: float):
    def extra(mo, t):
        x, v, _ = mo(t)
        return 200.0 * np.tanh(v / 1e-3) + k3 * (x - rc.X0_CHAIN) ** 3

    return rc.chain_random(extra=extra, band=(0.5, 15.0), fs=fs, n=4000, n_rec=4)


@pytest.mark.slow
def test_a_switching_force_at_13_samples_per_period_no_longer_hides_a_cubic():
    """The noise is read again (the warning says so) within 25 % of the 5 N simulated on every record, and the
    chain takes the cubic as well as the friction: F_c within 2 % of 200 N and a cubic-law term (deadband of
    exponent about 3, or hardening) that takes the held-out NRMSE under 0.02."""
    from chainid.gap.diagnose import diagnose

    recs, model = _friction_cubic(200.0, 3000.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = diagnose(recs, ["r3"], model, quiet=True)
    assert any(w.startswith("force noise read again") for w in res["warnings"])
    for t in res["tests"]:
        assert abs(t["sigma_N"] / rc.SF_CHAIN - 1.0) <= 0.25, t
        assert res["noise"]["tests"][t["test"]]["sigma_read_N"] > 8 * rc.SF_CHAIN  # the first reading, kept
    names = res["verdict"].split("+")
    assert "friction" in names and ({"deadband", "hardening"} & set(names)), res["verdict"]
    assert res["best"]["params"]["friction.F_c"] == pytest.approx(200.0, rel=0.02)
    assert res["residual"]["nrmse_holdout"] < 0.02


@pytest.mark.slow
def test_a_record_sampled_70_times_its_band_keeps_its_first_reading():
    """The same device sampled at 1000 Hz: the force's second difference reads the noise within 25 % (the friction's
    jumps, few among the samples, still lift it 10–20 %: under the check's 3 dB), the residual does not refute it,
    and no warning is given."""
    from chainid.gap.diagnose import diagnose

    recs, model = _friction_cubic(1000.0, 0.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = diagnose(recs, ["r3"], model, quiet=True)
    assert not any(w.startswith("force noise read again") for w in res["warnings"])
    for t in res["tests"]:
        assert res["noise"]["tests"][t["test"]]["sigma_read_N"] == t["sigma_N"]
        assert abs(t["sigma_N"] / rc.SF_CHAIN - 1.0) <= 0.25, t


@pytest.mark.slow
@pytest.mark.xfail(strict=True, reason=(
    "force noise behind a causal 4th-order Butterworth anti-alias filter at 0.15·fs (1000 Hz, the chain under random "
    "motion 1-15 Hz, nothing added, 5 N of noise): the second difference reads the noise's top octaves only, and the "
    "spectrum above 4x the band is read by its median (white noise assumed), so sigma comes out 0.26-0.29 N and the "
    "control reads 'unexplained', 25.1 dB over that noise, instead of 'none' (at 0.3·fs: 3.2 N and 3.9 dB). The noise "
    "is white in every grid and test record; a reading that integrates the spectrum's shape is needed"))
def test_force_noise_behind_an_anti_alias_filter_is_read_whole():
    """A control whose force noise is low-passed the way a DAQ's anti-alias filter does it reads as ``none``, with σ
    within 25 % of the 5 N simulated (the noise's whole variance, not its top octaves)."""
    from scipy.signal import butter, sosfilt

    import sim_devices as sd
    from chainid.gap.diagnose import diagnose
    from chainid.model import ChainModel
    from chainid.records import Record

    fs, n = 1000.0, 5000
    model = ChainModel()
    t = sd.sample_times(n, fs)
    rng = np.random.default_rng(5)
    sos = butter(4, 0.15 / 0.5, output="sos")
    recs = []
    for i, mo in enumerate(sd.random_motions(4, n, fs, 1.0, 15.0, rc.RMS_CHAIN, rc.X0_CHAIN, 3)):
        x, xd, xdd = mo(t)
        F = np.asarray(model.force(x), float) + model.mass_kg * xdd * 1e-3 + rc.C_CHAIN * xd
        e = sosfilt(sos, rng.normal(0.0, 1.0, n))
        recs.append(Record(f"r{i}", t, x + rng.normal(0.0, rc.SX_CHAIN, n), F + e * (rc.SF_CHAIN / np.std(e))))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = diagnose(recs, ["r3"], model, quiet=True)
    for t_ in res["tests"]:
        assert abs(t_["sigma_N"] / rc.SF_CHAIN - 1.0) <= 0.25, t_
    assert res["verdict"] == "none", res["verdict"]
