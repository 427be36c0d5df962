"""The slack warning of a chain record (:func:`chainid.records.validate.check_data`) is for x < 0 *throughout*
under a mean tension: a record whose x dips below zero only at its low points (a chain going slack for part of a
cycle) is not an offset zero and gets no warning; the same record shifted below zero throughout does.
"""
from __future__ import annotations

import warnings

import numpy as np
import pytest

from chainid.records.record import Record
from chainid.records.validate import RecordWarning, check_data

T = np.linspace(0.0, 1.0, 101)
F = 13000.0 + 500.0 * np.sin(2 * np.pi * 4 * T)  # N: a mean tension, positive throughout


def test_x_below_zero_only_at_its_low_points_is_no_warning():
    x = 0.1 + 0.2 * np.sin(2 * np.pi * 4 * T)  # mm: min -0.1, max 0.3
    assert x.min() < 0 < x.max()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_data(Record("part", T, x, F))


def test_the_same_record_below_zero_throughout_warns():
    x = -0.5 + 0.2 * np.sin(2 * np.pi * 4 * T)  # mm: max -0.3
    with pytest.warns(RecordWarning, match=r"test 'all': x < 0 throughout \(max x = -0\.3\d* mm\)"):
        check_data(Record("all", T, x, F))
