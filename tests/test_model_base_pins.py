"""Pins of the stiffness models' small contract (chainid.model.base; issue 20 §5, own mutation seeds of mutH):
names, masses, the linear spring's checks and its least-squares fit, by hand.  Units: mm, N, kg."""
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
