"""Pins of chainid.model's Eq. 1 pieces to closed forms (issue 20 §5, beyond the seed-21 survivors): the forward
prediction F = m·ẍ + F_k(x) + c_e·ẋ, the time-domain damping forms and laws, and each effect's force term on a
linear spring.  Units: mm, N, s, kg, rad/s.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.model.augmented import AugmentedModel
from chainid.model.base import LinearModel
from chainid.model.effects import make_effect
from chainid.model.laws import PolynomialLaw, ViscousLaw
from chainid.model.predict import predict_force
from chainid.model.timedamping import Damping, design

W, A, X0 = 2 * math.pi * 2.0, 0.5, 3.0  # 2 Hz, 0.5 mm about 3 mm


def _sine(n=400, periods=1.0):
    t = np.linspace(0.0, periods * 2 * math.pi / W, n, endpoint=False)
    ps = W * t
    return t, X0 + A * np.sin(ps), W * A * np.cos(ps), -W * W * A * np.sin(ps)


# ---------------------------------------------------------------- predict_force (Eq. 1)
def test_predict_force_closed_form_with_given_derivatives():
    """k = 200 N/mm, m = 4 kg (model) or 9 kg (given), c = 1.5 N·s/mm: F = m·ẍ·1e-3 + k·(x − 1) + c·ẋ."""
    t, x, xd, xdd = _sine()
    spring = LinearModel(200.0, 1.0, 4.0)
    F = predict_force(t, x, spring, 1.5, xdot=xd, xddot=xdd)
    np.testing.assert_allclose(F, 4.0 * xdd * 1e-3 + 200.0 * (x - 1.0) + 1.5 * xd, rtol=1e-13, atol=1e-9)
    F9 = predict_force(t, x, spring, 1.5, xdot=xd, xddot=xdd, mass_kg=9.0)
    np.testing.assert_allclose(F9 - F, 5.0 * xdd * 1e-3, rtol=1e-9, atol=1e-9)


def test_predict_force_differentiates_a_ramp_exactly():
    """x = 0.3·t on a non-uniform grid: ẋ = 0.3 and ẍ = 0 exactly by np.gradient, so F = k·x + c·0.3."""
    t = np.array([0.0, 0.1, 0.15, 0.4, 0.41, 1.0])
    F = predict_force(t, 0.3 * t, LinearModel(50.0, 0.0, 7.0), 2.0)
    np.testing.assert_allclose(F, 50.0 * 0.3 * t + 0.6, rtol=1e-12, atol=1e-12)


def test_predict_force_law_at_the_test_point_or_estimated_from_x():
    """A law is evaluated at (ω, A, x0): Eq. 21 with α = (0.001, 0.02, 0.4, 0.6, 0.5) at ω = 4π, A = 0.5 gives
    c = 0.001·ω² + 0.02·ω + 0.1 + 0.3 + 0.5 (by hand); without ω, A they are estimated from x(t) (a clean sine:
    the same c to 1e-6)."""
    t, x, xd, xdd = _sine(2000, periods=6.0)
    law = PolynomialLaw([0.001, 0.02, 0.4, 0.6, 0.5])
    c = 0.001 * W * W + 0.02 * W + 0.4 * A * A + 0.6 * A + 0.5
    spring = LinearModel(100.0, 0.0, 0.0)
    F = predict_force(t, x, spring, law, omega=W, A=A, x0=X0, xdot=xd, xddot=xdd)
    np.testing.assert_allclose(F, 100.0 * x + c * xd, rtol=1e-12)
    Fe = predict_force(t, x, spring, law, xdot=xd, xddot=xdd)
    np.testing.assert_allclose(Fe, 100.0 * x + c * xd, rtol=1e-6, atol=1e-6 * c * W * A)
    assert predict_force(t, x, spring, ViscousLaw([2.5]), xdot=xd, xddot=xdd)[0] == pytest.approx(
        100.0 * x[0] + 2.5 * xd[0], rel=1e-12)


# ---------------------------------------------------------------- timedamping
def test_design_columns_closed_form():
    """Eq. 21's columns (ω², ω, A², A, 1); coulomb 4/(πωA); hysteretic k_e/ω; sums side by side."""
    w, a, ke = np.array([2.0, 5.0]), np.array([0.5, 0.25]), np.array([100.0, 300.0])
    np.testing.assert_allclose(design("polynomial", w, a, ke), [[4, 2, 0.25, 0.5, 1], [25, 5, 0.0625, 0.25, 1]])
    np.testing.assert_allclose(design("viscous+coulomb+hysteretic", w, a, ke),
                               [[1, 4 / (math.pi * 1.0), 50.0], [1, 4 / (math.pi * 1.25), 60.0]], rtol=1e-14)
    with pytest.raises(ValueError, match="unknown"):
        design("cubic", w, a, ke)


def test_law_resolves_to_viscous_c_or_the_fitted_test_value():
    """viscous+coulomb c = c₁ + 4·F_f/(πωA) = 2 + 4·30/(π·10·0.5) (by hand); a test the law was fitted on uses its
    own c_e only when asked (fitted=True)."""
    d = Damping("law", law="viscous+coulomb", coefficients=[2.0, 30.0], per_test={"T1": 9.0})
    c = 2.0 + 120.0 / (math.pi * 5.0)
    assert d.ce(10.0, 0.5, 123.0) == pytest.approx(c, rel=1e-14)
    assert d.resolve(10.0, 0.5, 123.0).params == {"c": pytest.approx(c, rel=1e-14)}
    assert d.resolve(10.0, 0.5, 123.0, test="T1", fitted=True).params == {"c": 9.0}
    assert d.resolve(10.0, 0.5, 123.0, test="T1").params["c"] == pytest.approx(c, rel=1e-14)
    assert d.resolve(10.0, 0.5, 123.0, test="T2", fitted=True).params["c"] == pytest.approx(c, rel=1e-14)
    h = Damping("law", law="hysteretic", coefficients=[0.2]).resolve(10.0, 0.5, 150.0)
    assert h.form == "viscous" and h.params["c"] == pytest.approx(0.2 * 150.0 / 10.0, rel=1e-14)  # η·k_e/ω


def test_hysteretic_rule_dissipates_the_viscous_energy_per_cycle_in_quadrature():
    """Rule `hysteretic`: the Iwan distribution of equal energy per cycle: on x = x0 + A sin ψ its steady loop has
    the viscous loop's energy π·c·ω·A² and (the compensating spring) no in-phase first harmonic.
    c = 3 N·s/mm, ω = 4π rad/s, A = 0.5 mm: π·3·4π·0.25 = 29.61 N·mm."""
    d = Damping("law", law="viscous", coefficients=[3.0], rule="hysteretic").resolve(W, A, 0.0, x0=X0)
    assert d.form == "hysteretic" and d.params["eta_k"] == pytest.approx(3.0 * W, rel=1e-14)
    assert d.params["x_max"] == A and d.params["x_c"] == X0
    psi = np.linspace(0.0, 2 * math.pi, 4000, endpoint=False)
    x = X0 + A * np.sin(psi)
    F, _ = d.force(x, W * A * np.cos(psi), periodic=True)
    energy = -float(np.sum(F * np.gradient(np.sin(psi), psi) * A)) * (psi[1] - psi[0])  # ∮F dx with dx = A cos ψ dψ
    assert abs(energy) == pytest.approx(math.pi * 3.0 * W * A * A, rel=0.02)
    assert abs(2 * np.mean(F * np.sin(psi))) < 0.02 * abs(2 * np.mean(F * np.cos(psi)))


def test_damping_forms_closed_form():
    """none → 0; viscous c·ẋ; coulomb without stick F_c·sgn(ẋ) (0 at a reversal sample); a law unresolved is
    refused; an unknown form / parameter / rule or a negative value is refused naming it."""
    x = np.array([0.0, 1.0, 2.0, 1.0, 0.0])
    xd = np.array([1.0, 2.0, 0.0, -2.0, -1.0])
    assert not np.any(Damping("none").force(x, xd)[0])
    np.testing.assert_allclose(Damping("viscous", {"c": 2.5}).force(x, xd)[0], 2.5 * xd)
    np.testing.assert_allclose(Damping("coulomb", {"F_c": 40.0}).force(x, xd, periodic=False)[0],
                               [40.0, 40.0, 0.0, -40.0, -40.0])
    with pytest.raises(ValueError, match="resolved"):
        Damping("law", law="viscous", coefficients=[1.0]).force(x, xd)
    for kw, msg in ((dict(form="viscid"), "form"), (dict(form="coulomb", params={"c": 1.0}), "unknown parameter"),
                    (dict(form="coulomb", params={"F_c": -1.0}), "out of range"),
                    (dict(form="law", law="viscous", coefficients=[1.0, 2.0]), "1 coefficient"),
                    (dict(form="viscous", rule="stiff"), "rule")):
        with pytest.raises(ValueError, match=msg):
            Damping(**kw)
    assert Damping("viscous", {"c": -0.5}).params["c"] == -0.5  # an identified viscous c may be negative


# ---------------------------------------------------------------- effect force terms on a linear spring
def _effect(name, p, **kw):
    t, x, xd, xdd = _sine()
    spring = LinearModel(200.0, 1.0, 4.0)
    return make_effect(name).force(p, spring, t, x, xd, xdd, W, A, X0, **kw), (t, x, xd, xdd)


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


# ---------------------------------------------------------------- own-seed 804 survivors
def test_dahl_cycle_energy_closed_form_against_the_operator_loop():
    """4·F_h·(A − x_h·tanh(A/x_h)) against the loop area ∮F dx of the Dahl operator's steady cycle on ±A (another
    method: numerical integration): F_h = 50 N, x_h = 0.2 mm, A = 0.5 mm."""
    from chainid.model.operators import dahl_cycle_energy

    want = 4 * 50.0 * (0.5 - 0.2 * math.tanh(0.5 / 0.2))
    assert dahl_cycle_energy(50.0, 0.2, 0.5) == pytest.approx(want, rel=1e-14)
    psi = np.linspace(0.0, 2 * math.pi, 20001)
    x = 0.5 * np.sin(psi)
    from chainid.model.effects import dahl_operator

    F = dahl_operator(x, 50.0, 0.2, periodic=True)
    loop = abs(float(np.sum(0.5 * (F[1:] + F[:-1]) * np.diff(x))))
    assert loop == pytest.approx(want, rel=2e-3)


def test_series_compliance_of_a_large_compliance():
    """c = 1 mm/N on k = 100 N/mm: F = k·x/(1 + c·k) = x·100/101 (not the bare spring)."""
    from chainid.model.effects import series_compliance_force

    x = np.array([0.0, 0.5, 2.0])
    np.testing.assert_allclose(series_compliance_force(LinearModel(100.0, 0.0), x, 1.0), x * 100 / 101, rtol=1e-9)


def test_hysteretic_law_uses_the_given_mean_elongation():
    """c_e = η·k_e(x0)/ω on a spring whose tangent is 100·x0 N/mm: η = 0.2, ω = 4, x0 = 3 → 0.2·300/4 = 15 (by
    hand); without x0 the law refuses."""
    from chainid.model.laws import HystereticLaw

    class Stiffening:
        def stiffness(self, x):
            return 100.0 * np.asarray(x, float)

    law = HystereticLaw(Stiffening(), [0.2])
    assert law.predict(4.0, 0.5, 3.0)[0] == pytest.approx(15.0, rel=1e-12)
    with pytest.raises(ValueError, match="x0"):
        law.predict(4.0, 0.5)


def test_model_file_keeps_infinities_with_their_sign(tmp_path):
    """±inf is written as TOML inf / -inf and parses back with its sign; a model file holding them in keys the
    schema does not know (and n_bins = 3, below its range of 8 to 4096) is refused on load, naming the keys."""
    import tomllib

    from chainid.model.modelfile import load_model, save_model, to_toml

    ev = {"upper": math.inf, "lower": -math.inf, "n_bins": 3}
    text = to_toml({"evaluation": ev})
    assert "upper = inf" in text and "lower = -inf" in text
    back = tomllib.loads(text)["evaluation"]
    assert back["upper"] == math.inf and back["lower"] == -math.inf and back["n_bins"] == 3
    p = save_model(AugmentedModel(LinearModel(100.0, 0.0), info={"evaluation": ev}), tmp_path / "m.toml")
    with pytest.raises(ValueError, match=r"unknown keys evaluation\.upper, evaluation\.lower"):
        load_model(p)


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


def test_cycle_force_viscous_law_delay_and_coulomb_closed_form():
    """cycle_force on a linear spring k = 100 N/mm (x_ref 1, mass 0.5 kg): a viscous c = 2 adds 2·ẋ; a
    viscous+coulomb law resolved at the test's ω, A (c = 1 + 4·30/(π·ω·A)) adds c·ẋ; a delay τ evaluates the
    inputs at t − τ; a Coulomb form adds F_c·sgn(ẋ) in its periodic steady state, of the delayed inputs under a
    delay (bug caught: ``t − τ`` → ``t % τ`` in the rate-independent branch)."""
    from types import SimpleNamespace

    w, A = 2 * math.pi * 3.0, 0.5
    t = np.linspace(0.0, 1.0 / 3.0, 64, endpoint=False) + 0.5 / 3.0 / 64

    def xfun(ts):
        ps = w * ts
        return 2 + A * np.sin(ps), A * w * np.cos(ps), -A * w * w * np.sin(ps)

    x, xd, xdd = xfun(t)
    d = SimpleNamespace(grid={"t": t, "x": x, "xd": xd, "xdd": xdd}, omega=w, A=A, x0=2.0, xfun=xfun, test="T",
                        gridmean=lambda y: np.asarray(y, float))
    spring = LinearModel(100.0, 1.0, 0.5)
    base = 100.0 * (x - 1.0) + 0.5 * xdd * 1e-3
    m = AugmentedModel(spring, damping=Damping("viscous", {"c": 2.0}))
    np.testing.assert_allclose(m.cycle_force(d), base + 2.0 * xd, rtol=1e-12)
    law = AugmentedModel(spring, damping=Damping("law", law="viscous+coulomb", coefficients=[1.0, 30.0]))
    np.testing.assert_allclose(law.cycle_force(d), base + (1.0 + 120.0 / (math.pi * w * A)) * xd, rtol=1e-12)
    xs, xds, xdds = xfun(t - 0.01)
    late = AugmentedModel(spring, damping=Damping("viscous", {"c": 2.0}), delay_s=0.01)
    np.testing.assert_allclose(late.cycle_force(d), 100.0 * (xs - 1.0) + 0.5 * xdds * 1e-3 + 2.0 * xds, rtol=1e-12)
    cou = AugmentedModel(spring, damping=Damping("coulomb", {"F_c": 40.0}))
    np.testing.assert_allclose(cou.cycle_force(d), base + 40.0 * np.sign(xd), rtol=1e-12)
    # a rate-independent form under a delay: the Coulomb force too follows the inputs at t − τ
    late_cou = AugmentedModel(spring, damping=Damping("coulomb", {"F_c": 40.0}), delay_s=0.01)
    np.testing.assert_allclose(late_cou.cycle_force(d), 100.0 * (xs - 1.0) + 0.5 * xdds * 1e-3 + 40.0 * np.sign(xds),
                               rtol=1e-12)
