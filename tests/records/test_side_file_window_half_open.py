"""With a side file (omega, x0, A), :func:`chainid.records.validate.analyse_record` fits the phase and measures the
noise of x over the steady window half-open, [t_start, t_end), like every other identification window: a sample
exactly on t_end is not used.

A 2 Hz sine of 0.4 mm about 2 mm (theta = 0), 64 samples per period, 10 periods, with 5 mm added to the one sample
at t_end; the steady window is set on sample times exactly, t_start = t[128], t_end = t[384] (the cycle selection is
replaced by it).  Hand reference: over the samples 128 .. 383 the record is the side file's harmonic itself, so
the fitted phase is 0 and the RMS noise 0; the spike, if it were used, would give a noise of about
sqrt(5² / 257) = 0.31 mm (and the record would be refused: A = 0.4 mm < 3 x noise).
"""
from __future__ import annotations

import pytest

from chainid.records import validate
from chainid.records.record import Record
from chainid.signal.steady import select_steady
from window_cases import AMP, I0, I1, W, X0, on_samples, sine


def test_side_file_noise_and_phase_leave_out_the_sample_on_t_end(monkeypatch):
    t, x = sine()
    win = on_samples(select_steady(t, x, W, 0.0), t)
    monkeypatch.setattr(validate, "select_steady", lambda *a, **k: win)
    x[I1] += 5.0
    rec = Record("S", t, x, 1000.0 + 100.0 * x)
    est = validate.analyse_record(rec, (W, X0, AMP))
    assert est.source == "side file" and (est.omega, est.x0, est.A) == (W, X0, AMP)
    assert est.theta == pytest.approx(0.0, abs=1e-9)
    assert est.noise < 1e-9  # with the spike it would be about 0.31 mm
    assert (est.window.t_start, est.window.t_end) == (float(t[I0]), float(t[I1]))
