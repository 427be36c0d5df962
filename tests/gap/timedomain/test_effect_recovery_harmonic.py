"""Each new library effect recovered blind on harmonic excitation: steady sine tests at 6 (f, A) pairs, one
operating condition (the harmonic route of ``diagnose``); the verdict names the effect and its parameters come back
within 10 % of the truth of an independent simulation (:mod:`sim_devices`).

Linear device F = 10·x + 0.2·ẋ + effect at (f [Hz], A [mm]) = :data:`recovery_cases.HARMONIC_PAIRS`, 8 cycles of 64
samples, σ_x = 1 µm, σ_F = 0.1 N; the built-in chain about x0 = 2 mm (σ_x = 0.2 µm, σ_F = 5 N) for
``fixture_mass`` and ``sensor_delay``.  Test h3 is held out.  The sines start at phase 0, so a sample falls on every
reversal (64 samples a cycle); Stribeck's tests sample half a step off them (:data:`OFF_REVERSALS`), as a rig's
clock, not locked to its actuator, does: locked to them its chain differs
(:func:`test_stribeck_on_samples_locked_to_the_reversals`, xfail).
"""
from __future__ import annotations

import math

import pytest
from scipy.stats import chi2

import recovery_cases as rc
import sim_devices as sd

#: the sines' phase [rad]: half a sample step of 64 a cycle, so no sample falls on a reversal
OFF_REVERSALS = math.pi / 64

pytestmark = pytest.mark.slow


def _lin(mo, t):
    x, xd, _ = mo(t)
    return rc.K_LIN * x + rc.C_LIN * xd


def _linear_set(extra, phase=0.0):
    return rc.harmonic_set(lambda mo, t, f, A: _lin(mo, t) + extra(mo, t), phase=phase), ["h3"], None


def _chain_set(pairs, tau=0.0, extra_mass=0.0):
    from chainid.model import ChainModel

    m = ChainModel()

    def force(mo, t, f, A):
        x, xd, xdd = mo(t - tau)  # the force channel shows the force at t − τ
        return m.force(x) + (m.mass_kg + extra_mass) * xdd * 1e-3 + rc.C_CHAIN * xd

    return rc.harmonic_set(force, pairs=pairs, x0=rc.X0_CHAIN, sigma_x=rc.SX_CHAIN, sigma_F=rc.SF_CHAIN), ["h3"], m


#: the held-out test's phase bins (64 samples a cycle: B = 4·(64 // 8))
HELD_OUT_BINS = 32
#: the named chain's held-out residual power over the bins' noise floor σ²/n [dB], at most what noise alone reaches
#: 19 times in 20: the 95 % point of χ²₃₂/32, 1.59 dB.  (Until the noise σ was read from the cycles' scatter this was
#: 1 dB, against a σ that the force's shape within a bin inflated: 1.5 times on the deadband, 3.7 on Stribeck's.)
NEAR_FLOOR_DB = 10.0 * math.log10(chi2.ppf(0.95, HELD_OUT_BINS) / HELD_OUT_BINS)


def _run(key, build):
    res, _, _ = rc.diagnosed(key, build)
    assert res.get("route") != "time", "a set of steady sines at one condition takes the harmonic route"
    assert res["residual"]["db_over_noise"] <= NEAR_FLOOR_DB, res["chain_text"]  # the chain explains the effect
    return res, rc.final_params(res)


def test_hardening_recovered_on_sines():
    res, p = _run("harm_hardening", lambda: _linear_set(lambda mo, t: 2.0 * mo(t)[0] ** 3))
    assert res["verdict"] == "hardening", res["chain_text"]
    assert rc.rel_err(p["hardening.k3"], 2.0) <= 0.10, p


def test_bouc_wen_recovered_on_sines():
    res, p = _run("harm_bouc_wen", lambda: _linear_set(rc.hysteresis_force(3.0, 0.1, 2.0, 0.6)))
    assert res["verdict"] == "bouc_wen", res["chain_text"]
    for k, v in {"F_y": 3.0, "x_y": 0.1, "n": 2.0, "r": 0.6}.items():
        assert rc.rel_err(p[f"bouc_wen.{k}"], v) <= 0.10, (k, p)


@pytest.mark.xfail(strict=True, reason="the chain is deadband k_d = 29.9, g = 0.805 mm, p = 1.96 (within 2 %) but "
                   "3.9 dB over the noise on h3 (bound 1.59 dB), where the true law's own residual is at the noise "
                   "(χ²/n = 0.90); on six other noise seeds 3.3–17.4 dB (at 2101303), with p above 2 on 4 of 6 by "
                   "2–3 jack-knife sd. "
                   "The 1 dB this test held before was against a σ the dead band's corner within a bin inflated 1.5 "
                   "times (3.5 dB)")
def test_deadband_recovered_on_sines():
    res, p = _run("harm_deadband", lambda: _linear_set(lambda mo, t: sd.deadband_force(mo(t)[0], 30.0, 0.8, 2.0, 0.0)))
    assert res["verdict"] == "deadband", res["chain_text"]
    for k, v in {"k_d": 30.0, "g": 0.8, "p": 2.0}.items():
        assert rc.rel_err(p[f"deadband.{k}"], v) <= 0.10, (k, p)


def _stribeck_set():
    return _linear_set(lambda mo, t: sd.stribeck_force(mo(t)[1], 2.0, 1.5, 3.0), OFF_REVERSALS)


@pytest.mark.xfail(strict=True, reason="samples locked to the reversals (x = A·sin 2πft sampled 64 times a cycle "
                   "from t = 0: one sample on each turning point): the F test refutes the tie of the step's c_e to "
                   "one viscous c, F_c comes from the loop's corners alone, 1.777 N (11 % low, as untied), and a "
                   "damping_law step follows, 6.9 dB over the noise on h3, where the true law's own residual is at "
                   "the noise (χ²/n = 0.96); half a step off the reversals the tie holds and F_c is within 0.2 %")
def test_stribeck_on_samples_locked_to_the_reversals():
    def build():
        force = lambda mo, t, f, A: _lin(mo, t) + sd.stribeck_force(mo(t)[1], 2.0, 1.5, 3.0)  # noqa: E731
        return rc.harmonic_set(force, phase=0.0), ["h3"], None

    res, p = _run("harm_stribeck_locked", build)
    assert res["verdict"] == "stribeck", res["chain_text"]
    assert rc.rel_err(p["stribeck.F_c"], 2.0) <= 0.10, p


def test_stribeck_recovered_on_sines():
    """F_c from the friction's first harmonic too: the step's c_e is tied to its law (:mod:`chainid.gap.harmonic.
    tie`; with each test's own c_e, F_c came back 11.8 % low, from the loop's corners alone)."""
    res, p = _run("harm_stribeck", _stribeck_set)
    assert res["verdict"] == "stribeck", res["chain_text"]
    assert res["steps"][1]["c_e_tied_to_law"], res["steps"][1]
    assert rc.rel_err(p["stribeck.F_c"], 2.0) <= 0.10, p
    assert rc.rel_err(p["stribeck.F_c"] + p["stribeck.dF_s"], 3.5) <= 0.10, p
    assert rc.rel_err(p["stribeck.v_s"], 3.0) <= 0.10, p


def test_stribeck_asymmetry_is_not_invented_on_sines():
    res, p = _run("harm_stribeck", _stribeck_set)
    assert abs(p.get("stribeck.dF", 0.0)) <= 0.10 * 3.5, p


def test_fixture_mass_recovered_on_sines_on_a_chain():
    pairs = ((2.0, 0.3), (5.0, 0.2), (10.0, 0.3), (10.0, 0.15), (20.0, 0.2), (20.0, 0.1))
    res, p = _run("harm_fixture_mass", lambda: _chain_set(pairs, extra_mass=20.0))
    assert res["verdict"] == "fixture_mass", res["chain_text"]
    assert rc.rel_err(p["fixture_mass.m_f"], 20.0) <= 0.10, p


@pytest.mark.parametrize("tau", [0.125, -0.125], ids=["force_lags", "displacement_lags"])
def test_sensor_delay_of_a_quarter_period_recovered_on_sines(tau):
    """Sines of 1–3 Hz on the chain; the lag is a quarter period at 2 Hz."""
    pairs = ((1.0, 0.3), (1.5, 0.2), (2.0, 0.3), (2.0, 0.15), (3.0, 0.2), (3.0, 0.1))
    res, p = _run(f"harm_delay_{tau}", lambda: _chain_set(pairs, tau=tau))
    assert res["verdict"] == "sensor_delay", res["chain_text"]
    assert rc.rel_err(p["sensor_delay.tau"], tau) <= 0.10, p
