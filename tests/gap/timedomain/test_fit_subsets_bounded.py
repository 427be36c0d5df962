"""The shape search's fit subsets are bounded: a record held out whole keeps a token subset (nothing changes
numerically), and past ``FIT_TOTAL`` samples the training records keep evenly spaced contiguous windows of
``FIT_WINDOW_PERIODS`` low-edge periods each."""
from __future__ import annotations

import math

import numpy as np
import pytest

import recovery_cases as rc
from chainid.gap.timedomain import data as D
from chainid.gap.timedomain.route import build_problem


def _tdata(n_rec: int = 4, n: int = 4000, band: tuple[float, float] = rc.BAND_LIN) -> list:
    return [D.prepare_time(r, 4) for r in rc.linear_random(n_rec=n_rec, n=n, band=band)]


def test_under_the_bound_every_training_subset_is_kept_and_a_whole_held_out_record_keeps_64_samples():
    data = _tdata()
    sub = D.fit_subsets(data, held=["r3"], total=10**9)
    for d in data[:3]:
        assert np.array_equal(sub[d.test], d.fit_idx)
    assert np.array_equal(sub["r3"], data[3].fit_idx[:64])


def test_over_the_bound_each_record_keeps_its_share_as_contiguous_windows_of_four_low_periods():
    data = _tdata(n=16000, band=(2.0, 8.0))  # 2 s low-edge periods: windows of ~400 samples, several per record
    full = sum(d.fit_idx.size for d in data)
    total = full // 8
    sub = D.fit_subsets(data, total=total)
    kept = sum(v.size for v in sub.values())
    assert total - 4 * 64 <= kept <= total  # each record its floor(share), within a window's rounding
    for d in data:
        idx = sub[d.test]
        pos = np.searchsorted(d.fit_idx, idx)
        assert np.array_equal(d.fit_idx[pos], idx)  # a subset of the record's own fit subset
        runs = np.split(pos, np.flatnonzero(np.diff(pos) != 1) + 1)
        dt = float(d.t[d.fit_idx[1]] - d.t[d.fit_idx[0]])
        want = min(idx.size, max(64, math.ceil(4.0 / d.f_low / dt)))  # four periods of the low band edge
        for r in runs:
            assert r.size >= min(want, idx.size // len(runs))
        starts = np.array([r[0] for r in runs])
        assert starts.size >= 3  # several windows, evenly spaced over the record, the last one ending at its end
        gaps = np.diff(starts)
        assert gaps.max() - gaps.min() <= 1
        assert runs[-1][-1] == d.fit_idx.size - 1


def test_a_record_held_out_whole_weighs_nothing_in_the_search_so_its_token_subset_changes_no_fit():
    """The same fit with the held-out record's whole subset (the former rule) and with its 64-sample token."""
    recs = rc.linear_random(n_rec=4, extra=lambda mo, t: 0.4 * np.sign(mo(t)[1]))
    prob = build_problem(recs, ["r3"], 0, None)
    assert prob._fit_idx["r3"].size == 64
    got = prob.fit(["friction"]).params
    prob._fit_idx["r3"] = prob.tdata[3].fit_idx
    prob._cache.store.clear()
    ref = prob.fit(["friction"]).params
    for k, v in ref.items():
        assert got[k] == pytest.approx(v, rel=1e-9, abs=1e-12), k
