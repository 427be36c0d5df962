"""The identification window is half-open, [t_start, t_end): a sample exactly on t_end is not used.

The record is a linear spring with a dashpot, F = k (x − x_ref) + c·ẋ, sampled 64 times per period; the window is
set on sample times exactly.  The reference c_e is a hand least-squares fit of F − k (x − x_ref) on 1, sin ψ, cos ψ
over the samples t_start <= t < t_end (numpy lstsq, written here); a spike on the sample at t_end must change
nothing.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from chainid.damping.identify import identify_test
from chainid.model.base import LinearModel
from chainid.records.record import Record
from chainid.records.validate import analyse_record

K, XR, C, F_HZ, X0, AMP = 300.0, 0.1, 5.0, 2.0, 2.0, 0.4
W = 2 * math.pi * F_HZ
SPC = 64
DT = 1.0 / (F_HZ * SPC)


def _record(spike_at: int | None = None) -> Record:
    t = np.arange(10 * SPC + 1) * DT
    x = X0 + AMP * np.sin(W * t)
    F = K * (x - XR) + C * AMP * W * np.cos(W * t)
    if spike_at is not None:
        F = F.copy()
        F[spike_at] += 1e6
    return Record("h", t, x, F)


def _hand_ce(rec: Record, est, i0: int, i1: int) -> float:
    t = rec.t[i0:i1]  # [i0, i1): the half-open window
    psi = est.phase(t)
    y = rec.F[i0:i1] - K * (rec.x[i0:i1] - XR)
    M = np.column_stack([np.ones_like(t), np.sin(psi), np.cos(psi)])
    coef = np.linalg.lstsq(M, y, rcond=None)[0]
    return float(coef[2] / (est.omega * est.A))


@pytest.mark.parametrize("i0, i1", [(2 * SPC, 6 * SPC), (3 * SPC, 8 * SPC)])
def test_a_sample_on_t_end_is_not_used(i0, i1):
    clean = _record()
    est = analyse_record(clean, allow_compression=True)
    win = dataclasses.replace(est.window, t_start=float(clean.t[i0]), t_end=float(clean.t[i1]),
                              cycles_kept=list(range((i1 - i0) // SPC)))
    est = dataclasses.replace(est, window=win)
    model = LinearModel(K, XR, mass=0.0)
    r_clean = identify_test(clean, model, estimate=est)
    spiked = _record(spike_at=i1)  # 1e6 N on the sample at t_end exactly
    r_spiked = identify_test(spiked, model, estimate=est)
    assert r_spiked.c_e == r_clean.c_e
    assert r_spiked.F_ac == r_clean.F_ac and r_spiked.W == r_clean.W
    assert r_clean.c_e == pytest.approx(_hand_ce(clean, est, i0, i1), rel=1e-9)
    assert r_clean.c_e == pytest.approx(C, rel=1e-3)  # and the dashpot itself (the estimate's ω, A are fitted)
    # while the sample at t_start is used: a spike there moves c_e
    assert identify_test(_record(spike_at=i0), model, estimate=est).c_e != r_clean.c_e


def test_record_window_is_half_open():
    rec = _record()
    sub = rec.window(float(rec.t[10]), float(rec.t[20]))
    assert sub.t.size == 10
    assert sub.t[0] == rec.t[10] and sub.t[-1] == rec.t[19]
