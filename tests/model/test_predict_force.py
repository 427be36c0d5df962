"""predict_force (chainid.model.predict) against F = m·ẍ·1e-3 + F_k(x) + c·ẋ in closed form.  Units mm, N, s, kg."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.model.base import LinearModel
from chainid.model.laws import PolynomialLaw, ViscousLaw
from chainid.model.predict import predict_force


W, A, X0 = 2 * math.pi * 2.0, 0.5, 3.0  # 2 Hz, 0.5 mm about 3 mm


def _sine(n=400, periods=1.0):
    t = np.linspace(0.0, periods * 2 * math.pi / W, n, endpoint=False)
    ps = W * t
    return t, X0 + A * np.sin(ps), W * A * np.cos(ps), -W * W * A * np.sin(ps)


# ---------------------------------------------------------------- predict_force (Eq. 1)
def test_predict_force_closed_form_with_given_derivatives():
    """k = 200 N/mm, m = 4 kg (model) or 9 kg (given), c = 1.5 N·s/mm: F = m·ẍ·1e-3 + k·(x − 1) + c·ẋ."""
    t, x, xd, xdd = _sine()
    spring = LinearModel(200.0, 1.0, 4.0)
    F = predict_force(t, x, spring, 1.5, xdot=xd, xddot=xdd)
    np.testing.assert_allclose(F, 4.0 * xdd * 1e-3 + 200.0 * (x - 1.0) + 1.5 * xd, rtol=1e-13, atol=1e-9)
    F9 = predict_force(t, x, spring, 1.5, xdot=xd, xddot=xdd, mass_kg=9.0)
    np.testing.assert_allclose(F9 - F, 5.0 * xdd * 1e-3, rtol=1e-9, atol=1e-9)


def test_predict_force_differentiates_a_ramp_exactly():
    """x = 0.3·t on a non-uniform grid: ẋ = 0.3 and ẍ = 0 exactly by np.gradient, so F = k·x + c·0.3."""
    t = np.array([0.0, 0.1, 0.15, 0.4, 0.41, 1.0])
    F = predict_force(t, 0.3 * t, LinearModel(50.0, 0.0, 7.0), 2.0)
    np.testing.assert_allclose(F, 50.0 * 0.3 * t + 0.6, rtol=1e-12, atol=1e-12)


def test_predict_force_law_at_the_test_point_or_estimated_from_x():
    """A law is evaluated at (ω, A, x0): Eq. 21 with α = (0.001, 0.02, 0.4, 0.6, 0.5) at ω = 4π, A = 0.5 gives
    c = 0.001·ω² + 0.02·ω + 0.1 + 0.3 + 0.5 (by hand); without ω, A they are estimated from x(t) (a clean sine:
    the same c to 1e-6)."""
    t, x, xd, xdd = _sine(2000, periods=6.0)
    law = PolynomialLaw([0.001, 0.02, 0.4, 0.6, 0.5])
    c = 0.001 * W * W + 0.02 * W + 0.4 * A * A + 0.6 * A + 0.5
    spring = LinearModel(100.0, 0.0, 0.0)
    F = predict_force(t, x, spring, law, omega=W, A=A, x0=X0, xdot=xd, xddot=xdd)
    np.testing.assert_allclose(F, 100.0 * x + c * xd, rtol=1e-12)
    Fe = predict_force(t, x, spring, law, xdot=xd, xddot=xdd)
    np.testing.assert_allclose(Fe, 100.0 * x + c * xd, rtol=1e-6, atol=1e-6 * c * W * A)
    assert predict_force(t, x, spring, ViscousLaw([2.5]), xdot=xd, xddot=xdd)[0] == pytest.approx(
        100.0 * x[0] + 2.5 * xd[0], rel=1e-12)
