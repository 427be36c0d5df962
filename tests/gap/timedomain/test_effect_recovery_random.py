"""Each new library effect recovered blind on random excitation (the time-domain route): the verdict names it and
its parameters come back within 10 % of the truth of an independent simulation (:mod:`sim_devices`).

Devices (:mod:`recovery_cases`): the linear device F = 10·x + 0.2·ẋ + preload per record + effect (random motion
0.2–4 Hz, RMS 1 mm, 200 Hz, 5 records of 4 000 samples, σ_x = 1 µm, σ_F = 0.1 N), and the built-in chain
(``ChainModel().force``, x about 2 mm) for ``fixture_mass``.  One record (r4) is held out.
"""
from __future__ import annotations

import pytest

import recovery_cases as rc
import sim_devices as sd

pytestmark = pytest.mark.slow


def _named(res: dict, effect: str) -> None:
    """The verdict names the effect, and the named chain explains the held-out data to the noise floor."""
    assert effect in res["verdict"].split("+"), res["chain_text"]
    assert res["residual"]["db_over_noise"] <= 1.0, res["chain_text"]


def _bouc_wen():
    return rc.linear_random(rc.hysteresis_force(3.0, 0.1, 2.0, 0.6)), ["r4"], None


def _deadband():
    ex = lambda mo, t: sd.deadband_force(mo(t)[0], 30.0, 0.8, 2.0, 0.0)  # noqa: E731
    return rc.linear_random(ex), ["r4"], None


def _hardening():
    return rc.linear_random(lambda mo, t: 2.0 * mo(t)[0] ** 3), ["r4"], None


def _delay(tau: float, rest: float = 0.0):
    return lambda: (rc.linear_random(delay=tau, rest=rest), ["r4"], None)


@pytest.mark.xfail(strict=True, reason=(
    "stribeck F_c = 2, F_s = 3.5, v_s = 3 mm/s: named, but F_s = 3.876 (+10.7 %) and v_s = 2.53 (-16 %), residual "
    "+9.5 dB over the noise. Cause: the sign of sliding is softened by the velocity's spread including "
    "(xdd*dt)^2/12 (Kinematics.v_spread), ~1.3 mm/s at a reversal, for a point-sampled force; at the true v_s the "
    "same columns with the spread err_v alone give F_c 2.000, dF_s 1.509 and 0.138 N RMS (noise 0.1 N), with the "
    "(xdd*dt) term dF_s 1.745 and 0.317 N RMS (1.68 N RMS on samples with |v| < 0.5 mm/s)"))
def test_stribeck_recovered_on_random_excitation():
    res, _, _ = rc.diagnosed("rand_stribeck", rc.stribeck_set)
    _named(res, "stribeck")
    p = rc.final_params(res)
    assert rc.rel_err(p["stribeck.F_c"], 2.0) <= 0.10, p
    assert rc.rel_err(p["stribeck.F_c"] + p["stribeck.dF_s"], 3.5) <= 0.10, p
    assert rc.rel_err(p["stribeck.v_s"], 3.0) <= 0.10, p


def test_bouc_wen_recovered_on_random_excitation():
    res, _, _ = rc.diagnosed("rand_bouc_wen", _bouc_wen)
    _named(res, "bouc_wen")
    p = rc.final_params(res)
    for k, v in {"F_y": 3.0, "x_y": 0.1, "n": 2.0, "r": 0.6}.items():
        assert rc.rel_err(p[f"bouc_wen.{k}"], v) <= 0.10, (k, p)


def test_deadband_recovered_on_random_excitation():
    res, _, _ = rc.diagnosed("rand_deadband", _deadband)
    _named(res, "deadband")
    p = rc.final_params(res)
    for k, v in {"k_d": 30.0, "g": 0.8, "p": 2.0}.items():
        assert rc.rel_err(p[f"deadband.{k}"], v) <= 0.10, (k, p)
    assert abs(p["deadband.x_c"]) <= 0.05 * 0.8, p  # the centre: 0 mm (5 % of the half-width)


def test_hardening_recovered_on_a_linear_base():
    res, _, _ = rc.diagnosed("rand_hardening", _hardening)
    _named(res, "hardening")
    p = rc.final_params(res)
    assert rc.rel_err(p["hardening.k3"], 2.0) <= 0.10, p
    assert rc.rel_err(p["_base"]["k"], rc.K_LIN) <= 0.10, p  # the linear spring stays the device's


def test_fixture_mass_recovered_on_a_chain_base():
    res, _, _ = rc.diagnosed("rand_fixture_mass", rc.fixture_mass_set)
    _named(res, "fixture_mass")
    p = rc.final_params(res)
    assert rc.rel_err(p["fixture_mass.m_f"], 20.0) <= 0.10, p
    assert rc.rel_err(p["damping.c"], rc.C_CHAIN) <= 0.10, p


@pytest.mark.parametrize("tau", [0.125, -0.125], ids=["force_lags", "displacement_lags"])
def test_sensor_delay_of_a_quarter_period_recovered_after_a_rest(tau):
    """A lag of a quarter period of the band centre (about 2 Hz): the force lags (τ > 0) or the displacement lags
    (τ < 0).  The device rests for the first and the last second, so no sample's lagged motion falls outside the
    record."""
    res, _, _ = rc.diagnosed(f"rand_delay_rest_{tau}", _delay(tau, rest=1.0))
    _named(res, "sensor_delay")
    p = rc.final_params(res)
    assert rc.rel_err(p["sensor_delay.tau"], tau) <= 0.10, p


@pytest.mark.xfail(strict=True, reason=(
    "motion running before the record starts (as on a rig), band 0.2-4 Hz: tau = +0.125 s comes out 0.1058 "
    "(-15 %) with damping.c pinned at 0 (truth 0.2), residual +18.9 dB over the noise; tau = -0.125 s comes out "
    "-0.115 (-8 %) with a mass of 2.17 kg (truth 0) and c 0.296 (+48 %), residual +13.8 dB. Cause: the model "
    "evaluates x(t - tau) by np.interp, which holds x(t0) for the first tau*fs samples (x(t_end) for the last ones "
    "when tau < 0): 25 samples per record whose model force is wrong by about k*travel - at the true tau 0.69 N "
    "RMS against 0.11 N with the first 40 samples left out - so the fit bends tau, m and c to shrink them. With "
    "rests at both ends the same lags come out 0.1277 and -0.1222 at the noise floor. Samples whose lagged motion "
    "lies outside the record should be left out of the fit and the score"))
@pytest.mark.parametrize("tau", [0.125, -0.125], ids=["force_lags", "displacement_lags"])
def test_sensor_delay_of_a_quarter_period_recovered_mid_motion(tau):
    res, _, _ = rc.diagnosed(f"rand_delay_{tau}", _delay(tau))
    _named(res, "sensor_delay")
    p = rc.final_params(res)
    assert rc.rel_err(p["sensor_delay.tau"], tau) <= 0.10, p
