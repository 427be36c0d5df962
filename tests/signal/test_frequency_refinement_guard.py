"""A least-squares frequency that ran away from its start is not taken (:func:`chainid.signal.harmonic.refines`),
and a cycle count above the samples is a clear error, not a terabyte allocation (:mod:`chainid.signal.steady`).

On one machine the refinement of a clean 1 rad/s sine (4 cycles of 128 samples) from the FFT peak of its last
third (1.3 cycles: 1.25 rad/s) converged on 1.2e11 rad/s, whose cycle boundaries the steady-window search then
tried to allocate (3.39 TiB)."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.signal.harmonic import estimate_harmonic, refines
from chainid.signal.steady import select_steady

DT = 2 * math.pi / 128  # 128 samples a cycle of 1 rad/s
T = np.arange(512) * DT


def test_a_refinement_within_half_its_start_and_below_nyquist_is_taken():
    assert refines(1.0, 1.25, T)
    assert refines(1.9, 1.25, T) is False  # moved by more than half of 1.25 (0.625)
    assert refines(0.62, 1.25, T) is False
    assert refines(1.16e11, 1.25, T) is False
    nyquist = math.pi / DT  # 64 rad/s
    assert refines(0.99 * nyquist, 0.9 * nyquist, T) and not refines(1.01 * nyquist, 0.9 * nyquist, T)
    assert not refines(float("nan"), 1.0, T) and not refines(-1.0, 1.0, T)


def test_a_clean_sine_is_estimated_exactly():
    x = 2.0 + 0.1 * np.sin(T)
    e = estimate_harmonic(T, x)
    assert e.omega == pytest.approx(1.0, rel=1e-9) and e.A == pytest.approx(0.1, rel=1e-9)


def test_a_frequency_above_nyquist_names_itself_in_the_steady_window_search():
    x = 2.0 + 0.1 * np.sin(T)
    with pytest.raises(ValueError, match=r"omega = 1\.16e\+11 rad/s gives .* cycles over 512 samples"):
        select_steady(T, x, 1.16e11, 0.0)
