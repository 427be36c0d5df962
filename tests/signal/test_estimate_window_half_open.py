"""The harmonic estimate's final fit of x (:func:`chainid.signal.harmonic.estimate_harmonic`, step 3) uses the
steady window half-open, [t_start, t_end): a sample exactly on t_end is not fitted.

A 2 Hz sine of 0.4 mm about 2 mm, 64 samples per period, with 5 mm added to the one sample at t_end; the steady
window is set on sample times exactly (the cycle selection is replaced by it).  The reference is a hand linear
least-squares fit of x0 + a·sin ωt + b·cos ωt over the samples t_start <= t < t_end at the estimate's own ω
(numpy lstsq, written here), which the spike cannot reach.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.signal import harmonic
from chainid.signal.steady import select_steady
from window_cases import I0, I1, W, on_samples, sine


def test_the_final_fit_leaves_out_the_sample_on_t_end(monkeypatch):
    t, x = sine()
    win = on_samples(select_steady(t, x, W, 0.0), t)
    monkeypatch.setattr(harmonic, "select_steady", lambda *a, **k: win)
    xs = x.copy()
    xs[I1] += 5.0
    est = harmonic.estimate_harmonic(t, xs)
    tt = t[I0:I1]
    M = np.column_stack([np.ones_like(tt), np.sin(est.omega * tt), np.cos(est.omega * tt)])
    x0, a, b = np.linalg.lstsq(M, xs[I0:I1], rcond=None)[0]
    assert est.x0 == pytest.approx(x0, rel=1e-9, abs=1e-12)
    assert est.A == pytest.approx(math.hypot(a, b), rel=1e-9)
    assert est.noise < 1e-6  # the window's samples are the clean sine
