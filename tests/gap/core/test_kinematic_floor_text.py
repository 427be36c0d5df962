"""The chain's text states the residual against the kinematic floor (what the true model would leave on the
estimated ẋ, ẍ) only where that floor tells more than the force noise, and says when the fit is below it (the
floor is then an upper bound, as on the real friction damper: 2.78 kN floor, residual 6.6 dB under it)."""
from __future__ import annotations

import math

from chainid.gap.core.verdict import kinematic_floor_text


def _res(kf: float, nf: float, resid: float) -> dict:
    return {"kinematic_floor_N": kf, "noise_floor_N": nf, "db_over_kinematic_floor": 20 * math.log10(resid / kf)}


def test_a_residual_over_the_floor_is_stated_in_db():
    assert kinematic_floor_text(_res(10.0, 2.0, 20.0)) == " (+6.0 dB over the kinematic floor 10 N)"


def test_a_residual_under_the_floor_says_the_floor_is_an_upper_bound():
    text = kinematic_floor_text(_res(2780.0, 36.0, 2780.0 * 10 ** (-6.6 / 20)))
    assert text == (" (below the kinematic floor 2.78e+03 N by 6.6 dB: the kinematics' predicted error is an upper "
                    "bound here)")


def test_a_floor_within_1_db_of_the_noise_is_not_stated():
    assert kinematic_floor_text(_res(2.2, 2.0, 20.0)) == ""  # 0.83 dB over the noise
