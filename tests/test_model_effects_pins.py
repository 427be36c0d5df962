"""Pins of the effect library's bounds (chainid.model.effects.make_effect; issue 20 §5, own mutation seeds of
mutH): the bounds are "set from the data scales", so a diagnosis of the same data in other force or length
units searches the same physical box.  Units: F N, x mm, τ s, ω rad/s."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.model.effects import EFFECT_NAMES, make_effect


def _by_unit(e, unit):
    return [(n, b, g) for n, u, b, g in zip(e.param_names, e.units, e.bounds, e.x0_guess) if u == unit]


@pytest.mark.parametrize("name", EFFECT_NAMES)
def test_effect_bounds_follow_the_data_scales(name):
    """Every force parameter [N] has bounds and start value proportional to the force scale (× 1000 when the data
    are given in mN) and reaching at least that scale (an effect as large as the data is admissible), every length
    parameter [mm] proportional to the displacement scale; dimensionless ones do not move; the delay's box is
    ± half the shortest period, π/ω_max (the docstring)."""
    a = make_effect(name, F_scale=2e3, x_scale=0.4, omega_max=20.0)
    f = make_effect(name, F_scale=2e6, x_scale=0.4, omega_max=20.0)
    x = make_effect(name, F_scale=2e3, x_scale=400.0, omega_max=20.0)
    assert a.param_names == f.param_names == x.param_names
    for (n, b, g), (_, bf, gf), (_, bx, gx) in zip(_by_unit(a, "N"), _by_unit(f, "N"), _by_unit(x, "N")):
        assert bf == pytest.approx(tuple(1e3 * v for v in b), rel=1e-12) and gf == pytest.approx(1e3 * g, rel=1e-12)
        assert bx == b and b[0] <= 0.0 and b[1] >= 2e3, n
    for (n, b, g), (_, bf, gf), (_, bx, gx) in zip(_by_unit(a, "mm"), _by_unit(f, "mm"), _by_unit(x, "mm")):
        assert bx == pytest.approx(tuple(1e3 * v for v in b), rel=1e-12) and gx == pytest.approx(1e3 * g, rel=1e-12)
        assert bf == b and b[1] > 0.0, n
    for (n, b, g), (_, bf, _), (_, bx, _) in zip(_by_unit(a, "-"), _by_unit(f, "-"), _by_unit(x, "-")):
        assert b == bf == bx and b[0] <= g <= b[1], n
    if name == "sensor_delay":
        assert a.bounds == ((-math.pi / 20.0, math.pi / 20.0),) and a.x0_guess == (0.0,)
    for e in (a, f, x):
        assert all(lo <= g <= hi for (lo, hi), g in zip(e.bounds, e.x0_guess))  # the start is inside the box


def test_effect_check_refuses_below_the_lower_bound_and_accepts_it():
    """Effect.check: lo <= v <= hi on both sides (the lower bound itself accepted, anything below refused with the
    range): friction's F_c and μ from 0, the slack offset from −5·x_scale, the stiffness level from 0.2."""
    fr = make_effect("friction", F_scale=100.0, x_scale=2.0)
    fr.check({"F_c": 0.0, "mu": 0.0, "x_s": 0.0})
    for k, v in (("F_c", -1e-9), ("mu", -0.01), ("x_s", -1.0)):
        with pytest.raises(ValueError, match=rf"effect 'friction': {k} = {v!r} is out of range; valid range 0 to "):
            fr.check({k: v})
    sl = make_effect("slack", x_scale=2.0)
    sl.check({"s": -10.0})
    with pytest.raises(ValueError, match=r"s = -10.5 is out of range; valid range -10 to 10"):
        sl.check({"s": -10.5})
    lv = make_effect("stiffness_level")
    lv.check({"scale": 0.2})
    with pytest.raises(ValueError, match=r"scale = 0.19 is out of range; valid range 0.2 to 5"):
        lv.check({"scale": 0.19})


@pytest.mark.parametrize("name", EFFECT_NAMES)
def test_an_effect_given_without_parameters_is_the_baseline(name):
    """``--effect NAME`` with no parameters takes the library's neutral defaults (no friction, no play, no offset,
    scale 1, the Hertz exponent 2/3, no delay, no extra damping), so the hook returns the baseline Eq. 1 force
    unchanged (to round-off) on a harmonic test of the paper chain."""
    from chainid.model.base import ChainModel
    from chainid.model.effects import parse_effect

    model = ChainModel()
    t = np.linspace(0.0, 2.0, 401)
    w, A = 2 * math.pi, 0.25
    x = 2.2 + A * np.sin(w * t)
    xd, xdd = A * w * np.cos(w * t), -A * w * w * np.sin(w * t)
    F_model = model.mass_kg * xdd * 1e-3 + model.force(x) + 300.0 * xd
    hook = parse_effect(name, model)
    if name == "contact_law":
        assert hook.effect_params == {"scale": 1.0, "beta": pytest.approx(2.0 / 3.0, rel=1e-15)}
    np.testing.assert_allclose(hook(t, x, xd, xdd, F_model), F_model, rtol=1e-9, atol=1e-6)


@pytest.mark.parametrize("spec", ["damping_law:eta=0.1,F_f=50", "friction:F_c=100", "contact_law:scale=1.2"])
def test_an_effect_hook_on_a_hold_without_motion_is_finite(spec):
    """A record segment that does not move (x constant, ẋ = ẍ = 0: a hold at the pretension) has no amplitude and
    no frequency: the hook still returns a finite force, the stiffness-side change of F_k and no velocity term
    (the extra damping multiplies ẋ = 0), not a division by zero."""
    from chainid.model.base import ChainModel
    from chainid.model.effects import parse_effect

    model = ChainModel()
    t = np.linspace(0.0, 1.0, 101)
    x = np.full(101, 2.2)
    z = np.zeros(101)
    F_model = model.force(x)
    out = parse_effect(spec, model)(t, x, z, z, F_model)
    assert np.all(np.isfinite(out))
    if spec.startswith("damping_law"):
        np.testing.assert_allclose(out, F_model, rtol=1e-12)
    if spec.startswith("contact_law"):
        np.testing.assert_allclose(out, ChainModel(hertz_scale=1.2).force(x), rtol=1e-12)


@pytest.mark.parametrize("name", ["friction", "hysteresis"])
def test_effect_bounds_follow_a_force_scale_under_one_newton(name):
    """A small device (force scale 0.02 N, displacement scale 0.001 mm) gets the same box as a 2 kN / 0.4 mm
    test scaled down by 1e5 in force and 400 in length: the scales are floored only at 1e-9 (a zero scale),
    never at 1 N or 1 mm.  Bug caught (seed 25): the force floor ``1e-9`` → ``1.000000001`` (the box of a 1 N
    test: friction up to 5 N where the data reach 0.02 N)."""
    big = make_effect(name, F_scale=2e3, x_scale=0.4)
    small = make_effect(name, F_scale=0.02, x_scale=1e-3)
    for (n, b, g), (_, bs, gs) in zip(_by_unit(big, "N"), _by_unit(small, "N")):
        assert bs == pytest.approx(tuple(v * 1e-5 for v in b), rel=1e-12) and gs == pytest.approx(g * 1e-5), n
    for (n, b, g), (_, bs, gs) in zip(_by_unit(big, "mm"), _by_unit(small, "mm")):
        assert bs == pytest.approx(tuple(v / 400.0 for v in b), rel=1e-12) and gs == pytest.approx(g / 400.0), n
