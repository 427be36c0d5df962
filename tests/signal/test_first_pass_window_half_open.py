"""The first-pass search of the harmonic estimate (:func:`chainid.signal.harmonic.estimate_harmonic`, step 2) uses
its provisional steady window half-open, [t_start, t_end), like every other identification window: a sample exactly
on t_end is not among the samples its first candidate fit sees.

A 2 Hz sine of 0.4 mm about 2 mm, 64 samples per period, 10 periods, with 5 mm added to the one sample at t_end; the
provisional window (the first cycle selection, the one called with ``drift_tol = inf``) is set on sample times
exactly, t_start = t[128], t_end = t[384].  The candidate fits are recorded as they are called.  The reference is
the index range written here: the first candidate fit gets exactly the samples 128 .. 383, so neither t_end nor the
spike on it.
"""
from __future__ import annotations

import math

import numpy as np

from chainid.signal import harmonic
from chainid.signal.steady import select_steady
from window_cases import AMP, I0, I1, W, X0, on_samples, sine


def test_the_first_pass_candidate_fit_leaves_out_the_sample_on_t_end(monkeypatch):
    t, x = sine()
    x[I1] += 5.0
    real = select_steady
    provisional = on_samples(real(t, x, W, 0.0), t)

    def steady(tt, xx, w, theta, **kw):
        # only the first pass is lenient on the drift: that call gets the window on sample times
        return provisional if kw.get("drift_tol") == math.inf else real(tt, xx, w, theta, **kw)

    seen: list[tuple[np.ndarray, np.ndarray]] = []
    nls = harmonic._nls_harmonic

    def spy(tt, xx, w0):
        seen.append((tt.copy(), xx.copy()))
        return nls(tt, xx, w0)

    monkeypatch.setattr(harmonic, "select_steady", steady)
    monkeypatch.setattr(harmonic, "_nls_harmonic", spy)
    harmonic.estimate_harmonic(t, x)
    assert seen, "no candidate fit was made"
    t_first, x_first = seen[0]
    assert t_first.size == I1 - I0 == 256
    assert np.array_equal(t_first, t[I0:I1])  # exactly the samples [I0, I1)
    assert t_first[-1] < t[I1]
    assert np.array_equal(x_first, x[I0:I1]) and float(np.max(x_first)) <= X0 + AMP + 1e-12  # the spike is out
