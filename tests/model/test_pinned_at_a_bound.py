"""The step rule's "pinned at a bound" test of a fitted effect parameter (chainid.model.effects.library.pinned): a
unit-box position u within 1e-6 of the upper bound (u >= 1 − 1e-6), or within 1e-6 of a nonzero lower bound
(u <= 1e-6), is pinned, both ends inclusive and alike; a zero lower bound (the effect absent) and an end the
library declares a legitimate limit of the form are not."""
from __future__ import annotations

import pytest

from chainid.model.effects.library import pinned


@pytest.mark.parametrize("u,expect", [(0.0, True), (1e-6, True), (2e-6, False), (0.5, False),
                                      (1.0 - 2e-6, False), (1.0 - 1e-6, True), (1.0, True)])
def test_pinned_within_a_millionth_of_either_bound_inclusive(u, expect):
    """Bouc–Wen's knee sharpness n has the box 0.3 .. 8 (a nonzero lower bound, no declared limit): positions
    0 and 1e-6 from either end are pinned, 2e-6 from an end is not (the same distance counts the same at both
    ends).  Bug caught: the lower end's ``u <= 1e-6`` → ``u < 1e-6`` (u = 1e-6 pinned at the top, not at the
    bottom)."""
    assert pinned("bouc_wen.n", u, 0.3) is expect


def test_a_zero_lower_bound_or_a_declared_limit_is_not_pinned():
    """friction.F_c at its zero lower bound is the effect absent, not a pinned form; Bouc–Wen's r at 0 or 1 and
    the deadband exponent p at its lower bound 1 are legitimate limits of the form (``Param.limits``); p at its
    upper bound (no limit declared there) is pinned."""
    assert pinned("friction.F_c", 0.0, 0.0) is False and pinned("friction.F_c", 1e-6, 0.0) is False
    assert pinned("bouc_wen.r", 0.0, 0.0) is False and pinned("bouc_wen.r", 1.0, 0.0) is False
    assert pinned("deadband.p", 0.0, 1.0) is False and pinned("deadband.p", 1e-6, 1.0) is False
    assert pinned("deadband.p", 1.0, 1.0) is True
