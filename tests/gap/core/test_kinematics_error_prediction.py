"""The kinematics of the time-domain diagnosis (:func:`chainid.gap.core.kinematics.estimate`) against motions whose
ẋ is known in closed form (:mod:`sim_devices`): the RMS error of the estimated ẋ is within a factor 2 of the error
the estimator predicts (``err_v``), and on a damping-dominated device the residual of the *true* model evaluated on
the estimated kinematics is the predicted floor √(σ_F² + (c·err_v)²) to 1 dB.

Motions: 8 s at 500 Hz (4 000 samples), RMS 1 mm, band 0.5–10 Hz; white noise σ_x on x.
"""
from __future__ import annotations

import numpy as np
import pytest

import sim_devices as sd
from chainid.gap.core.kinematics import estimate
from chainid.gap.core.noise import excitation_band

FS, N = 500.0, 4000
T = N / FS


def _motions() -> dict[str, sd.MotionFn]:
    return {
        "random": sd.multisine(T, 0.5, 10.0, 1.0, 0.0, seed=1, periodic=False),
        "periodic": sd.multisine(T, 0.5, 10.0, 1.0, 0.0, seed=2, periodic=True),
        "rest_onset": sd.onset(sd.multisine(T, 0.5, 10.0, 1.0, 0.0, seed=3), 2.0, 0.5, 0.0),
        "chirp_rests": sd.chirp(0.5, 8.0, 1.5, 6.5, 1.0, 0.3, 0.0),
    }


def _estimated(name: str, sigma_x: float, seed: int = 5):
    t = sd.sample_times(N, FS)
    x, xd, xdd = _motions()[name](t)
    xm = x + np.random.default_rng(seed).normal(0.0, sigma_x, N)
    return t, x, xd, xm, estimate(t, xm, excitation_band(t, xm))


@pytest.mark.parametrize("sigma_x", [1e-3, 5e-3])
@pytest.mark.parametrize("name", ["random", "periodic", "rest_onset", "chirp_rests"])
def test_velocity_error_is_within_a_factor_two_of_its_prediction(name, sigma_x):
    t, x, xd, xm, kin = _estimated(name, sigma_x)
    actual = float(np.sqrt(np.mean((kin.xd - xd) ** 2)))
    ratio = actual / kin.err_v
    assert 0.5 <= ratio <= 2.0, (name, sigma_x, kin.method, actual, kin.err_v)
    # the error is small against the motion itself (RMS of ẋ about 38 mm/s): a real estimate, not noise
    assert actual < 0.02 * float(np.std(xd))


def test_the_estimator_follows_the_record():
    """A whole number of periods takes the spectral derivative, a record cut off-period the filter."""
    assert _estimated("periodic", 1e-3)[-1].method == "spectral"
    assert _estimated("random", 1e-3)[-1].method.startswith("butterworth")


@pytest.mark.xfail(strict=True, reason=(
    "the per-sample predicted error err_v_t is 3x too small at the ends of a non-periodic record: random "
    "0.5-10 Hz, sigma_x 1 um, first 20 samples actual RMS 0.324 mm/s vs predicted 0.108 (five-point differences "
    "after odd padding about the quadratic end value; before: 0.353 vs 0.104, last 20 0.731 vs 0.126)"))
def test_predicted_velocity_error_holds_at_the_record_ends():
    t, x, xd, xm, kin = _estimated("random", 1e-3)
    err = kin.xd - xd
    for sl in (slice(0, 20), slice(-20, None)):
        actual = float(np.sqrt(np.mean(err[sl] ** 2)))
        pred = float(np.sqrt(np.mean(np.asarray(kin.v_error() * np.ones(N))[sl] ** 2)))
        assert 0.5 <= actual / pred <= 2.0, (sl, actual, pred)


def _damping_dominated(periodic: bool) -> tuple[float, float, float]:
    """F = c·ẋ + k·x + noise (c = 2 N·s/mm, k = 1 N/mm, σ_F = 0.1 N, σ_x = 1 µm): the RMS residual of the true
    model on the estimated kinematics [N], the predicted floor [N] and the ratio of the dashpot's to the spring's
    dynamic force."""
    c, k, sF = 2.0, 1.0, 0.1
    t = sd.sample_times(N, FS)
    x, xd, _ = sd.multisine(T, 0.5, 10.0, 1.0, 0.0, seed=1, periodic=periodic)(t)
    rng = np.random.default_rng(6)
    xm = x + rng.normal(0.0, 1e-3, N)
    Fm = c * xd + k * x + rng.normal(0.0, sF, N)
    kin = estimate(t, xm, excitation_band(t, xm))
    res = float(np.sqrt(np.mean((Fm - c * kin.xd - k * kin.x) ** 2)))
    return res, float(np.hypot(sF, c * kin.err_v)), float(np.std(c * xd) / np.std(k * x))


def test_damping_dominated_residual_matches_the_predicted_floor_on_a_periodic_record():
    res, floor, dominance = _damping_dominated(periodic=True)
    assert dominance > 5.0
    assert abs(20 * np.log10(res / floor)) <= 1.0, (res, floor)


def test_damping_dominated_residual_matches_the_predicted_floor_on_a_random_record():
    res, floor, dominance = _damping_dominated(periodic=False)
    assert dominance > 5.0
    assert abs(20 * np.log10(res / floor)) <= 1.0, (res, floor)


@pytest.mark.xfail(strict=True, reason=(
    "the predicted acceleration error err_a is 2-3x too small on the filter estimator (sigma_x 1 um): random "
    "0.5-10 Hz 2.6x, rest then onset 2.1x (before the five-point differences: 3.3x and 4.2x); the spectral "
    "estimator on a periodic record is right (12.6 vs 11.7). It enters the floor as m*err_a (a resonant device)"))
@pytest.mark.parametrize("name", ["random", "rest_onset"])
def test_acceleration_error_is_within_a_factor_two_of_its_prediction(name):
    t = sd.sample_times(N, FS)
    _, _, xdd = _motions()[name](t)
    *_, kin = _estimated(name, 1e-3)
    ratio = float(np.sqrt(np.mean((kin.xdd - xdd) ** 2))) / kin.err_a
    assert 0.5 <= ratio <= 2.0, (name, ratio)


def _narrowband(periodic: bool):
    """12–20 Hz multisine, RMS 0.5 mm, 1 kHz, 6 000 samples, σ_x = 0.1 µm (a resonant response's band)."""
    fs, n = 1000.0, 6000
    t = sd.sample_times(n, fs)
    x, xd, xdd = sd.multisine(n / fs, 12.0, 20.0, 0.5, 0.0, seed=4, periodic=periodic)(t)
    xm = x + np.random.default_rng(1).normal(0.0, 1e-4, n)
    return t, x, xd, xdd, estimate(t, xm, excitation_band(t, xm))


def test_velocity_error_on_a_periodic_narrowband_record():
    t, x, xd, xdd, kin = _narrowband(True)
    assert kin.method == "spectral"
    assert 0.5 <= float(np.sqrt(np.mean((kin.xd - xd) ** 2))) / kin.err_v <= 2.0


def test_velocity_error_on_a_narrowband_record_is_within_a_factor_two_of_its_prediction():
    t, x, xd, xdd, kin = _narrowband(False)
    assert 0.5 <= float(np.sqrt(np.mean((kin.xd - xd) ** 2))) / kin.err_v <= 2.0
