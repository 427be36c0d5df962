"""The elongation at a given force used by the Eq. 26 record (bisection of F_k(x) = F on [0, x_hi]).

Reference: a linear stand-in spring F_k = 10 N/mm · x, whose inverse is x = F/10 by hand.  The ends of the bracket
belong to it: the force at x = 0 gives x = 0 (not NaN); a force beyond F_k(x_hi) gives NaN.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.report.eq26 import _x_at_force


class Spring:
    def force(self, x):
        return 10.0 * np.asarray(x, float)


@pytest.mark.parametrize("F, x", [(25.0, 2.5), (49.0, 4.9), (0.0, 0.0), (50.0, 5.0)])
def test_the_elongation_of_a_linear_spring_is_F_over_k_up_to_the_ends(F, x):
    assert _x_at_force(Spring(), F, 5.0) == pytest.approx(x, abs=1e-12)


@pytest.mark.parametrize("F", [50.1, -1.0])
def test_a_force_outside_the_bracket_has_no_elongation(F):
    assert math.isnan(_x_at_force(Spring(), F, 5.0))
