"""The design of the time-domain model (:func:`chainid.gap.timedomain.design.build`) called as documented without a
cache (``cache`` is optional) gives the fixed force, columns and target that a cached call gives, and those match a
hand-built design of the linear base (x, ẍ·1e-3, ẋ, each minus its mean over the record)."""
from __future__ import annotations

import numpy as np
import pytest

import recovery_cases as rc
from chainid.gap.timedomain.data import prepare_time
from chainid.gap.timedomain.design import Base, ColumnCache, build


def _record():
    return prepare_time(rc.linear_random(n_rec=1, n=1000)[0], 4)


def test_cached_design_of_the_linear_base_is_the_hand_built_one():
    d = _record()
    f, Phi, y = build(Base("linear"), [], {}, d, None, ColumnCache())
    hand = np.column_stack([d.x, d.xdd * 1e-3, d.xd])
    assert np.allclose(Phi, hand - hand.mean(axis=0), rtol=0, atol=1e-12)
    assert np.allclose(y, d.F - d.F.mean(), rtol=0, atol=1e-12) and np.all(f == 0.0)


def test_design_without_a_cache_is_the_cached_one():
    d = _record()
    ref = build(Base("linear"), ["hardening"], {}, d, None, ColumnCache())
    got = build(Base("linear"), ["hardening"], {}, d)
    for a, b in zip(got, ref):
        assert np.array_equal(a, b)
