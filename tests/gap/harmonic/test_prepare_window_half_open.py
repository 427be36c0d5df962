"""The diagnosis' harmonic route folds each record's steady window half-open, [t_start, t_end)
(:func:`chainid.gap.harmonic.prepare.prepare_test`): a sample exactly on t_end is not among the test's samples.

The record is a linear spring with a dashpot sampled 64 times per period, its window set on sample times exactly
(the analysis is replaced by that estimate).  The reference is the record's own samples t_start <= t < t_end,
indexed here: the prepared force is those samples, and a spike of 10⁶ N on the sample at t_end changes neither
the prepared force nor its bin means.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from chainid.gap.harmonic import prepare
from chainid.records.record import Record
from chainid.records.validate import analyse_record

K, XR, C, F_HZ, X0, AMP = 300.0, 0.1, 5.0, 2.0, 2.0, 0.4
W = 2 * math.pi * F_HZ
SPC = 64
DT = 1.0 / (F_HZ * SPC)
I0, I1 = 2 * SPC, 6 * SPC


def _record(spike_at: int | None = None) -> Record:
    t = np.arange(10 * SPC + 1) * DT
    x = X0 + AMP * np.sin(W * t)
    F = K * (x - XR) + C * AMP * W * np.cos(W * t)
    if spike_at is not None:
        F[spike_at] += 1e6
    return Record("h", t, x, F)


def test_a_sample_on_t_end_is_not_prepared(monkeypatch):
    clean = _record()
    est = analyse_record(clean, allow_compression=True)
    win = dataclasses.replace(est.window, t_start=float(clean.t[I0]), t_end=float(clean.t[I1]),
                              cycles_kept=list(range((I1 - I0) // SPC)))
    est = dataclasses.replace(est, window=win)
    monkeypatch.setattr(prepare, "_estimate", lambda rec, allow, tol: est)
    d = prepare.prepare_test(clean)
    assert np.array_equal(d.F, clean.F[I0:I1])  # exactly the samples [I0, I1)
    spiked = prepare.prepare_test(_record(spike_at=I1))
    assert np.array_equal(spiked.F, d.F) and np.array_equal(spiked.Fbar, d.Fbar)
