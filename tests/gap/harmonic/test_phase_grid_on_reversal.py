"""A phase point that sits on a reversal has ẋ = 0 (:func:`chainid.gap.harmonic.prepare.on_reversal`), and the
smooth ẋ's standard error it is judged by (:func:`chainid.gap.harmonic.prepare.velocity_sd`).

A sine sampled 64 times a cycle puts two samples exactly on its turning points, where a sliding contact's force is
set-valued (midpoint 0).  The grid's ẋ comes from the estimate, so at those points it is the estimate's error
(here 1e-4 rad of phase), and a friction evaluated on it is a full ±F off.  Closed forms: ẋ = Aω·cos ψ.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.gap.harmonic.prepare import fourier_x, on_reversal, velocity_sd
from chainid.model.operators import coulomb_sign

A, W = 1.0, 2.0 * math.pi
V_SD = A * W * 1e-4  # the smooth ẋ's standard error of these tests: a phase error of 1e-4 rad


def _grid(offset_steps: float, phase_error: float = 1e-4) -> np.ndarray:
    psi = 2 * math.pi * (np.arange(64) + offset_steps) / 64 + phase_error
    return A * W * np.cos(psi)


def test_the_samples_on_the_turning_points_take_zero_velocity():
    xd = _grid(0.0)
    out = on_reversal(xd, V_SD)
    assert np.flatnonzero(out == 0.0).tolist() == [16, 48]  # ψ = π/2 and 3π/2
    keep = np.ones(64, bool)
    keep[[16, 48]] = False
    assert np.array_equal(out[keep], xd[keep])
    # the friction's sign there is the midpoint, elsewhere the sign of the true velocity cos ψ
    s = coulomb_sign(out, True)
    assert s[16] == 0.0 and s[48] == 0.0
    assert np.array_equal(s[keep], np.sign(np.cos(2 * math.pi * np.arange(64) / 64))[keep])


def test_a_grid_between_the_turning_points_keeps_every_velocity():
    """Offset by a quarter of a step, the nearest samples are 0.025 rad (245 standard errors) from a turning point:
    still sliding."""
    xd = _grid(0.25)
    assert np.array_equal(on_reversal(xd, V_SD), xd)


def test_a_point_is_on_the_reversal_within_three_standard_errors_not_beyond():
    assert on_reversal(_grid(0.0, 2.9e-4), V_SD)[16] == 0.0
    assert on_reversal(_grid(0.0, 3.1e-4), V_SD)[16] != 0.0
    # a record with no error on ẋ resolves every point: nothing is set to 0
    assert np.array_equal(on_reversal(_grid(0.0), 0.0), _grid(0.0))


def test_the_standard_error_of_the_smooth_velocity_matches_monte_carlo():
    """300 noisy sines (σ = 0.01 mm, 512 samples, 5 harmonics fitted): the spread of the fitted ẋ at a turning
    point against (2σ²ω²/N)·Σk², and the estimate from one record's residual within 10 %."""
    n, sigma, w = 512, 0.01, 2 * math.pi
    t = np.arange(n) / 64.0
    rng = np.random.default_rng(3)
    got, est = [], []
    for _ in range(300):
        x = A * np.sin(w * t) + rng.normal(0.0, sigma, n)
        f = fourier_x(t, x, w, 0.0)
        got.append(float(f(np.array([0.25]))[1][0]))
        est.append(velocity_sd(x - f(t)[0], w))
    closed = w * math.sqrt(2 * sigma**2 / n * 55)
    assert float(np.std(got)) == pytest.approx(closed, rel=0.1)
    assert float(np.median(est)) == pytest.approx(closed, rel=0.1)
