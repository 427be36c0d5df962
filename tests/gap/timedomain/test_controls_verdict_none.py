"""Controls of the time-domain diagnosis: devices with no effect at all get the verdict ``none``, and the baseline's
held-out residual sits at the noise floor (within 1 dB), with an independent simulation (:mod:`sim_devices`).

* a damping-dominated linear device F = 1·x + 2·ẋ + preload (c·ẋ about 75× the spring's dynamic force; random
  motion 0.5–10 Hz, RMS 1 mm, 1 kHz, 5 records of 5 000 samples, σ_x = 2 µm, σ_F = 0.5 N), ``model=None``;
* the built-in chain, F = F_k(x) + m_chain·ẍ·1e-3 + 30·ẋ, random motion about 2 mm (RMS 0.15 mm, peaks about
  ±0.3 mm, 0.3–4 Hz), σ_x = 0.2 µm, σ_F = 5 N, at 500 Hz and at 200 Hz.
"""
from __future__ import annotations

import numpy as np
import pytest

import recovery_cases as rc

pytestmark = pytest.mark.slow


def _chain(fs: float, n: int):
    def build():
        recs, model = rc.chain_random(fs=fs, n=n)
        return recs, ["r4"], model
    return build


def test_damping_dominated_linear_control_is_none_at_the_noise_floor():
    res, recs, _ = rc.diagnosed("ctl_linear_dd", rc.damping_dominated_set)
    assert res["route"] == "time"
    assert res["verdict"] == "none", res["chain_text"]
    assert abs(res["baseline"]["db_over_noise"]) <= 1.0, res["baseline"]
    p = rc.final_params(res)
    assert p["damping.c"] == pytest.approx(2.0, rel=0.01)
    assert p["_base"]["k"] == pytest.approx(1.0, rel=0.05)


def test_chain_control_is_none_at_the_noise_floor():
    res, recs, _ = rc.diagnosed("ctl_chain_500", _chain(500.0, 5000))
    assert res["verdict"] == "none", res["chain_text"]
    assert abs(res["baseline"]["db_over_noise"]) <= 1.0, res["baseline"]
    assert rc.final_params(res)["damping.c"] == pytest.approx(rc.C_CHAIN, rel=0.02)


def test_chain_control_at_200_hz_is_at_the_noise_floor():
    res, recs, _ = rc.diagnosed("ctl_chain_200", _chain(200.0, 4000))
    assert res["verdict"] == "none", res["chain_text"]
    assert abs(res["baseline"]["db_over_noise"]) <= 1.0, res["baseline"]


def test_force_noise_is_estimated_on_the_controls():
    """The per-record force noise the floor is built on: σ_F = 0.5 N and 5 N as simulated (within 15 %)."""
    res, _, _ = rc.diagnosed("ctl_linear_dd", rc.damping_dominated_set)
    s = np.array([t["sigma_N"] for t in res["tests"]])
    assert np.all(np.abs(s / 0.5 - 1) <= 0.15), s
    res, _, _ = rc.diagnosed("ctl_chain_500", _chain(500.0, 5000))
    s = np.array([t["sigma_N"] for t in res["tests"]])
    assert np.all(np.abs(s / rc.SF_CHAIN - 1) <= 0.15), s
