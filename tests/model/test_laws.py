"""Damping laws (chainid.model.laws): each formula evaluated by hand, parameter counts, the fit and its refusals,
leave-one-out leverages (without an M × M matrix), the ranking, rebuilding a law from its dict.
Units N·s/mm, rad/s, mm."""
from __future__ import annotations

import math
import tracemalloc

import numpy as np
import pytest

from chainid.model.laws import (
    CombinedLaw,
    CoulombLaw,
    DampingLaw,
    HystereticLaw,
    PolynomialLaw,
    ViscousLaw,
    default_laws,
    fit_law,
    law_from_dict,
    leverages,
    rank_laws,
)

from stand_ins import LinearSpring


W = np.array([1.0, 2.0, 3.0, 1.5, 2.5, 3.5, 0.5])


A = np.array([0.2, 0.3, 0.4, 0.25, 0.35, 0.3, 0.22])


X0 = np.full(7, 2.2)


def _eval_formula(law, w, a, x0, model=None):
    """The law's formula text as a Python expression (w, A, pi, k_e(x0) and the parameter names)."""
    rhs = law.formula().replace(" (Eq. 21)", "")
    rhs = rhs.split("c_e = ", 1)[1] if rhs.startswith("c_e = ") else rhs
    names = dict(zip(law.param_names, law.params))
    names.update({"a%d" % (i + 1): v for i, v in enumerate(law.params)} if law.name == "polynomial" else {})
    env = {"w": w, "A": a, "x0": x0, "pi": math.pi, "k_e": (lambda x: model.stiffness(x)) if model else None,
           **names}
    return eval(rhs.replace("^", "**"), {"__builtins__": {}}, env)


def test_each_formula_computes_what_the_law_predicts():
    """The formula a law states (in reports and the JSON) is the law it predicts: each evaluated by hand at seven
    (ω, A, x0) equals ``predict``; a combined law's formula is its parts' right-hand sides joined by " + " and its
    name their names joined by "+"."""
    model = LinearSpring(12_000.0)
    laws = [PolynomialLaw([1.0, -2.0, 30.0, 4.0, 50.0]), ViscousLaw([7.0]), CoulombLaw([100.0]),
            HystereticLaw(model, [0.1]), CombinedLaw([ViscousLaw(), CoulombLaw()], [5.0, 100.0]),
            CombinedLaw([ViscousLaw(), HystereticLaw(model)], [5.0, 0.2])]
    for law in laws:
        want = np.broadcast_to(_eval_formula(law, W, A, X0, model), W.shape)
        np.testing.assert_allclose(law.predict(W, A, X0), want, rtol=1e-12, err_msg=law.name)
    comb = laws[4]
    assert comb.name == "viscous+coulomb" and comb.formula() == "c + 4*F_f/(pi*w*A)"
    assert comb.param_names == ("c", "F_f") and comb.param_units == ("N s/mm", "N")
    assert CombinedLaw().name == "viscous+coulomb"  # the documented default parts
    d = laws[2].to_dict()
    assert d == {"name": "coulomb", "formula": "c_e = 4*F_f/(pi*w*A)", "param_names": ["F_f"], "params": [100.0]}
    assert ViscousLaw().to_dict()["params"] is None


def test_laws_refuse_wrong_parameter_counts_and_missing_inputs():
    """A parameter vector of the wrong length names the law, the count and the expected names; predicting without
    parameters is refused; the hysteretic law needs x0 for every test (k_e is taken there)."""
    with pytest.raises(ValueError) as exc:
        PolynomialLaw([1.0, 2.0, 3.0])
    assert str(exc.value) == "polynomial: params has 3 values; expected 5 (alpha1, alpha2, alpha3, alpha4, alpha5)"
    with pytest.raises(ValueError, match=r"^viscous: not fitted and no params given$"):
        ViscousLaw().predict(1.0, 0.2)
    with pytest.raises(ValueError, match=r"hysteretic law needs x0 \[mm\] for every test"):
        HystereticLaw(LinearSpring(), [0.1]).predict(W, A)
    with pytest.raises(ValueError, match=r"hysteretic law needs x0"):
        HystereticLaw(LinearSpring(), [0.1]).predict(W, A, np.where(np.arange(7) == 3, np.nan, 2.2))


def test_fit_law_refusals_name_the_problem():
    """fit_law: sizes must agree; at least max(min_tests, p + 1) tests (a 5-parameter law needs 6 even with
    min_tests = 3; a 1-parameter law fits 2 with min_tests = 2); finite inputs; ω and A > 0 for every test."""
    c = np.full(7, 100.0)
    with pytest.raises(ValueError, match=r"^omega/A have 7 values but c_e has 6$"):
        fit_law(ViscousLaw(), W, A, c[:6])
    with pytest.raises(ValueError, match=r"^polynomial law: 5 test\(s\) given; at least 6 are needed"):
        fit_law(PolynomialLaw(), W[:5], A[:5], c[:5], min_tests=3)
    f = fit_law(ViscousLaw(), W[:2], A[:2], [90.0, 110.0], min_tests=2)
    assert f.params[0] == pytest.approx(100.0, rel=1e-12) and (f.n_tests, f.dof) == (2, 1)
    assert f.rmse == pytest.approx(10.0, rel=1e-12) and f.stderr[0] == pytest.approx(10.0, rel=1e-12)
    with pytest.raises(ValueError, match=r"^viscous law: 1 test\(s\) given; at least 2 are needed"):
        fit_law(ViscousLaw(), W[:1], A[:1], c[:1], min_tests=1)
    for bad in (dict(c=np.where(np.arange(7) == 2, np.inf, 100.0)), dict(w=np.where(np.arange(7) == 2, np.nan, W))):
        with pytest.raises(ValueError, match=r"^omega, A and c_e must all be finite$"):
            fit_law(ViscousLaw(), bad.get("w", W), A, bad.get("c", c))
    for w, a in ((np.where(np.arange(7) == 0, 0.0, W), A), (W, np.where(np.arange(7) == 6, -0.1, A))):
        with pytest.raises(ValueError, match=r"^omega \[rad/s\] and A \[mm\] must be > 0 for every test$"):
            fit_law(ViscousLaw(), w, a, c)


class _Spike(DampingLaw):
    """c_e = c + d·[test 0]: test 0 alone fixes d (leverage 1)."""

    name = "spike"
    param_names = ("c", "d")

    def design(self, omega, A, x0):
        return np.column_stack([np.ones(omega.size), (np.arange(omega.size) == 0).astype(float)])


class _Twice(DampingLaw):
    """c_e = c1 + c2: two equal columns (rank deficient, G singular)."""

    name = "twice"
    param_names = ("c1", "c2")

    def design(self, omega, A, x0):
        return np.column_stack([np.ones(omega.size), np.ones(omega.size)])


def test_leverages_and_the_fits_degenerate_cases():
    """Leverages are diag(X X⁺) (numpy's pseudo-inverse), also for a rank-deficient X (two equal columns: 1/M each)
    and a row that alone fixes a parameter (1).  Such a test has no leave-one-out residual: LOO RMSE = inf (None in
    the JSON).  Singular normal equations G = XᵀX give NaN (None in the JSON) while lstsq still fits."""
    rng = np.random.default_rng(3)
    X = rng.normal(size=(8, 3))
    np.testing.assert_allclose(leverages(X), np.diag(X @ np.linalg.pinv(X)), rtol=1e-10)
    np.testing.assert_allclose(leverages(np.ones((5, 2))), np.full(5, 0.2), rtol=1e-12)
    c = np.array([500.0, 100.0, 101.0, 99.0, 100.0, 100.5, 99.5])
    f = fit_law(_Spike(), W, A, c)
    np.testing.assert_allclose(leverages(_Spike().design(W, A, X0))[0], 1.0, rtol=1e-12)
    assert f.loo_rmse == math.inf and f.to_dict()["loo_rmse"] is None
    assert f.params == pytest.approx([100.0, 400.0], rel=1e-9)
    g = fit_law(_Twice(), W, A, c)
    assert np.all(np.isnan(g.params_normal)) and g.to_dict()["params_normal_equations"] == [None, None]
    assert g.params.sum() == pytest.approx(c.mean(), rel=1e-12)  # lstsq's minimum-norm split of the mean
    assert g.to_dict()["dof"] == 5 and g.to_dict()["n_tests"] == 7


def test_rank_laws_order_and_laws_that_cannot_be_fitted():
    """default_laws: the four model-free laws, plus hysteretic and viscous+hysteretic given a model.  rank_laws:
    best leave-one-out error first; a law that cannot be fitted (the hysteretic law without x0) is listed last with
    its error (loo_rmse inf); on exact viscous data viscous fits exactly (LOO 0 to round-off) and leads, Coulomb's
    1/(ωA) shape does not."""
    assert [x.name for x in default_laws()] == ["polynomial", "viscous", "coulomb", "viscous+coulomb"]
    assert [x.name for x in default_laws(LinearSpring())][4:] == ["hysteretic", "viscous+hysteretic"]
    rows = rank_laws(W, A, np.full(7, 250.0), None, [HystereticLaw(LinearSpring()), CoulombLaw(), ViscousLaw()])
    assert [r["law"] for r in rows] == ["viscous", "coulomb", "hysteretic"]
    assert rows[0]["params"] == pytest.approx([250.0], rel=1e-12) and rows[0]["loo_rmse"] < 1e-9
    assert rows[-1]["loo_rmse"] == math.inf and "hysteretic law needs x0" in rows[-1]["error"]
    assert rows[-1]["n_params"] == 1 and rows[-1]["formula"] == "c_e = eta*k_e(x0)/w"
    with pytest.raises(ValueError, match=r"^5 test\(s\) given; ranking damping laws needs at least 6"):
        rank_laws(W[:5], A[:5], np.full(5, 250.0))


def test_law_from_dict_rebuilds_every_documented_name():
    """Names as DampingLaw.name: the three simple laws with their parameters, hysteretic alone or in a sum (needs a
    model), any "a+b" of known parts; an unknown part is named with the valid names."""
    model = LinearSpring(12_000.0)
    for name, params in (("polynomial", [1.0, 2.0, 3.0, 4.0, 5.0]), ("viscous", [7.0]), ("coulomb", [100.0]),
                         ("hysteretic", [0.1]), ("viscous+coulomb", [5.0, 100.0]), ("coulomb+hysteretic", [50.0, 0.2])):
        law = law_from_dict({"name": name, "params": params}, model)
        assert law.name == name and law.params.tolist() == params
    assert isinstance(law_from_dict({"name": "hysteretic", "params": [0.1]}, model), HystereticLaw)
    assert law_from_dict({"name": "hysteretic", "params": [0.1]}, model).predict(4.0, 0.3, 2.0)[0] == \
        pytest.approx(0.1 * 12_000.0 / 4.0, rel=1e-12)
    assert law_from_dict({"name": "viscous"}).params is None
    with pytest.raises(ValueError, match=r"^hysteretic law needs a stiffness model$"):
        law_from_dict({"name": "viscous+hysteretic", "params": [1.0, 0.1]})
    with pytest.raises(ValueError) as exc:
        law_from_dict({"name": "viscous+magic"})
    assert str(exc.value) == "unknown damping law 'magic'; valid: polynomial, viscous, coulomb, hysteretic, a+b"


def test_loo_leverages_match_hat_matrix_small():
    """h_i from the thin SVD equal diag(X pinv(X)) computed independently (M = 40)."""
    rng = np.random.default_rng(0)
    w = rng.uniform(1, 20, 40)
    A = rng.uniform(0.1, 0.5, 40)
    c = 3.0 * w**2 - 2 * w + 50 * A**2 + 4 * A + 100 + rng.normal(0, 0.5, 40)
    f = fit_law(PolynomialLaw(), w, A, c)
    X = PolynomialLaw().design(w, A, np.full(40, np.nan))
    h = np.diag(X @ np.linalg.pinv(X))
    assert np.allclose(f.loo_residuals, f.residuals / (1 - h), rtol=1e-9, atol=1e-12)


def test_fit_law_memory_linear_in_tests():
    """M = 20,000 tests: an M x M hat matrix would need 3.2 GB; the fit stays under 30 MB of
    traced allocations (design matrix 0.8 MB, thin U 0.8 MB, a few vectors)."""
    M = 20_000
    rng = np.random.default_rng(1)
    w = rng.uniform(1, 20, M)
    A = rng.uniform(0.1, 0.5, M)
    c = 2.0 * w + 100 + rng.normal(0, 0.5, M)
    tracemalloc.start()
    try:
        f = fit_law(PolynomialLaw(), w, A, c)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 30e6
    assert f.params[1] == pytest.approx(2.0, abs=0.05)
    assert f.loo_rmse == pytest.approx(0.5, rel=0.05)


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


def test_a_one_parameter_law_takes_its_value_alone_and_refuses_a_non_finite_one():
    """``ViscousLaw(0.05)`` is c_e = 0.05 N·s/mm at any ω and A (it crashed in ``predict`` on a 0-d array); a NaN or
    an infinite parameter is refused by name, with the law's parameter names and units; so is a nested list."""
    from chainid.model.laws import PolynomialLaw, ViscousLaw

    np.testing.assert_array_equal(ViscousLaw(0.05).predict([1.0, 10.0], [0.1, 0.5]), [0.05, 0.05])
    assert ViscousLaw(0.05).params.shape == (1,)
    with pytest.raises(ValueError, match=r"viscous: params = \[nan\] must be finite numbers \(c in N s/mm\)"):
        ViscousLaw(float("nan"))
    with pytest.raises(ValueError, match="must be finite"):
        PolynomialLaw([0.0, 0.0, float("inf"), 0.0, 1.0])
    with pytest.raises(ValueError,
                       match=r"viscous: params must be a flat list of 1 values \(c\); got an array of shape \(1, 1\)"):
        ViscousLaw([[0.05]])
