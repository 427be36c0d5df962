"""The augmented model's force over a record (chainid.model.augmented) against closed forms: a linear spring with
mass, viscous damping, a delay and Coulomb friction; memory effects run forward whatever the sampling.
Units mm, N, s, kg."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.model import LinearModel
from chainid.model.augmented import AugmentedModel
from chainid.model.timedamping import Damping


def test_force_closed_form_linear_viscous_mass_delay_and_non_uniform_sampling():
    k, xr, c, m, tau, w = 200.0, 0.5, 3.0, 2.0, 0.01, 5.0
    model = AugmentedModel(LinearModel(k, xr), [], Damping("viscous", {"c": c}), tau, m)
    rng = np.random.default_rng(0)
    for t in (np.linspace(0, 4, 8001), np.sort(np.r_[0.0, rng.uniform(0, 4, 8000), 4.0])):
        x = 1.0 + 0.3 * np.sin(w * t)
        F = model.force(t, x)
        ts = t - tau  # closed form at t − τ (inside the record)
        ref = m * 1e-3 * (-0.3 * w * w * np.sin(w * ts)) + k * (1.0 + 0.3 * np.sin(w * ts) - xr) + c * 0.3 * w * np.cos(w * ts)
        inner = (t > 0.05) & (t < 3.95)
        assert np.max(np.abs(F - ref)[inner]) < 2e-3 * np.max(np.abs(ref))


def test_memory_effects_run_forward_and_do_not_depend_on_the_sampling():
    model = AugmentedModel(LinearModel(100.0, 0.0), [("friction", {"F_c": 30.0, "x_s": 0.05}),
                                                      ("hysteresis", {"F_h": 20.0, "x_h": 0.1})])
    t = np.linspace(0, 3, 3001)
    x = 0.4 * np.sin(2 * math.pi * t) * np.minimum(t, 1.0)
    keep = np.unique(np.r_[np.random.default_rng(1).choice(t.size, 400, replace=False), 0, t.size - 1])
    # the non-uniform subset keeps every reversal of x (the path of a rate-independent operator)
    rev = np.flatnonzero(np.diff(np.sign(np.diff(x))) != 0) + 1
    keep = np.unique(np.r_[keep, rev])
    Fu, Fn = model.force(t, x), model.force(t[keep], x[keep])
    assert np.max(np.abs(Fn - Fu[keep])) < 1e-9 * np.max(np.abs(Fu))


W, A, X0 = 2 * math.pi * 2.0, 0.5, 3.0  # 2 Hz, 0.5 mm about 3 mm


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


def test_augmented_force_refuses_repeated_time():
    """Two equal time stamps are not strictly increasing.  Bug caught: <= 0 made < 0."""
    m = AugmentedModel(LinearModel(100.0, 0.0), [], Damping("viscous", {"c": 1.0}), 0.0, 0.0)
    with pytest.raises(ValueError, match="strictly increasing"):
        m.force([0.0, 0.1, 0.1, 0.2], [0.0, 1.0, 1.0, 2.0])


@pytest.mark.parametrize("which", ["xd", "xdd"])
@pytest.mark.parametrize("n", [3, 5])
def test_augmented_force_refuses_a_velocity_or_acceleration_of_another_length(which, n):
    """Given ẋ or ẍ must have the shape of t, longer or shorter.  Bug caught: != made < (a longer one passed)."""
    m = AugmentedModel(LinearModel(100.0, 0.0), [], Damping("viscous", {"c": 1.0}), 0.0, 0.0)
    t = [0.0, 0.1, 0.2, 0.3]
    with pytest.raises(ValueError, match=r"xd and xdd must have the shape of t \(4,\)"):
        m.force(t, [0.0, 1.0, 2.0, 3.0], **{which: np.zeros(n)})


def test_cycle_parts_total_mass_closed_form():
    """With a moving mass m = 3 kg set on a linear spring k = 100 N/mm (x_ref = 1 mm) whose own mass is 0.5 kg,
    the undamped force is k·(x − x_ref) + m·ẍ·1e-3 on x = 2 + 0.5·sin(ω t) (closed form, ẍ = −ω²·0.5·sin).
    Bug caught: the mass correction (m − m_base)·ẍ subtracted instead of added."""
    from types import SimpleNamespace

    w = 2 * math.pi * 3.0
    t = np.linspace(0.0, 1.0 / 3.0, 64, endpoint=False)
    x, xd, xdd = 2 + 0.5 * np.sin(w * t), 0.5 * w * np.cos(w * t), -0.5 * w * w * np.sin(w * t)
    d = SimpleNamespace(grid={"t": t, "x": x, "xd": xd, "xdd": xdd}, omega=w, A=0.5, x0=2.0, xfun=None,
                        gridmean=lambda y: np.asarray(y, float))
    m = AugmentedModel(LinearModel(100.0, 1.0, 0.5), mass_kg=3.0)
    Fn, v = m.cycle_parts(d)
    np.testing.assert_allclose(Fn, 100.0 * (x - 1.0) + 3.0 * xdd * 1e-3, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(v, xd, rtol=1e-12)


def test_covariate_terms_move_each_parameter_by_slope_times_condition_change():
    """p + slope·(cov − ref) (module docstring) on the three kinds of target: the damping's c, the spring's k and an
    effect's parameter.  ``machine_compliance.c`` shares the name ``c`` with the damping and must move only the
    compliance; by hand at i = 1.5 A (ref 0.5 A): c 2 + 3·1 = 5 N·s/mm, k 100 − 10·1 = 90 N/mm, compliance
    1e-4 + 2e-5·1 = 1.2e-4 mm/N, F_c 30 + 4·1 = 34 N."""
    model = AugmentedModel(LinearModel(100.0, 0.0), [("friction", {"F_c": 30.0, "x_s": 0.05}),
                                                      ("machine_compliance", {"c": 1e-4})],
                           Damping("viscous", {"c": 2.0}),
                           covariate_terms={"damping.c@i": 3.0, "spring.k@i": -10.0, "friction.F_c@i": 4.0,
                                            "machine_compliance.c@i": 2e-5},
                           covariate_refs={"i": 0.5})
    at = model.at_conditions({"i": 1.5})
    assert at.damping.params["c"] == pytest.approx(5.0, rel=1e-12)
    assert at.base.k == pytest.approx(90.0, rel=1e-12)
    got = dict(at.effects)
    assert got["friction"]["F_c"] == pytest.approx(34.0, rel=1e-12)
    assert got["machine_compliance"]["c"] == pytest.approx(1.2e-4, rel=1e-12)
    assert at.covariate_terms == {}
    assert model.damping.params["c"] == 2.0 and dict(model.effects)["friction"]["F_c"] == 30.0  # the model unchanged
    with pytest.raises(ValueError, match="covariate 'i'"):
        model.at_conditions({"p": 1.0})
