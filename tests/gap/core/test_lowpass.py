"""The filter estimator's padding and its predicted error near the ends (:mod:`chainid.gap.core.lowpass`).

References: polynomials continued in closed form by the padding; the stationary error budget
(:func:`chainid.gap.core.kinematics.error_budget`, the filter's and the difference's gains in closed form) inside a
record; and, near the ends, the RMS error over 20 records of one spectrum whose ẋ and ẍ are known in closed form
(:mod:`sim_devices`: random-phase multisines).
"""
from __future__ import annotations

import numpy as np
import pytest

import sim_devices as sd
from chainid.gap.core import kinematics as K
from chainid.gap.core import lowpass as LP
from chainid.gap.core.noise import excitation_band


def test_the_padding_continues_a_cubic_exactly():
    """x a cubic: its padding with the full curvature is the cubic itself beyond both ends (to rounding)."""
    u = np.arange(200, dtype=float)
    q = lambda s: 0.3 + 0.02 * s - 1e-4 * s ** 2 + 2e-7 * s ** 3  # noqa: E731
    got = LP.pad_odd(q(u), 30, 12)
    want = q(np.arange(-30, 230, dtype=float))
    assert np.max(np.abs(got - want)) < 1e-9 * np.max(np.abs(want))


def test_without_its_curvature_the_padding_is_the_odd_reflection_of_a_line():
    """ρ = 0: a straight line continues exactly (its odd reflection about the end value), a parabola does not."""
    u = np.arange(100, dtype=float)
    got = LP.pad_odd(0.5 + 0.01 * u, 20, 10, rho=0.0)
    assert np.allclose(got, 0.5 + 0.01 * np.arange(-20, 120), rtol=0, atol=1e-12)
    bent = LP.pad_odd(1e-3 * u ** 2, 20, 10, rho=0.0)
    assert bent[0] == pytest.approx(-1e-3 * 20 ** 2, rel=1e-9)  # 2·0 − x(20): the curvature flips


def test_curvature_weight_is_one_without_noise_and_zero_without_motion():
    f = np.linspace(0.0, 250.0, 1001)
    S = np.where((f > 1) & (f < 10), 1e-3, 0.0)
    assert LP.curvature_weight(f, S, 500.0, 13, 0.0) == 1.0
    assert LP.curvature_weight(f, np.zeros_like(f), 500.0, 13, 1e-3) == 0.0


def test_curvature_weight_is_a_half_where_the_fitted_curvatures_noise_equals_its_signal():
    """The noise variance of the cubic's u² coefficient over k = 13 samples by Monte Carlo (8 000 draws of white
    noise σ = 1 µm through np.polyfit), and a line at 5 Hz whose curvature a₂ = ẍ·h²/2 has that mean square
    (E[ẍ²] = S·(2π·5)⁴): the weight is 1/2 within the Monte Carlo's error."""
    rng = np.random.default_rng(3)
    u = np.arange(13, dtype=float)
    var_mc = float(np.var(np.polyfit(u, rng.normal(0.0, 1e-3, (13, 8000)), 3)[1]))
    fs = 500.0
    S_line = var_mc / ((0.5 / fs ** 2) ** 2 * (2 * np.pi * 5.0) ** 4)
    f = np.array([0.0, 5.0, 10.0])
    assert LP.curvature_weight(f, np.array([0.0, S_line, 0.0]), fs, 13, 1e-3) == pytest.approx(0.5, abs=0.02)


def _record(kind: str, seed: int):
    """(t, x, ẋ, ẍ, measured x, σ_x): 8 s at 500 Hz of a 0.5-10 Hz multisine (RMS 1 mm, σ_x 1 µm) or 6 s at 1 kHz
    of a 12-20 Hz one (RMS 0.5 mm, σ_x 0.1 µm), off the frequency grid (not periodic)."""
    if kind == "broadband":
        n, fs, band, rms, sx = 4000, 500.0, (0.5, 10.0), 1.0, 1e-3
    else:
        n, fs, band, rms, sx = 6000, 1000.0, (12.0, 20.0), 0.5, 1e-4
    t = sd.sample_times(n, fs)
    x, xd, xdd = sd.multisine(n / fs, band[0], band[1], rms, 0.0, seed=400 + seed, periodic=False)(t)
    return t, x, xd, xdd, x + np.random.default_rng(seed).normal(0.0, sx, n), sx


def _spectrum(t, xm):
    fs = K.sample_rate(t)
    fb = excitation_band(t, xm)
    sx = K.displacement_noise(xm, fs, fb)
    f, P, floor = K.periodogram(xm, fs, window=True)
    return fs, fb, sx, f, K.signal_power(P, floor, windowed=True, continuous=False)


@pytest.mark.parametrize("order", [0, 1, 2])
def test_the_end_profile_settles_on_the_stationary_budget(order):
    """Far enough from the end (its last row, three periods of the cut in) the profile is the closed-form
    stationary budget of the cut, within 2 %."""
    t, *_, xm, _ = _record("broadband", 0)
    fs, fb, sx, f, S = _spectrum(t, xm)
    prof = LP.end_profile(f, S, fs, 3.0 * fb, fb, sx, t.size)
    budget = K.error_budget(f, S, fs, 3.0 * fb, sx, order)[0]
    for side in (0, 1):
        assert prof[side, order, -1] == pytest.approx(budget, rel=0.02)
    assert prof[0, order, 0] > 2.0 * budget  # the first sample rests on the padding


@pytest.mark.parametrize("kind, mult", [("broadband", 3.0), ("broadband", 1.5), ("narrowband", 2.0),
                                        ("narrowband", 8.0)])
def test_the_end_profile_is_the_rms_error_over_records_of_one_spectrum(kind, mult):
    """The filter at a fixed cut (mult × the band edge) on 40 records: the RMS error of ẋ and ẍ over the first and
    the last 8 samples, each end apart, is its predicted profile's within 25 % (one record's error there varies
    with the phase of its motion: the profile is the expectation; over 40 records its RMS is known to about 10 %,
    a narrowband record's ends having few degrees of freedom)."""
    act = np.zeros((2, 2, 8))
    pred = np.zeros((2, 2, 8))
    for seed in range(40):
        t, x, xd, xdd, xm, _ = _record(kind, seed)
        fs, fb, sx, f, S = _spectrum(t, xm)
        est = LP.filtered(t, xm, mult * fb, fb)
        prof = LP.end_profile(f, S, fs, mult * fb, fb, sx, t.size)
        for side, rows in enumerate((np.arange(8), t.size - 1 - np.arange(8))):
            for i, (e, true) in enumerate(((est[1], xd), (est[2], xdd))):
                act[side, i] += (e[rows] - true[rows]) ** 2
                pred[side, i] += prof[side, i + 1, :8] ** 2
    ratio = np.sqrt(act.sum(axis=2) / pred.sum(axis=2))
    assert np.all((ratio > 0.8) & (ratio < 1.25)), ratio


def test_the_derivative_of_a_quadratic_is_exact_at_every_sample():
    """Five-point stencil inside, np.gradient's second-order formulas at the two samples of each end: all exact for a
    quadratic y = 3 + 2t − 5t² on a uniform grid (dy/dt = 2 − 10t)."""
    from chainid.gap.core.lowpass import derivative

    t = 0.01 * np.arange(40)
    d = derivative(3.0 + 2.0 * t - 5.0 * t**2, t)
    np.testing.assert_allclose(d, 2.0 - 10.0 * t, rtol=0, atol=1e-10)
