"""The step rule's log error ratio stays finite at extreme errors (:func:`chainid.gap.core.selection.loto_jackknife`).

A unit whose new error is 0 (clipped at 1e-300 N²) beside one whose old error is 1e10 N²: the ratio 1e310 overflows
a float, its logarithm does not.  Reference by hand: g = ½·(ln 1e10 − ln 1e-300) = ½·(23.02585 + 690.77553) and
g = ½·ln 4 for the other unit.
"""
from __future__ import annotations

import math
import warnings
from types import SimpleNamespace

import numpy as np
import pytest

from chainid.gap.core.selection import loto_jackknife


def test_an_error_of_zero_gives_a_finite_log_ratio_without_a_warning():
    prev = SimpleNamespace(loto_num={"a": 1e10, "b": 4.0})
    new = SimpleNamespace(loto_num={"a": 0.0, "b": 1.0})
    g1 = 0.5 * (math.log(1e10) + 300 * math.log(10))
    g2 = 0.5 * math.log(4.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mean, se = loto_jackknife(prev, new)
    assert mean == pytest.approx((g1 + g2) / 2, rel=1e-12)
    assert se == pytest.approx(float(np.std([g1, g2], ddof=1)) / math.sqrt(2), rel=1e-12)
