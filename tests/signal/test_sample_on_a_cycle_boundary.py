"""Which cycle a sample lying exactly on a cycle boundary belongs to (chainid.signal.steady): cycle k spans
``omega t + theta`` in [2 pi k, 2 pi (k+1)), so the boundary sample is the *first* sample of the cycle that
starts there, never the last of the one before.  Units s, mm."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.signal.steady import select_steady


def test_a_sample_on_a_boundary_starts_the_next_cycle():
    """1 Hz sampled at 100 Hz from t = 0 (boundaries at 0, 1, 2, 3, 4 s, each on a sample), with the mean
    stepping from 3 to 3.5 mm at t = 1 s (the sample on the boundary is the first at 3.5 mm).  Cycle 0 holds
    samples 0..99, all at mean 3, so its fit is exact: mean 3 mm, amplitude 1 mm; cycles 1..3 hold samples at
    mean 3.5 only: mean 3.5 mm (hand: the per-cycle fit of c0 + slope u + a sin + b cos reproduces a pure sine
    on a constant exactly).  Bug caught: the search for the boundary samples ``b - eps_t`` → ``b + eps_t``
    (sample 100 would end cycle 0 and move its mean)."""
    w = 2 * math.pi
    t = np.arange(400) * 0.01
    x = 3.0 + np.sin(w * t) + np.where(t >= 1.0 - 1e-12, 0.5, 0.0)
    win = select_steady(t, x, w, 0.0, rel_tol=0.03, drop_first=False)
    assert win.n_cycles_total == 4
    assert win.cycle_means == pytest.approx([3.0, 3.5, 3.5, 3.5], abs=1e-9)
    assert win.cycle_amplitudes == pytest.approx([1.0, 1.0, 1.0, 1.0], abs=1e-9)
