"""ẍ is the derivative of the unzeroed ẋ on the two estimators :mod:`tests.gap.test_kinematics_rest` does not reach:
the spectral one of a periodic record (:func:`chainid.gap.core.kinematics.estimate` on a whole number of periods)
and the plain low-pass of :func:`chainid.gap.core.noise.kinematics`.

The motion is a closed form that returns to its start, so its circular extension is smooth: rest, a cosine speed
ramp to +v over Tr, constant speed, a ramp back to rest, the same to −v and back, rest.  Its acceleration is
±a_max·sin(π(t − t_k)/Tr) on the ramps (a_max = π·v/(2·Tr)) and 0 elsewhere.  With noise on x the rest threshold
is a visible jump of ẋ: the difference quotient of the zeroed ẋ is a spike of 0.6 to 2.5 a_max over the closed
form for the noise levels here, against 0.11 to 0.14 a_max for the unzeroed derivative (measured once, hence the
tolerance 0.25 a_max).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.gap.core import noise
from chainid.gap.core.kinematics import estimate

FS, V, TR = 1000.0, 10.0, 0.5  # Hz, mm/s, s
A_MAX = math.pi * V / (2 * TR)
RAMPS = [(1.0, 0.0, V), (2.5, V, 0.0), (4.0, 0.0, -V), (5.5, -V, 0.0)]  # start [s], speed from, speed to [mm/s]


def _motion() -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    t = np.arange(0.0, 8.0, 1.0 / FS)
    v = np.zeros_like(t)
    a = np.zeros_like(t)
    v[(t >= 1.5) & (t < 2.5)] = V
    v[(t >= 4.5) & (t < 5.5)] = -V
    for t0, v0, v1 in RAMPS:
        m = (t >= t0) & (t < t0 + TR)
        s = math.pi * (t[m] - t0) / TR
        v[m] = v0 + (v1 - v0) * (1 - np.cos(s)) / 2
        a[m] = (v1 - v0) / V * A_MAX * np.sin(s)
    x = np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]) / FS)])  # trapezoidal: exact to O(dt²)
    rest = (t < 0.9) | ((t > 3.1) & (t < 3.9)) | (t > 6.1)
    return t, x, a, rest


def _noisy(sigma_mm: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    t, x, a, rest = _motion()
    assert abs(x[-1]) < 1e-9 and x.max() == pytest.approx(V * 1.5, rel=1e-9)  # back at the start: periodic
    return t, x + np.random.default_rng(0).normal(0.0, sigma_mm, t.size), a, rest


@pytest.mark.parametrize("sigma_mm", [0.01, 0.05])
def test_spectral_estimate_of_a_periodic_record_has_no_spike_at_rest_edges(sigma_mm):
    t, xn, a, rest = _noisy(sigma_mm)
    kin = estimate(t, xn, noise.excitation_band(t, xn))
    assert kin.method == "spectral"
    assert np.count_nonzero(kin.xd[rest] == 0.0) > 0.9 * np.count_nonzero(rest)  # the rests are recognised
    assert float(np.max(np.abs(kin.xdd - a))) < 0.25 * A_MAX
    assert float(np.max(np.abs(kin.xdd))) < 1.25 * A_MAX


@pytest.mark.parametrize("sigma_mm", [0.01, 0.05])
def test_noise_kinematics_differentiates_the_unzeroed_speed(sigma_mm):
    t, xn, a, rest = _noisy(sigma_mm)
    _, xd, xdd = noise.kinematics(t, xn, noise.excitation_band(t, xn))
    assert np.count_nonzero(xd[rest] == 0.0) > 0.9 * np.count_nonzero(rest)
    assert float(np.max(np.abs(xdd - a))) < 0.25 * A_MAX
    assert float(np.max(np.abs(xdd))) < 1.25 * A_MAX
