"""Two closed forms of the excitation generators that the derivative checks cannot see (each derivative follows the
same wrong time or frequency): the start-up's load steps are equally spaced in the rest of the record, and the
earthquake's near-fault pulse is a Gabor wavelet at half the ground frequency."""
from __future__ import annotations

import numpy as np
import pytest

from chainid.records import excitation as ex


def test_startup_steps_are_equally_spaced_after_the_ramp():
    n, fs, t_ramp, t_step = 8000, 400.0, 2.5, 0.5
    levels = [1.0, 3.0, 2.0]  # two steps: at t_ramp + (i + 1)·(T − t_ramp)/3 = 8.33 s and 14.17 s (T = 20 s)
    m = ex.startup_steps(n, fs, levels, t_ramp, t_step, f_run=2.0, A=1e-9, x_start=0.0)
    T = n / fs
    for i, (a, b) in enumerate(zip(levels[:-1], levels[1:])):
        ti = t_ramp + (i + 1) * (T - t_ramp) / 3.0
        # the quintic step is half way at ti + t_step/2 and complete at ti + t_step
        assert np.interp(ti + 0.5 * t_step, m.t, m.x) == pytest.approx(0.5 * (a + b), abs=1e-6)
        assert np.interp(ti - 1e-3, m.t, m.x) == pytest.approx(a, abs=1e-6)
        assert np.interp(ti + t_step + 1e-3, m.t, m.x) == pytest.approx(b, abs=1e-6)


def test_earthquake_pulse_is_at_half_the_ground_frequency():
    n, fs, f_g = 8000, 400.0, 2.0
    # a pulse a hundred times the ground motion's peak: near its centre x − x0 is the pulse to 1 %
    m = ex.earthquake(n, fs, 0.3, 2.0, np.random.default_rng(7), f_g=f_g, pulse=100.0)
    t_rise, sig = 0.15 * n / fs, 0.6 / (0.5 * f_g)
    near = np.abs(m.t - t_rise) < 1.5 * sig  # the Gaussian still holds a third of its peak there
    s = np.sign(m.x[near] - 2.0)
    crossings = m.t[near][1:][np.diff(s) != 0]
    # sin(2π·(f_g/2)·(t − t_rise)) crosses zero every 1/f_g s, at t_rise + k/f_g
    assert crossings.size >= 2
    assert np.diff(crossings) == pytest.approx(np.full(crossings.size - 1, 1.0 / f_g), abs=3.0 / fs)
    assert np.min(np.abs(crossings - t_rise)) < 3.0 / fs


def test_earthquake_acceleration_is_the_second_difference_of_its_displacement_to_1e_4():
    """ẍ = ë·g + 2·ė·ġ + e·g̈ under the envelope e (and the pulse's terms): at 2 kHz, 100 samples per period of the
    20 Hz band edge, the central second difference of x errs by about (2πf/fs)²/12 of ẍ at f, a few 1e-5 of the
    peak (measured: 4e-6); the envelope's cross term 2·ė·ġ is larger than 1e-4 of it.  (The permanent offset's
    quintic step has a jump in its third derivative at its start, where the difference errs by 8e-4: left out.)"""
    fs = 2000.0
    m = ex.earthquake(int(10 * fs), fs, 0.3, 2.0, np.random.default_rng(3), f_g=2.0, pulse=1.0)
    a = (m.x[2:] - 2.0 * m.x[1:-1] + m.x[:-2]) * fs**2
    inner = m.xdd[1:-1]
    assert np.all(np.isfinite(m.xdd))
    assert np.max(np.abs(a - inner)) <= 1e-4 * np.max(np.abs(inner))
