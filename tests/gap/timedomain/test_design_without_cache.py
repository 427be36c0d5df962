"""The design of the time-domain model (:func:`chainid.gap.timedomain.design.build`) called as documented without a
cache (``cache`` is optional) gives the fixed force, columns and target that a cached call gives, and those match a
hand-built design of the linear base (x, ẍ·1e-3, ẋ, each minus its mean over the record).  This record's random
motion rolls off past ẍ's cut while its force has only noise there, so it is compared below the cut: the hand-built
columns and force pass scipy's 4th-order Butterworth at that cut, forward and backward
(:mod:`chainid.gap.timedomain.bandlimit`)."""
from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import butter, sosfiltfilt

import recovery_cases as rc
from chainid.gap.timedomain.data import prepare_time
from chainid.gap.timedomain.design import Base, ColumnCache, build


def _record():
    return prepare_time(rc.linear_random(n_rec=1, n=1000)[0], 4)


def test_cached_design_of_the_linear_base_is_the_hand_built_one():
    d = _record()
    assert np.isfinite(d.f_res) and d.f_res == d.kin.f_cut_a
    f, Phi, y = build(Base("linear"), [], {}, d, None, ColumnCache())
    sos = butter(4, d.f_res / (0.5 * d.fs), output="sos")
    hand = sosfiltfilt(sos, np.column_stack([d.x, d.xdd * 1e-3, d.xd]), axis=0)
    F = sosfiltfilt(sos, d.F)
    assert np.allclose(Phi, hand - hand.mean(axis=0), rtol=0, atol=1e-9 * np.abs(hand).max())
    assert np.allclose(y, F - F.mean(), rtol=0, atol=1e-9 * np.abs(F).max()) and np.all(f == 0.0)


def test_design_without_a_cache_is_the_cached_one():
    d = _record()
    ref = build(Base("linear"), ["hardening"], {}, d, None, ColumnCache())
    got = build(Base("linear"), ["hardening"], {}, d)
    for a, b in zip(got, ref):
        assert np.array_equal(a, b)


def test_column_cache_keeps_what_fits_and_drops_the_oldest_first():
    calls = []

    def make(n):
        def f():
            calls.append(n)
            return np.zeros(n)
        return f

    cache = ColumnCache(max_bytes=8 * 100)  # room for 100 float64s
    a = cache.get(("a",), make(30))
    assert cache.get(("a",), make(30)) is a and calls == [30]  # kept: made once
    big = cache.get(("big",), make(101))  # larger than the whole cache: returned, never kept
    assert big.size == 101 and ("big",) not in cache.store and cache.nbytes == 240
    cache.get(("b",), make(30))  # 240 + 240 <= 800: both kept
    assert list(cache.store) == [("a",), ("b",)] and cache.nbytes == 480
    cache.get(("c",), make(50))  # 480 + 400 > 800: the oldest (a) alone is dropped to make room
    assert list(cache.store) == [("b",), ("c",)] and cache.nbytes == 640
    assert cache.get(("b",), make(30)) is cache.store[("b",)] and calls == [30, 101, 30, 50]
