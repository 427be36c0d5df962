"""The stiffness models (chainid.model.base): ChainModel's name, mass, fields and contact law, LinearModel's
checks, force, stiffness and fit, by hand.  Units mm, N, N/mm, kg."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.chain.spec import default_chain
from chainid.model.base import ChainModel, LinearModel, model_for


def test_chain_model_name_mass_and_default():
    """The name states the kernel variant ("chain[<variant>]", as the reports print it); the moving mass is the
    links' mass, 4 kg/m × 16 links × 50 mm = 3.2 kg for the paper chain; model_for(None) is the built-in chain."""
    assert ChainModel().name == "chain[paper]" and ChainModel(variant="inner_bend").name == "chain[inner_bend]"
    assert ChainModel().mass_kg == pytest.approx(4.0 * 16 * 50.0 * 1e-3, rel=1e-12)
    assert model_for(None) == ChainModel(default_chain(), "paper")
    assert model_for(None, "shear").variant == "shear"


def test_linear_model_checks_name_field_value_and_range():
    for kw, msg in ((dict(k=-1.0), "LinearModel.k = -1.0 is invalid: valid range >= 0 N/mm"),
                    (dict(k=math.nan), "LinearModel.k = nan is invalid: valid range >= 0 N/mm"),
                    (dict(k=1.0, x_ref=math.inf), "LinearModel.x_ref = inf is invalid: must be finite (mm)"),
                    (dict(k=1.0, mass=-0.1), "LinearModel.mass = -0.1 is invalid: valid range >= 0 kg")):
        with pytest.raises(ValueError) as exc:
            LinearModel(**kw)
        assert str(exc.value) == msg
    m = LinearModel(0.0, 0.0, 0.0)  # the bounds themselves
    assert m.name == "linear" and m.mass_kg == 0.0


def test_linear_model_force_stiffness_and_fit_by_hand():
    """F = k(x − x_ref), k_e = k; the fit is least squares on F = k·x + b, x_ref = −b/k; a falling force line is
    no spring: k = 0 (x_ref 0); fewer than two samples or unequal lengths are refused with the counts."""
    m = LinearModel(500.0, 1.5, 2.0)
    np.testing.assert_allclose(m.force([1.5, 2.5, 0.5]), [0.0, 500.0, -500.0], rtol=1e-15)
    assert m.stiffness(np.zeros((2, 3))).tolist() == [[500.0] * 3] * 2 and m.mass_kg == 2.0
    x = np.array([1.0, 2.0, 3.0, 4.0])
    F = np.array([0.0, 510.0, 990.0, 1500.0])  # least squares by hand: Sxy/Sxx = 2490/5 = 498, b = 750 − 498·2.5
    f = LinearModel.fit(x, F, mass=3.2)
    assert f.k == pytest.approx(498.0, rel=1e-12) and f.x_ref == pytest.approx(495.0 / 498.0, rel=1e-12)
    assert f.mass == 3.2
    g = LinearModel.fit(x, -F)
    assert (g.k, g.x_ref) == (0.0, 0.0)
    with pytest.raises(ValueError, match=r"^LinearModel.fit needs x and F of equal length >= 2; got 1 and 1$"):
        LinearModel.fit([1.0], [2.0])
    with pytest.raises(ValueError, match=r"got 3 and 2$"):
        LinearModel.fit([1.0, 2.0, 3.0], [2.0, 3.0])


@pytest.mark.parametrize("beta", [0.5, 0.8, 1.2])
def test_contact_power_law_meets_hertz_at_the_reference_force(beta):
    """ChainModel docstring: with β set, c is chosen so that the approach equals the variant's Hertz approach
    (times hertz_scale) at contact_ref_force; so both springs reach F_ref at the same elongation (root finding
    on each force, not the kernels' inverse), and a different β only bends the curve away from it."""
    from scipy.optimize import brentq

    from chainid.model.base import ChainModel

    kw = {"hertz_scale": 1.3, "contact_ref_force": 5e3, "ea_scale": 0.9, "compliance": 1e-6}
    hertz, power = ChainModel(**kw), ChainModel(contact_exponent=beta, **kw)

    def x_at(m, F):
        return brentq(lambda x: float(m.force(np.array([x]))[0]) - F, 1e-9, 50.0, xtol=1e-14, rtol=1e-14)

    assert x_at(power, 5e3) == pytest.approx(x_at(hertz, 5e3), rel=1e-9)
    assert x_at(power, 2e4) != pytest.approx(x_at(hertz, 2e4), rel=1e-4)
    c_lin, c_h = hertz.coefficients
    assert power.coefficients == pytest.approx((c_lin, c_h * 5e3 ** (2 / 3 - beta), beta), rel=1e-12)
    base = ChainModel()
    assert c_lin == pytest.approx(base.coefficients[0] / 0.9 + 1e-6, rel=1e-12)
    assert c_h == pytest.approx(base.coefficients[1] * 1.3, rel=1e-12)
    # x = +inf: F = inf; the tangent tends to 1/c_lin (β < 1), 1/(c_lin + c) (β = 1) or 0 (β > 1)
    k_inf = {0.5: 1 / c_lin, 0.8: 1 / c_lin, 1.2: 0.0}[beta]
    assert power.force(np.array([np.inf]))[0] == np.inf
    assert power.stiffness(np.array([np.inf]))[0] == pytest.approx(k_inf, rel=1e-12)
    one = ChainModel(contact_exponent=1.0, **kw)
    assert one.stiffness(np.array([np.inf]))[0] == pytest.approx(1 / sum(one.coefficients[:2]), rel=1e-12)


@pytest.mark.parametrize("field,ok,bad,msg", [
    ("contact_exponent", (0.2, 1.5), (0.19, 1.51), "valid range 0.2 to 1.5"),
    ("ea_scale", (1e-3, 1e3), (0.99e-3, 1.01e3, float("nan")), "valid range 0.001 to 1000"),
    ("hertz_scale", (1e-9,), (0.0, -1.0, float("inf")), "valid range > 0"),
    ("compliance", (0.0,), (-1e-9, float("nan")), "valid range >= 0 mm/N"),
    ("contact_ref_force", (1e-9,), (0.0, float("inf")), "valid range > 0 N"),
    ("slack", (-0.5, 0.0), (float("nan"),), "must be a finite number of mm"),
])
def test_chain_model_fields_ranges_inclusive_and_named(field, ok, bad, msg):
    from chainid.model.base import ChainModel

    for v in ok:
        ChainModel(**{field: v})
    for v in bad:
        with pytest.raises(ValueError, match=rf"ChainModel\.{field} = .* is invalid: {msg}"):
            ChainModel(**{field: v})


def test_both_base_models_are_stiffness_models_at_run_time_and_a_bare_object_is_not():
    """``StiffnessModel`` is a public, run-time checkable protocol: user code may ask ``isinstance`` of a model."""
    from chainid.model.base import StiffnessModel

    assert isinstance(ChainModel(default_chain()), StiffnessModel)
    assert isinstance(LinearModel(100.0, 0.0), StiffnessModel)
    assert not isinstance(object(), StiffnessModel)
