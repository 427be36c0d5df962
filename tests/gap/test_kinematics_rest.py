"""Smooth kinematics of a record with rests (:func:`chainid.gap.core.kinematics.estimate`, the band from
:func:`chainid.gap.core.noise.excitation_band`): ẋ is zeroed where the record is at rest, but ẍ is the derivative
of the unzeroed ẋ, so no spike appears where motion starts or stops.

The motion is a closed form: at rest, a cosine speed ramp to v over Tr, constant speed, a cosine ramp back to
rest; its acceleration is a_max·sin(π(t − t_k)/Tr) on the ramps (a_max = π·v/(2·Tr)) and 0 elsewhere.  With
noise on x the rest threshold (4 noise standard deviations of the smooth speed) is a visible jump of ẋ: its
difference quotient would be a spike of several a_max (about 4 a_max for the noisiest record here).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.gap.core.kinematics import estimate
from chainid.gap.core.noise import excitation_band

FS, V, TR = 1000.0, 10.0, 0.5  # Hz, mm/s, s
A_MAX = math.pi * V / (2 * TR)


def _motion() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    t = np.arange(0.0, 6.0, 1.0 / FS)
    v = np.zeros_like(t)
    a = np.zeros_like(t)
    up = (t >= 1.0) & (t < 1.0 + TR)
    v[up] = V * (1 - np.cos(math.pi * (t[up] - 1.0) / TR)) / 2
    a[up] = A_MAX * np.sin(math.pi * (t[up] - 1.0) / TR)
    v[(t >= 1.0 + TR) & (t < 3.5)] = V
    down = (t >= 3.5) & (t < 3.5 + TR)
    v[down] = V * (1 + np.cos(math.pi * (t[down] - 3.5) / TR)) / 2
    a[down] = -A_MAX * np.sin(math.pi * (t[down] - 3.5) / TR)
    x = np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]) / FS)])  # trapezoidal: exact to O(dt²)
    return t, x, a


@pytest.mark.parametrize("sigma_mm", [0.001, 0.01, 0.05])
def test_no_acceleration_spike_where_motion_starts_or_stops(sigma_mm):
    t, x, a = _motion()
    xn = x + np.random.default_rng(0).normal(0.0, sigma_mm, t.size)
    kin = estimate(t, xn, excitation_band(t, xn))
    xd, xdd = kin.xd, kin.xdd
    rest = (t < 0.9) | (t > 4.1)
    assert np.count_nonzero(xd[rest] == 0.0) > 0.9 * np.count_nonzero(rest)  # the rests are recognised
    assert np.all(xd[(t > 1.6) & (t < 3.4)] != 0.0)  # the motion is not
    # ẍ follows the closed form everywhere, the starts and stops included (a spike would be several a_max)
    assert float(np.max(np.abs(xdd - a))) < 0.25 * A_MAX
    assert float(np.max(np.abs(xdd))) < 1.25 * A_MAX
