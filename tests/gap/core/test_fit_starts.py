"""Start points of the fits (chainid.gap.core.fitgrid): the documented grids per number of free parameters."""
from __future__ import annotations

import numpy as np
import pytest


def _set(out, cols=slice(None)):
    return sorted(tuple(np.round(np.asarray(u, float)[cols], 12)) for u in out)


def test_start_set_of_one_free_parameter_is_the_documented_one():
    """``starts`` with one free parameter (its docstring): the default first, then GRID1, 0.5 − (0.01, 0.05, 0.2),
    around 0 when the range straddles it, the 40 delay midpoints, and ug × (0.5 … 3) for a scale or delay."""
    from chainid.gap.core.fitgrid import starts

    grid1 = [0.0, 0.003, 0.01, 0.03, 0.1, 0.3, 0.6]
    mid = [0.49, 0.45, 0.3]
    one = lambda key, ug, lo, hi: starts([key], [key.split(".")[0]], np.array([ug]), np.zeros(1, bool),  # noqa: E731
                                         np.array([lo]), np.array([hi]))
    out = one("friction.F_c", 0.02, 0.0, 50.0)  # a range from 0: no start around 0, no scale starts
    assert float(out[0][0]) == 0.02
    assert _set(out) == _set([[v] for v in [0.02] + grid1 + mid])
    z = 0.25  # range (−1, 3): 0 at u = 0.25
    out = one("backlash.b", 0.6, -1.0, 3.0)
    around = [z + s * g for g in (0.002, 0.01, 0.05, 0.15) for s in (-1, 1)]
    assert _set(out) == _set([[v] for v in [0.6] + grid1 + mid + around])
    out = one("stiffness_level.scale", 0.3, 0.5, 1.75)
    scale = [0.3 * f for f in (0.5, 0.7, 0.85, 1.2, 1.5, 2.0, 3.0)]
    assert _set(out) == _set([[v] for v in [0.3] + grid1 + mid + scale])
    out = one("sensor_delay.tau", 0.5, -0.2, 0.2)
    delay = [(i + 0.5) / 40 for i in range(40)]
    around = [0.5 + s * g for g in (0.002, 0.01, 0.05, 0.15) for s in (-1, 1)]
    scale = [min(0.5 * f, 1.0) for f in (0.5, 0.7, 0.85, 1.2, 1.5, 2.0, 3.0)]
    assert _set(out) == _set([[v] for v in [0.5] + grid1 + mid + around + delay + scale])


@pytest.mark.parametrize("effect, params, extra", [
    ("friction", ("F_c", "mu", "x_s"), [(a, 0.0, c) for a in (0.001, 0.003, 0.01, 0.03, 0.2)
                                        for c in (0.001, 0.003, 0.01, 0.03, 0.1, 0.4)]),
    ("contact_law", ("scale", "exponent"), [(a, b) for a in (0.05, 0.18, 0.4) for b in (0.2, 0.39, 0.6)]),
    ("hysteresis", ("F_h", "x_h"), [(a, b) for a in (0.01, 0.05, 0.2) for b in (0.005, 0.01, 0.02)]),
    ("backlash", ("b", "k2"), []),
])
def test_start_set_of_a_new_effect_with_several_parameters_is_the_documented_one(effect, params, extra):
    """Two or more free parameters: GRID2 × GRID2 (0, 0.003, 0.03, 0.2) over the first two (the others at the
    default), plus the effect's own documented starts (friction, contact law, hysteresis); the default first."""
    from chainid.gap.core.fitgrid import starts

    k = len(params)
    ug = np.full(k, 0.77)
    out = starts([f"{effect}.{p}" for p in params], [effect], ug, np.zeros(k, bool), np.zeros(k), np.ones(k))
    g2 = (0.0, 0.003, 0.03, 0.2)
    want = [tuple(ug)] + [(a, b) + (0.77,) * (k - 2) for a in g2 for b in g2]
    want += [tuple(e) + (0.77,) * (k - len(e)) for e in extra]
    assert np.array_equal(out[0], ug)
    assert _set(out) == _set(want)


def test_fit_start_points_follow_their_documentation():
    """``starts``: the default start first; a delay gets a grid over its whole range (± half the shortest period)
    at 1/40 of a period, i.e. the 40 midpoints (i + ½)/40; a scale or delay also starts around its neutral value
    (below and above it); a parameter whose range straddles 0 starts close to 0 on both sides; the linear spring
    of a --model linear baseline may soften a lot: every start again with k × 0.1 and × 0.01; parameters of
    effects already fitted (fixed) keep their value in every start; everything inside the unit box."""
    from chainid.gap.core.fitgrid import DELAY_GRID, starts

    ug = np.array([0.5])
    out = starts(["sensor_delay.tau"], ["sensor_delay"], ug, np.zeros(1, bool), np.array([-0.1]), np.array([0.1]))
    u = sorted({round(float(v[0]), 12) for v in out})
    assert np.allclose(out[0], ug)
    mids = [(i + 0.5) / DELAY_GRID for i in range(DELAY_GRID)]
    assert DELAY_GRID == 40 and all(any(abs(m - v) < 1e-12 for v in u) for m in mids)
    assert any(0.5 < v < 0.5 + 1e-2 for v in u) and any(0.5 - 1e-2 < v < 0.5 for v in u)  # close to τ = 0, both sides
    sc = starts(["stiffness_level.scale"], ["stiffness_level"], np.array([0.4]), np.zeros(1, bool), np.array([0.5]),
                np.array([1.75]))
    vals = [float(v[0]) for v in sc]
    assert any(0.2 <= v < 0.4 for v in vals) and any(0.4 < v <= 1.0 for v in vals)  # around the neutral 0.4
    assert min(vals) == 0.0 and all(0.0 <= v <= 1.0 for v in vals)
    # a linear spring and one fixed parameter of an earlier effect (slack.s = 0.3 of its range)
    keys = ["spring.k", "spring.x_ref", "slack.s", "friction.F_c", "friction.mu", "friction.x_s"]
    ug = np.array([0.4, 0.5, 0.3, 0.01, 0.0, 0.0])
    fixed = np.array([False, False, True, False, False, False])
    lo, hi = np.zeros(6), np.ones(6)
    out = starts(keys, ["slack", "friction"], ug, fixed, lo, hi)
    assert all(v[2] == 0.3 and v[1] == 0.5 for v in out)
    assert all(np.all((v >= 0) & (v <= 1)) for v in out)
    n = len(out) // 3  # the starts, then each with k × 0.1, then with k × 0.01
    assert len(out) == 3 * n
    for i in range(n):
        base = out[i]
        for j, f in ((1, 0.1), (2, 0.01)):
            np.testing.assert_allclose(out[j * n + i], np.concatenate([[base[0] * f], base[1:]]), rtol=1e-12)
    assert len({tuple(np.round(v[3:], 9)) for v in out}) > 10  # a grid over the new effect's parameters


def test_a_friction_on_a_linear_base_gets_its_stick_travel_starts_by_name():
    """On a linear base μ is not fitted: the free parameters are (F_c, x_s) and the friction starts set x_s by name
    (before, a positional (F_c, 0, x_s) put x_s at 0 and dropped the travel)."""
    from chainid.gap.core.fitgrid import starts

    keys = ["friction.F_c", "friction.x_s"]
    out = starts(keys, ["friction"], np.full(2, 0.77), np.zeros(2, bool), np.zeros(2), np.ones(2))
    got = {(round(float(u[0]), 6), round(float(u[1]), 6)) for u in out}
    want = {(a, c) for a in (0.001, 0.003, 0.01, 0.03, 0.2) for c in (0.001, 0.003, 0.01, 0.03, 0.1, 0.4)}
    assert want <= got
