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
import math

import numpy as np
import pytest

from chainid.damping import identify
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


def _fit(rec: Record, monkeypatch) -> tuple[float, float]:
    est = analyse_record(_record(), allow_compression=True)
    win = dataclasses.replace(est.window, t_start=float(rec.t[I0]), t_end=float(rec.t[I1]),
                              cycles_kept=list(range((I1 - I0) // SPC)))
    est = dataclasses.replace(est, window=win)
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
