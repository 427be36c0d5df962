"""The sign of sliding friction with an estimated velocity (chainid.model.effects.sliding_sign) keeps the reversal
rule of the exact one: the sample at a reversal is 0 (the set-valued Coulomb force at its midpoint), so the
expectation erf(ẋ/(√2·σ)) tends to coulomb_sign as σ → 0 instead of putting a full ±1 on every reversal sample.

By hand: ẋ = cos(2π·t) sampled at 40 Hz from t = 0.002 s (a sample 2 ms from each zero of ẋ, none on one); a reversal sample is one whose
neighbours have opposite signs and whose |ẋ| is under half of both (chainid.model.operators.coulomb_sign).
Units mm/s.
"""
from __future__ import annotations

import math

import numpy as np

from chainid.model.effects import sliding_sign


def _reversal_samples(v: np.ndarray) -> list[int]:
    return [i for i in range(1, v.size - 1)
            if v[i - 1] * v[i + 1] < 0 and abs(v[i]) < 0.5 * min(abs(v[i - 1]), abs(v[i + 1]))]


def test_a_reversal_sample_is_zero_with_an_estimated_velocity_too():
    t = 0.002 + np.arange(81) / 40.0
    v = np.cos(2 * math.pi * t)
    rev = _reversal_samples(v)
    assert len(rev) == 4  # two periods: four turning points, each with one sample nearer than half a step
    for sd in (1e-9, 0.05, 0.5):
        got = sliding_sign(v, periodic=False, v_err=sd)
        hand = np.array([0.0 if i in rev else math.erf(v[i] / (math.sqrt(2.0) * sd)) for i in range(v.size)])
        np.testing.assert_allclose(got, hand, rtol=0, atol=1e-15)
    # the limit σ → 0 is the exact rule: sgn(ẋ) with 0 at the reversal samples
    exact = np.array([0.0 if i in rev else math.copysign(1.0, v[i]) for i in range(v.size)])
    np.testing.assert_array_equal(sliding_sign(v, periodic=False, v_err=1e-9), exact)
    np.testing.assert_array_equal(sliding_sign(v, periodic=False), exact)


def test_a_per_sample_error_of_zero_takes_the_exact_sign_there():
    t = 0.002 + np.arange(81) / 40.0
    v = np.cos(2 * math.pi * t)
    rev = _reversal_samples(v)
    assert rev == [10, 30, 50, 70]
    sd = np.where(np.arange(v.size) % 2 == 1, 0.0, 0.3)  # the reversal samples (10, 30, 50, 70) estimated
    got = sliding_sign(v, periodic=False, v_err=sd)
    for i in range(v.size):
        want = 0.0 if i in rev else (math.copysign(1.0, v[i]) if sd[i] == 0 else math.erf(v[i] / (math.sqrt(2) * 0.3)))
        assert abs(got[i] - want) <= 1e-15, (i, got[i], want)
