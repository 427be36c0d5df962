"""A record at rest is stuck: the smooth velocity is 0 where it is within its noise (chainid.gap.core.noise).

Independent references: the velocity noise of the smoothing pipeline against a Monte Carlo of the same
pipeline on white noise; a record whose lead-in is exactly at rest (the simulation's ẋ = 0 there).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from chainid.gap.core import noise as nz


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


def test_coulomb_friction_behind_a_rest_lead_in_is_named_on_a_held_out_record() -> None:
    """The benchmark's small random friction case: its held-out record r4 starts with 323 samples at rest.
    Before the rest rule the noise's velocity sign put ±F_c on them (310 of 3970 samples with the wrong
    sign) and the case was `unexplained` (held-out shrinkage 49 %); the truth is F_c = 139.07 N
    (``effect_spec`` of the case) and c = 19.32 N·s/mm."""
    from chainid.gap.benchmark.grid import grid
    from chainid.gap.benchmark.nonharmonic import records
    from chainid.gap.diagnose import diagnose

    case = next(k for k in grid(True, 0, ("random",)) if k["family"] == "single")
    assert case["truth"] == ["friction"] and case["hold"] == "r4"
    recs, dev = records(case)
    assert np.count_nonzero(dev["motions"][3].xd == 0.0) == 323
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = diagnose(recs, ["r4"], dev["nominal"], uncertainty=False, quiet=True)
    assert res["verdict"] == "friction"
    last = res["steps"][-1]
    assert last["params"]["friction.F_c"] == pytest.approx(139.07, rel=0.03)
    assert last["params"]["damping.c"] == pytest.approx(19.32, rel=0.05)
    assert last["shrinkage"] > 0.8
