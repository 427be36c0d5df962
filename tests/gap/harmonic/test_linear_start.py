"""The linear base's start (:func:`chainid.gap.harmonic.bin_fits.linear_start`) on hand-made bin means: an exact
device F̄ = k·(x − x_ref) + m·ẍ·1e-3 + c_i·ẋ is recovered to rounding; a plan that cannot separate k from m (one
frequency, or no acceleration at all) gives {} so the caller keeps its own start.  Units N, mm, s, kg."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from chainid.gap.harmonic.bin_fits import linear_start

K, X_REF, M = 250.0, 1.5, 4.0


def _test(omega, A, c, a_scale=1.0):
    """One harmonic test's 16 phase-bin means about x0 = 2 mm (ẍ = −ω²(x − x0), scaled by ``a_scale``)."""
    ph = np.linspace(0.0, 2 * np.pi, 16, endpoint=False)
    x, xd = 2.0 + A * np.sin(ph), A * omega * np.cos(ph)
    xdd = -a_scale * omega ** 2 * A * np.sin(ph)
    F = K * (x - X_REF) + M * xdd * 1e-3 + c * xd
    return SimpleNamespace(grid={"x": x, "xd": xd, "xdd": xdd}, gridmean=lambda v: v, counts=np.full(16, 20.0),
                           sigma=1.0, Fbar=F)


def test_an_exact_device_is_recovered_with_its_mass_from_two_frequencies():
    got = linear_start([_test(20.0, 0.3, 2.0), _test(60.0, 0.2, 1.0)], fit_mass=True)
    assert got["spring.k"] == pytest.approx(K, rel=1e-9) and got["spring.x_ref"] == pytest.approx(X_REF, rel=1e-9)
    assert got["spring.m"] == pytest.approx(M, rel=1e-7)


def test_a_given_mass_is_taken_off_before_the_spring_is_fitted():
    got = linear_start([_test(20.0, 0.3, 2.0)], fit_mass=False, mass_kg=M)
    assert got["spring.k"] == pytest.approx(K, rel=1e-9) and "spring.m" not in got


def test_one_frequency_cannot_separate_spring_from_mass():
    assert linear_start([_test(20.0, 0.3, 2.0), _test(20.0, 0.1, 2.0)], fit_mass=True) == {}


def test_a_plan_with_no_acceleration_at_all_gives_no_start_rather_than_a_division_by_zero():
    tests = [_test(20.0, 0.3, 2.0, a_scale=0.0), _test(60.0, 0.2, 1.0, a_scale=0.0)]
    with np.errstate(all="raise"):
        assert linear_start(tests, fit_mass=True) == {}
