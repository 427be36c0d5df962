"""Pieces of the step rule (:mod:`chainid.gap.core.steprule`) by hand: the noise floor's two tests and their
edges, a chain term's parameter prefix and its pinned parameters, when one effect nests another, and the
near-tie order.  Units N², N; NRMSE dimensionless."""
from __future__ import annotations

import math
from types import SimpleNamespace

import pytest

from chainid.gap.core.steprule import (NESTED_ZERO, NONE_FRACTION, TIE, at_noise_floor, nested_pair, near_tie_first,
                                       pinned_params, term_prefix)


@pytest.mark.parametrize("r2, ok", [(2.5, True), (2.7, False)])
def test_an_estimated_floor_widens_the_ratio_band_by_its_relative_sd(r2, ok):
    """n = 200 cells and a floor known to 30 %: r2/f2 < 1 + 5·√(2/200 + 0.3²) = 1 + 5·√0.1 = 2.581 (σ small: the
    systematic part does not decide)."""
    assert 1 + 5 * math.sqrt(2 / 200 + 0.3 ** 2) == pytest.approx(2.5811, abs=1e-4)
    assert at_noise_floor(r2, 1.0, 0.01, 200, 0.3) is ok


@pytest.mark.parametrize("excess, ok", [(0.59, True), (0.61, False)])
def test_a_systematic_part_below_half_the_noise_is_at_the_floor(excess, ok):
    """σ = 1.2 N, f2 = 1 N², r2 = 1 + excess²: √(r2 − f2) = excess against NONE_FRACTION·σ = 0.6 N; the ratio
    test is closed (10⁶ cells: 1 + 5·√(2·10⁻⁶) = 1.007 < r2)."""
    assert NONE_FRACTION == 0.5
    assert at_noise_floor(1.0 + excess ** 2, 1.0, 1.2, 10 ** 6) is ok


def test_without_a_floor_only_the_systematic_part_decides():
    """f2 = 0: the ratio is infinite (no division by zero); r2 = 0.01 N² is 0.1 N < 0.5 N: at the floor; 4 N² is
    2 N: not."""
    assert at_noise_floor(0.01, 0.0, 1.0, 10) is True
    assert at_noise_floor(4.0, 0.0, 1.0, 10) is False


@pytest.mark.parametrize("ratio, ok", [(8.0, True), (8.2, False)])
def test_no_cells_counts_as_one(ratio, ok):
    """n = 0 is read as one cell: the band is 1 + 5·√2 = 8.07 (σ small)."""
    assert at_noise_floor(ratio, 1.0, 1e-3, 0) is ok


def test_a_terms_prefix_is_its_effect_or_the_slope_itself():
    assert term_prefix("friction") == "friction."
    assert term_prefix("friction@p_bar") == "friction."
    assert term_prefix("damping.c@p_bar") == "damping.c@p_bar"


def test_pinned_parameters_are_those_of_the_newest_term_or_the_one_asked():
    """at_bound holds a friction and a hysteresis parameter and a covariate slope: the newest term (hysteresis)
    has its own; asked for friction@p, the friction's; asked for the slope, the slope; a baseline has none."""
    c = SimpleNamespace(names=["friction@p", "damping.c@p", "hysteresis"],
                        at_bound=["friction.x_s", "hysteresis.x_h", "damping.c@p"])
    assert pinned_params(c) == ["hysteresis.x_h"]
    assert pinned_params(c, "friction@p") == ["friction.x_s"]
    assert pinned_params(c, "damping.c@p") == ["damping.c@p"]
    assert pinned_params(SimpleNamespace(names=[], at_bound=["spring.k"])) == []


def _c(names, **params):
    return SimpleNamespace(names=list(names), params=params)


@pytest.mark.parametrize("mu, nested", [(1e-4, True), (2e-4, False), (-2e-4, False)])
def test_bouc_wen_nests_a_friction_only_without_its_load_dependent_part(mu, nested):
    """Bouc–Wen reduces to a Jenkins friction with μ = 0: μ up to NESTED_ZERO (10⁻⁴) in size is absent, more is
    not (either sign); a friction's stick travel does not matter against Bouc–Wen."""
    assert NESTED_ZERO["friction.mu"] == 1e-4
    got = nested_pair(_c(["spring", "bouc_wen"]), _c(["spring", "friction"], **{"friction.mu": mu,
                                                                               "friction.x_s": 0.5}))
    assert got == (("bouc_wen", "friction") if nested else None)


@pytest.mark.parametrize("x_s, nested", [(1e-4, True), (2e-4, False)])
def test_stribeck_nests_a_friction_only_without_stick_travel(x_s, nested):
    """Stribeck friction without its peak is Coulomb friction: a stick travel x_s up to 10⁻⁴ mm is absent."""
    got = nested_pair(_c(["stribeck"]), _c(["friction"], **{"friction.mu": 0.0, "friction.x_s": x_s}))
    assert got == (("stribeck", "friction") if nested else None)


def test_only_one_effect_each_and_a_nesting_one_make_a_pair():
    """Bouc–Wen against Dahl hysteresis is a pair (no friction parameters to check); two effects apart, the same
    set, or Stribeck against hysteresis (Stribeck nests only friction), or the order reversed, is not."""
    assert nested_pair(_c(["bouc_wen"]), _c(["hysteresis"])) == ("bouc_wen", "hysteresis")
    assert nested_pair(_c(["bouc_wen", "slack"]), _c(["hysteresis"])) is None
    assert nested_pair(_c(["bouc_wen"]), _c(["bouc_wen"])) is None
    assert nested_pair(_c(["stribeck"]), _c(["hysteresis"])) is None
    assert nested_pair(_c(["hysteresis"]), _c(["bouc_wen"])) is None


def _t(name, loto, pinned=0, k=2, bic=0.0):
    return (SimpleNamespace(name=name, nrmse_loto=loto, at_bound=["p"] * pinned, n_params=k, bic=bic), name)


def test_near_ties_come_first_in_the_tie_order_then_the_rest_in_the_same_order():
    """Best LOTO 1.0, tie band up to 1 + TIE = 1.05.  Inside: a (1.0, one pinned), b (1.04, 3 parameters), c
    (1.05, 2 parameters, BIC 5), d (1.05, 2 parameters, BIC 1): order d, c, b, a (fewer pinned, then fewer
    parameters, then BIC).  Outside: e (1.06, 1 parameter) and f (2.0, none pinned, 1 parameter, lower BIC): f, e."""
    assert TIE == 0.05
    cands = [_t("e", 1.06, k=1, bic=3.0), _t("a", 1.0, pinned=1), _t("b", 1.04, k=3), _t("c", 1.05, bic=5.0),
             _t("d", 1.05, bic=1.0), _t("f", 2.0, k=1, bic=-1.0)]
    assert [t[1] for t in near_tie_first(cands)] == ["d", "c", "b", "a", "f", "e"]
