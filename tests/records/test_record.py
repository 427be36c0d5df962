"""The Record type (chainid.records.record): float columns of one length, a half-open time window."""
from __future__ import annotations

import numpy as np
import pytest

from chainid.records.record import Record


# --- own-seed (701) mutation survivors -------------------------------------------------------------------------
def test_record_window_is_half_open():
    """``window(t0, t1)`` keeps t0 <= t < t1: t = 0..9 s, window(2, 5) → 2, 3, 4 (x and F alike); window(2.5, 5)
    → 3, 4.  Bug caught: ``t >= t_start`` → ``t == t_start``."""
    from chainid.records.record import Record

    t = np.arange(10.0)
    r = Record("a", t, 10.0 + t, 100.0 * t)
    w = r.window(2.0, 5.0)
    assert w.t.tolist() == [2.0, 3.0, 4.0] and w.x.tolist() == [12.0, 13.0, 14.0]
    assert w.F.tolist() == [200.0, 300.0, 400.0] and w.test == "a"
    assert r.window(2.5, 5.0).t.tolist() == [3.0, 4.0]


def test_record_converts_to_float_arrays_and_refuses_ragged_or_two_dimensional_columns():
    """A Record holds float arrays and a string id; columns of different lengths or of two dimensions are one
    error naming the test and the lengths."""
    r = Record(7, [0, 1, 2], [1, 2, 3], [4, 5, 6])
    assert r.test == "7" and r.t.dtype == r.x.dtype == r.F.dtype == np.float64
    with pytest.raises(ValueError, match=r"^test 'a': t, x and F must have the same length \(got 3, 2, 3\)$"):
        Record("a", [0, 1, 2], [1, 2], [4, 5, 6])
    with pytest.raises(ValueError, match=r"^test 'b': t, x and F must be one-dimensional arrays$"):
        Record("b", np.zeros((2, 2)), np.zeros((2, 2)), np.zeros((2, 2)))
