"""The effect library (chainid.model.effects): each effect's force against its closed form, parameter bounds that
follow the data's scales, checks naming the parameter and its range, --effect parsing, the stiffness-side effects
that change Eq. 15.  Units mm, N, s."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.model.base import ChainModel, LinearModel
from chainid.model.effects import (
    EFFECT_NAMES,
    dahl_operator,
    effect_force,
    make_effect,
    parse_effect,
    play_operator,
    series_compliance_force,
    stick_slip,
)


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


MODEL = ChainModel()


def test_damping_law_effect_hook_by_hand():
    """`simulate --effect damping_law:...` adds (eta k_e(x0)/omega + 4 F_f/(pi omega A)) xdot to the model force."""
    omega, x0, A = 2.0, 2.0, 0.2
    t = np.linspace(0, 4 * 2 * np.pi / omega, 4 * 400 + 1)  # samples on the turning points: exact max/min
    psi = omega * t
    x, xd, xdd = x0 + A * np.sin(psi), A * omega * np.cos(psi), -A * omega**2 * np.sin(psi)
    F_model = 5000.0 + 100.0 * np.sin(psi)
    hook = parse_effect("damping_law:F_f=100", MODEL)
    expected = F_model + 4 * 100.0 / (math.pi * omega * A) * xd  # = F_model + 127.32 cos(psi)
    np.testing.assert_allclose(hook(t, x, xd, xdd, F_model), expected, rtol=1e-9, atol=1e-6)
    hook = parse_effect("damping_law:eta=0.3", MODEL)
    ke = float(MODEL.stiffness(np.array([x0]))[0])
    np.testing.assert_allclose(hook(t, x, xd, xdd, F_model), F_model + 0.3 * ke / omega * xd, rtol=1e-9, atol=1e-6)


def test_parse_effect_errors_and_operators():
    with pytest.raises(ValueError, match="unknown"):
        parse_effect("wobble:a=1", MODEL)
    with pytest.raises(ValueError, match="unknown parameter"):
        parse_effect("friction:Q=1", MODEL)
    with pytest.raises(ValueError, match=">= 0"):
        parse_effect("backlash:b=-1", MODEL)
    x = np.sin(np.linspace(0, 4 * np.pi, 401))
    y = play_operator(x, 0.1)
    assert np.max(np.abs(x - y)) == pytest.approx(0.1, abs=1e-9)
    s = stick_slip(x, np.cos(np.linspace(0, 4 * np.pi, 401)), 0.05)
    assert np.max(s) == pytest.approx(1.0) and np.min(s) == pytest.approx(-1.0)


W, A, X0 = 2 * math.pi * 2.0, 0.5, 3.0  # 2 Hz, 0.5 mm about 3 mm


def _sine(n=400, periods=1.0):
    t = np.linspace(0.0, periods * 2 * math.pi / W, n, endpoint=False)
    ps = W * t
    return t, X0 + A * np.sin(ps), W * A * np.cos(ps), -W * W * A * np.sin(ps)


# ---------------------------------------------------------------- effect force terms on a linear spring
def _effect(name, p, **kw):
    t, x, xd, xdd = _sine()
    spring = LinearModel(200.0, 1.0, 4.0)
    return effect_force(make_effect(name), p, spring, t, x, xd, xdd, W, A, X0, **kw), (t, x, xd, xdd)


def test_effect_force_terms_closed_form():
    """On k = 200 N/mm (x_ref 1 mm, m 4 kg), x = 3 + 0.5 sin(ωt): base = m·ẍ·1e-3 + k(x − 1);
    slack s: k(x − 1 − s); friction F_c (no stick): + F_c·sgn(ẋ); damping_law: extra c = η·k_e/ω + 4F_f/(πωA);
    sensor_delay τ: everything at t − τ (the damped velocity too)."""
    (F, v, extra), (t, x, xd, xdd) = _effect("slack", {"s": 0.2})
    base = 4.0 * xdd * 1e-3 + 200.0 * (x - 1.0)
    np.testing.assert_allclose(F, base - 200.0 * 0.2, rtol=1e-12)
    np.testing.assert_allclose(v, xd, rtol=0)
    assert not np.any(extra)
    (F, _, _), _ = _effect("friction", {"F_c": 30.0, "mu": 0.0, "x_s": 0.0})
    moving = np.abs(xd) > 0.05 * W * A
    np.testing.assert_allclose((F - base)[moving], 30.0 * np.sign(xd[moving]), rtol=1e-12)
    (F, _, _), _ = _effect("friction", {"F_c": 0.0, "mu": 0.1, "x_s": 0.0})
    np.testing.assert_allclose((F - base)[moving], 0.1 * np.abs(200.0 * (x - 1.0))[moving] * np.sign(xd[moving]),
                               rtol=1e-12)
    (F, _, extra), _ = _effect("damping_law", {"eta": 0.3, "F_f": 20.0})
    np.testing.assert_allclose(F, base, rtol=1e-12)
    np.testing.assert_allclose(extra, 0.3 * 200.0 / W + 80.0 / (math.pi * W * A), rtol=1e-12)

    def xfun(ts):
        ps = W * ts
        return X0 + A * np.sin(ps), W * A * np.cos(ps), -W * W * A * np.sin(ps)

    (F, v, extra), _ = _effect("sensor_delay", {"tau": 0.01}, xfun=xfun)
    xs, xds, xdds = xfun(t - 0.01)
    np.testing.assert_allclose(F, 4.0 * xdds * 1e-3 + 200.0 * (xs - 1.0), rtol=1e-12)
    np.testing.assert_allclose(v, xds, rtol=1e-12)
    assert not np.any(extra)
    with pytest.raises(ValueError, match="xfun"):
        _effect("sensor_delay", {"tau": 0.01})
    with pytest.raises(ValueError, match="chain"):
        _effect("contact_law", {"scale": 1.2})


def test_effect_check_names_the_parameter_and_its_range():
    e = make_effect("friction", F_scale=100.0, x_scale=2.0)
    e.check({"F_c": 500.0, "mu": 0.0})  # the bounds are inclusive: F_c up to 5·F_scale
    with pytest.raises(ValueError, match="F_c = 501.0 is out of range; valid range 0 to 500"):
        e.check({"F_c": 501.0})
    with pytest.raises(ValueError, match="unknown parameter 'tau'"):
        e.check({"tau": 0.1})
    with pytest.raises(ValueError, match="out of range"):
        e.check({"mu": float("nan")})


def test_series_compliance_of_a_large_compliance():
    """c = 1 mm/N on k = 100 N/mm: F = k·x/(1 + c·k) = x·100/101 (not the bare spring)."""
    from chainid.model.effects import series_compliance_force

    x = np.array([0.0, 0.5, 2.0])
    np.testing.assert_allclose(series_compliance_force(LinearModel(100.0, 0.0), x, 1.0), x * 100 / 101, rtol=1e-9)


# ---------------------------------------------------------------- stiffness-side effects and cycle_force
@pytest.mark.parametrize("name, p, compliance", [
    ("stiffness_level", {"scale": 2.0}, lambda F, cl, ch: cl / 2.0 * F + ch * F ** (2 / 3)),
    ("machine_compliance", {"c": 1e-5}, lambda F, cl, ch: (cl + 1e-5) * F + ch * F ** (2 / 3)),
    ("contact_law", {"scale": 1.5}, lambda F, cl, ch: cl * F + 1.5 * ch * F ** (2 / 3)),
    ("slack", {"s": 0.2}, lambda F, cl, ch: cl * F + ch * F ** (2 / 3) + 0.2),
])
def test_stiffness_side_effects_change_eq15(name, p, compliance):
    """Eq. 15 x = c_lin·F + c_hertz·F^(2/3) of the built-in chain changed by each stiffness-side effect (EA ×
    scale: c_lin/scale; a series compliance c: c_lin + c; the contact term × scale; a slack s: x + s): the
    modified model's force at that x is F (by hand, F = 5, 50, 500 kN)."""
    from chainid.model import kernels
    from chainid.model.base import ChainModel
    from chainid.model.effects import modify_model

    cl, ch = kernels.coefficients()
    m = modify_model(name, p, ChainModel())
    F = np.array([5e3, 5e4, 5e5])
    np.testing.assert_allclose(m.force(compliance(F, cl, ch)), F, rtol=1e-9)


def test_series_compliance_closed_form():
    """A spring k = 100 N/mm in series with c = 0.01 mm/N: F = k·x/(1 + c·k) = 50·x.
    Bug caught: the Newton step's denominator 1 + c·k changed."""
    x = np.array([0.0, 0.5, 2.0])
    np.testing.assert_allclose(series_compliance_force(LinearModel(100.0, 0.0), x, 0.01), 50.0 * x, rtol=1e-12)


def test_dahl_monotone_loading_closed_form():
    """From z = 0 on a monotone ramp: z = F_h·(1 − exp(−x/x_h)) (exact between samples).
    Bug caught: the operator's second output (the dissipation) returned instead of the force."""
    x = np.linspace(0.0, 1.0, 101)
    np.testing.assert_allclose(dahl_operator(x, 10.0, 0.2, periodic=False), 10.0 * (1 - np.exp(-x / 0.2)),
                               rtol=1e-9, atol=1e-12)


def _ramp():
    t = np.linspace(0.0, 1.0, 201)
    x = t.copy()  # mm, 1 mm/s
    return t, x, np.ones_like(t), np.zeros_like(t)


def test_effect_hook_backlash_on_a_ramp():
    """Backlash b = 0.2 mm (play half-width 0.1 mm) on a ramp from rest: F = k·max(0, x − 0.1).
    Bug caught: the memory operators' non-periodic rerun dispatched to the wrong effect."""
    model = LinearModel(100.0, 0.0)
    t, x, xd, xdd = _ramp()
    F = parse_effect("backlash:b=0.2", model)(t, x, xd, xdd, 100.0 * x)
    np.testing.assert_allclose(F, 100.0 * np.maximum(0.0, x - 0.1), atol=1e-9)


def test_effect_hook_friction_slides_after_stick():
    """Friction F_c = 30 N with stick travel x_s = 0.05 mm: past the stick travel the ramp slides, F = k·x + F_c.
    Bug caught: the friction rerun overwritten by another effect's branch."""
    model = LinearModel(100.0, 0.0)
    t, x, xd, xdd = _ramp()
    F = parse_effect("friction:F_c=30,x_s=0.05", model)(t, x, xd, xdd, 100.0 * x)
    late = x > 0.5
    np.testing.assert_allclose(F[late], 100.0 * x[late] + 30.0, rtol=1e-9)


def test_effect_force_stiffness_side_adds_the_inertia():
    """effect_force of stiffness_level: m·ẍ·1e-3 plus the changed chain's force (ChainModel(ea_scale=s) built
    directly).  Bug caught: the inertia and the force combined by anything but a sum."""
    from dataclasses import replace

    from chainid.model.base import ChainModel
    from chainid.model.effects import effect_force, make_effect

    model = ChainModel()
    x = np.linspace(0.5, 2.0, 7)
    xdd = np.linspace(-3e3, 3e3, 7)  # mm/s²
    F, _, _ = effect_force(make_effect("stiffness_level"), {"scale": 0.8}, model, np.linspace(0, 1, 7), x,
                           np.zeros(7), xdd, 10.0, 0.75, 1.25)
    expect = model.mass_kg * xdd * 1e-3 + replace(model, ea_scale=0.8).force(x)
    np.testing.assert_allclose(F, expect, rtol=1e-12)
    assert model.mass_kg > 0


# ---------------------------------------------------------------- seed-21 survivors (issue 20 §5)
def _runtime(s):
    """The string s built at run time (as from the command line: not the interned literal)."""
    return "".join(list(s))


def test_make_effect_of_a_runtime_name():
    """An effect named at run time (CLI `--effect hysteresis:…`) is the Dahl element with F_h, x_h.
    Bug caught: `name == "hysteresis"` → `name is "hysteresis"`."""
    from chainid.model.effects import make_effect

    e = make_effect(_runtime("hysteresis"), F_scale=100.0, x_scale=2.0)
    assert e.name == "hysteresis" and e.param_names == ("F_h", "x_h")
    assert e.bounds == ((0.0, 500.0), (2e-3, 20.0))  # (0, 5 F_scale), (1e-3, 10) x_scale: the documented ranges


@pytest.mark.parametrize("name", ["viscous_excess", "sensor_delay", "friction"])
def test_modify_model_refuses_an_effect_that_is_not_stiffness_side(name):
    """Only the four stiffness-side effects change the chain model; any other name is refused with the list
    (names after "slack" in the alphabet included: a comparison instead of equality would take them for slack).
    A stiffness-side effect changes only its own field: slack adds s, compliance adds c."""
    from chainid.chain.spec import default_chain
    from chainid.model.base import ChainModel
    from chainid.model.effects import modify_model

    m = ChainModel(default_chain())
    with pytest.raises(ValueError, match=rf"effect '{name}' is not a stiffness-side effect; those are: "
                                         "stiffness_level, contact_law, slack, machine_compliance"):
        modify_model(name, {"s": 0.5}, m)
    s = modify_model("slack", {"s": 0.5}, m)
    assert (s.slack, s.compliance, s.ea_scale) == (m.slack + 0.5, m.compliance, m.ea_scale)
    c = modify_model("machine_compliance", {"c": 1e-4}, m)
    assert (c.slack, c.compliance) == (m.slack, m.compliance + 1e-4)
