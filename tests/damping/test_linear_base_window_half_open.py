"""The linear spring fitted for ``--model linear`` without ``--k``
(:func:`chainid.damping.identify.linear_model_from_records`) uses each record's steady window half-open,
[t_start, t_end): a sample exactly on t_end is not used.

The record is a linear spring with a dashpot, F = k (x − x_ref) + c·ẋ, 64 samples per period, its window set on
sample times exactly (the analysis is replaced by that estimate).  The reference is a hand least-squares line
F = k·x + b over the samples t_start <= t < t_end (numpy polyfit, written here); a spike of 10⁶ N on the sample at
t_end must change nothing, a spike on the sample at t_start must.
"""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from chainid.damping import identify
from chainid.records.record import Record
from chainid.records.validate import analyse_record
from window_cases import I0, I1, K, XR, on_samples
from window_cases import spring_record as _record


def _fit(rec: Record, monkeypatch) -> tuple[float, float]:
    est = analyse_record(_record(), allow_compression=True)
    est = dataclasses.replace(est, window=on_samples(est.window, rec.t))
    monkeypatch.setattr(identify, "try_analyse", lambda r, **kw: (est, None))
    m = identify.linear_model_from_records([rec])
    return float(m.k), float(m.x_ref)


def test_a_sample_on_t_end_is_not_used_by_the_linear_base(monkeypatch):
    clean = _record()
    k, x_ref = _fit(clean, monkeypatch)
    slope, b = np.polyfit(clean.x[I0:I1], clean.F[I0:I1], 1)
    assert k == pytest.approx(slope, rel=1e-9) and x_ref == pytest.approx(-b / slope, rel=1e-9)
    assert k == pytest.approx(K, rel=1e-3) and x_ref == pytest.approx(XR, abs=1e-3)  # whole cycles: c·ẋ averages out
    assert _fit(_record(spike_at=I1), monkeypatch) == (k, x_ref)
    assert _fit(_record(spike_at=I0), monkeypatch)[0] != k
