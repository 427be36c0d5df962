"""A sensor delay composed after other simulation hooks measures the force of the instant it lags to
(chainid.model.effects.compose_hooks).

By hand: x = sin(2π·t) mm sampled at 50 Hz (the turning points between samples), a linear 10 N/mm spring as the
model force, Coulomb friction F_c = 5 N and a delay τ = 7 ms: the measured force at t is
10·sin(2π(t − τ)) + 5·sgn(cos(2π(t − τ))) up to the O(Δt²) of the interpolated motion (the sign exactly: no
lagged instant is on a turning point).  Interpolating the force built on the samples instead puts one sample per
reversal on the ramp between −5 and +5 N.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.model import LinearModel
from chainid.model.effects import compose_hooks, parse_effect

TAU, FC = 0.007, 5.0


def _motion():
    t = 0.003 + np.arange(200) / 50.0
    w = 2 * math.pi
    return t, np.sin(w * t), w * np.cos(w * t), -w * w * np.sin(w * t)


def test_friction_behind_a_delay_takes_the_sign_of_the_lagged_instant():
    model = LinearModel(10.0, 0.0)
    t, x, xd, xdd = _motion()
    hook = compose_hooks([parse_effect(f"friction:F_c={FC}", model), parse_effect(f"sensor_delay:tau={TAU}", model)])
    F = hook(t, x, xd, xdd, 10.0 * x)
    ts = t - TAU
    want = 10.0 * np.sin(2 * math.pi * ts) + FC * np.sign(np.cos(2 * math.pi * ts))
    inside = ts >= t[0]
    # the spring part through the interpolated motion: |error| <= 10·(2π)²·Δt²/8 = 0.02 N; the sign exact
    np.testing.assert_allclose(F[inside], want[inside], rtol=0, atol=0.02)


def test_interpolating_the_sampled_force_is_what_the_composition_avoids():
    model = LinearModel(10.0, 0.0)
    t, x, xd, xdd = _motion()
    fric, delay = parse_effect(f"friction:F_c={FC}", model), parse_effect(f"sensor_delay:tau={TAU}", model)
    naive = delay(t, x, xd, xdd, fric(t, x, xd, xdd, 10.0 * x))
    ts = t - TAU
    want = 10.0 * np.sin(2 * math.pi * ts) + FC * np.sign(np.cos(2 * math.pi * ts))
    inside = ts >= t[0]
    assert np.max(np.abs(naive[inside] - want[inside])) > 2.0  # a ramp sample per reversal: several newtons off


def test_composition_without_a_delay_applies_the_hooks_in_order():
    model = LinearModel(10.0, 0.0)
    t, x, xd, xdd = _motion()
    fric = parse_effect(f"friction:F_c={FC}", model)
    assert compose_hooks([]) is None
    np.testing.assert_array_equal(compose_hooks([fric])(t, x, xd, xdd, 10.0 * x), fric(t, x, xd, xdd, 10.0 * x))


def test_a_delay_alone_interpolates_the_smooth_model_force():
    model = LinearModel(10.0, 0.0)
    t, x, xd, xdd = _motion()
    F = compose_hooks([parse_effect(f"sensor_delay:tau={TAU}", model)])(t, x, xd, xdd, 10.0 * x)
    inside = t - TAU >= t[0]
    assert F[inside] == pytest.approx(10.0 * np.sin(2 * math.pi * (t[inside] - TAU)), abs=0.02)
