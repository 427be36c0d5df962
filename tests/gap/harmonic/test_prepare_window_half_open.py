"""The diagnosis' harmonic route folds each record's steady window half-open, [t_start, t_end)
(:func:`chainid.gap.harmonic.prepare.prepare_test`): a sample exactly on t_end is not among the test's samples.

The record is a linear spring with a dashpot sampled 64 times per period, its window set on sample times exactly
(the analysis is replaced by that estimate).  The reference is the record's own samples t_start <= t < t_end,
indexed here: the prepared force is those samples, and a spike of 10⁶ N on the sample at t_end changes neither
the prepared force nor its bin means.
"""
from __future__ import annotations

import dataclasses

import numpy as np

from chainid.gap.harmonic import prepare
from chainid.records.validate import analyse_record
from window_cases import I0, I1, on_samples
from window_cases import spring_record as _record


def test_a_sample_on_t_end_is_not_prepared(monkeypatch):
    clean = _record()
    est = analyse_record(clean, allow_compression=True)
    est = dataclasses.replace(est, window=on_samples(est.window, clean.t))
    monkeypatch.setattr(prepare, "_estimate", lambda rec, allow, tol: est)
    d = prepare.prepare_test(clean)
    assert np.array_equal(d.F, clean.F[I0:I1])  # exactly the samples [I0, I1)
    spiked = prepare.prepare_test(_record(spike_at=I1))
    assert np.array_equal(spiked.F, d.F) and np.array_equal(spiked.Fbar, d.Fbar)
