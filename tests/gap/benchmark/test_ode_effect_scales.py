"""The ODE world's effect strengths (chainid.gap.benchmark.odecases.effect_params) are dimensionally consistent:
a force parameter scales with the device's force scale S and nothing else does, a length with its amplitude A, a
speed with its speed scale v.  A rule that divides by a scale where it should multiply (or the reverse) fails."""
from __future__ import annotations

import numpy as np
import pytest

from chainid.gap.benchmark.odecases import effect_params

SC = {"S": 800.0, "A": 0.4, "v": 25.0, "k": 2000.0, "x_mean": 1.5, "f_hi": 4.0}
FORCES = {"F_c", "dF", "F_s", "F_h", "F_y"}
LENGTHS = {"x_s", "x_h", "x_y", "b", "s", "g"}
SPEEDS = {"v_s", "v_e"}


def _params(name, **scale):
    return effect_params(name, 1.3, {**SC, **scale}, np.random.default_rng(4))


@pytest.mark.parametrize("name", ["friction", "stribeck", "hysteresis", "bouc_wen", "backlash", "slack"])
@pytest.mark.parametrize("key, factor", [("S", 3.0), ("A", 2.0), ("v", 5.0)])
def test_each_parameter_scales_with_its_own_dimension_only(name, key, factor):
    base, scaled = _params(name), _params(name, **{key: SC[key] * factor})
    assert base.keys() == scaled.keys()
    own = {"S": FORCES, "A": LENGTHS, "v": SPEEDS}[key]
    for p, v in base.items():
        want = v * factor if p in own else v
        assert scaled[p] == pytest.approx(want, rel=1e-12), p
