"""The sign of sliding friction with an estimated velocity (chainid.model.effects.sliding_sign) keeps the rule of
the exact one (chainid.model.operators.coulomb_sign), so the expectation erf(ẋ/(√2·σ)) tends to it as σ → 0: an
instant on a turning point (|ẋ| at round-off) is 0, the set-valued Coulomb force at its midpoint; an instant near
one is still moving, erf, and ±1 in the limit.

By hand: ẋ = cos(2π·t) sampled at 40 Hz: from t = 0 (a sample on each turning point, t = 0.25 + k/2 s:
cos(2π·t) at round-off) or from t = 0.002 s (a sample 2 ms from each turning point, none on one).  Units mm/s.
"""
from __future__ import annotations

import math

import numpy as np

from chainid.model.effects import sliding_sign


def _on_turning(v: np.ndarray) -> list[int]:
    return [i for i in range(v.size) if abs(v[i]) <= 1e-12 * np.max(np.abs(v))]


def test_an_instant_on_a_turning_point_is_zero_with_an_estimated_velocity_too():
    v = np.cos(2 * math.pi * np.arange(81) / 40.0)
    on = _on_turning(v)
    assert on == [10, 30, 50, 70]  # cos at odd multiples of π/2: about 1e-16
    for periodic in (False, True):
        for sd in (1e-9, 0.05, 0.5):
            got = sliding_sign(v, periodic=periodic, v_err=sd)
            hand = np.array([0.0 if i in on else math.erf(v[i] / (math.sqrt(2.0) * sd)) for i in range(v.size)])
            np.testing.assert_allclose(got, hand, rtol=0, atol=1e-15)
        exact = np.array([0.0 if i in on else math.copysign(1.0, v[i]) for i in range(v.size)])
        np.testing.assert_array_equal(sliding_sign(v, periodic=periodic, v_err=1e-9), exact)
        np.testing.assert_array_equal(sliding_sign(v, periodic=periodic), exact)


def test_an_instant_near_a_turning_point_keeps_its_estimated_sign():
    t = 0.002 + np.arange(81) / 40.0
    v = np.cos(2 * math.pi * t)
    assert _on_turning(v) == [] and np.min(np.abs(v)) < 0.02  # 2 ms (a 13th of a step) from the turning points
    for sd in (1e-9, 0.05, 0.5):
        got = sliding_sign(v, periodic=False, v_err=sd)
        hand = np.array([math.erf(v[i] / (math.sqrt(2.0) * sd)) for i in range(v.size)])
        np.testing.assert_allclose(got, hand, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(sliding_sign(v, periodic=False, v_err=1e-9), np.sign(v))
    np.testing.assert_array_equal(sliding_sign(v, periodic=False), np.sign(v))


def test_a_per_sample_error_of_zero_takes_the_exact_sign_there():
    v = np.cos(2 * math.pi * (0.002 + np.arange(81) / 40.0))
    sd = np.where(np.arange(v.size) % 2 == 1, 0.0, 0.3)  # odd samples exact, even ones estimated
    got = sliding_sign(v, periodic=False, v_err=sd)
    for i in range(v.size):
        want = math.copysign(1.0, v[i]) if sd[i] == 0 else math.erf(v[i] / (math.sqrt(2) * 0.3))
        assert abs(got[i] - want) <= 1e-15, (i, got[i], want)
