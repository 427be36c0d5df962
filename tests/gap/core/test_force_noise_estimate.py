"""The force noise σ_F a time-domain record's noise floor is built on (:func:`chainid.gap.timedomain.data.prepare_time`:
``sigma`` from the second difference of F, ``sigma_hf`` from the force spectrum above 4× the band), on chain records
with white force noise of 5 N simulated independently (:mod:`recovery_cases`): random motion about 2 mm, RMS
0.15 mm, F_k(x) about 1 100 N RMS, with a 20 kg fixture moving with the chain.
"""
from __future__ import annotations

import numpy as np
import pytest

import recovery_cases as rc
from chainid.gap.timedomain.data import prepare_time


def _sigmas(fs: float, n: int, band: tuple[float, float]) -> tuple[np.ndarray, np.ndarray]:
    recs, _ = rc.chain_random(extra_mass=20.0, band=band, fs=fs, n=n, n_rec=3)
    d = [prepare_time(r, 4) for r in recs]
    return np.array([x.sigma for x in d]), np.array([x.sigma_hf for x in d])


def test_force_noise_on_a_record_sampled_70_times_its_band():
    sig, hf = _sigmas(1000.0, 5000, (1.0, 15.0))
    assert np.all(np.abs(sig / rc.SF_CHAIN - 1) <= 0.15), sig
    assert np.all(np.abs(hf / rc.SF_CHAIN - 1) <= 0.15), hf


def test_force_spectrum_floor_on_a_record_sampled_13_times_its_band():
    """The spectrum above 4× the band (60–100 Hz) holds the noise alone: its level is the simulated 5 N."""
    _, hf = _sigmas(200.0, 4000, (0.5, 15.0))
    assert np.all(np.abs(hf / rc.SF_CHAIN - 1) <= 0.15), hf


def test_force_noise_on_a_record_sampled_13_times_its_band():
    sig, _ = _sigmas(200.0, 4000, (0.5, 15.0))
    assert np.all(np.abs(sig / rc.SF_CHAIN - 1) <= 0.15), sig


@pytest.mark.slow
@pytest.mark.xfail(strict=True, reason=(
    "a 20 kg fixture mass on the chain at 200 Hz (band 0.5-15 Hz, mass force ~14 N RMS against 5 N of noise): "
    "sigma_F is now right, and the chain names sensor_delay tau = -0.44 ms (held-out NRMSE 0.0105 -> 0.00445, 0.4 dB "
    "over the noise): on the chain's stiffness k, a lag tau is to second order a dashpot k*tau (the fitted c takes "
    "it) plus a mass k*tau^2/2, which is 20 kg here; the two are told apart only by the higher orders"))
def test_fixture_mass_is_not_hidden_by_the_noise_estimate():
    def build():
        recs, model = rc.chain_random(extra_mass=20.0, band=(0.5, 15.0))
        return recs, ["r4"], model

    res, _, _ = rc.diagnosed("fm_200", build)
    assert res["verdict"] == "fixture_mass", res["chain_text"]
