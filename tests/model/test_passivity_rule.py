"""One rule for a damping that is a negative dashpot (chainid.model.passivity): predict, simulate --model and
dynamics --segment-model refuse to run the model at an operating point where it feeds energy in, naming the point
and the c; at passive points they run.

The law is viscous + Coulomb-equivalent, c_e(ω, A) = α + 4·F_f/(π·ω·A) with α = −2 N·s/mm and F_f = 50 N: by hand,
c_e < 0 exactly where ω·A > 4·F_f/(π·|α|) = 31.83 mm/s.
"""
from __future__ import annotations

import math

import pytest

from chainid.chain.spec import PAPER_CHAIN
from chainid.dynamics.model import ChainLine
from chainid.dynamics.segment_model import segment_kwargs
from chainid.gap.modelio import predict
from chainid.model.augmented import AugmentedModel
from chainid.model.base import ChainModel
from chainid.model.modelfile import save_model
from chainid.model.passivity import OperatingPoint, check_passive
from chainid.model.timedamping import Damping, feature_c
from chainid.records.simulate import TestSpec, simulate_model

ALPHA, F_F = -2.0, 50.0
BASE = ChainModel(PAPER_CHAIN)


def ce(w: float, A: float) -> float:
    return ALPHA + 4 * F_F / (math.pi * w * A)


def law_model(rule: str = "viscous") -> AugmentedModel:
    return AugmentedModel(BASE, [], Damping("law", law="viscous+coulomb", coefficients=[ALPHA, F_F], rule=rule))


SLOW = TestSpec("slow", 20.0, 2.2, 0.5)   # ω·A = 10 mm/s: c_e = +4.37 N·s/mm
FAST = TestSpec("fast", 200.0, 2.2, 0.5)  # ω·A = 100 mm/s: c_e = −1.36 N·s/mm


def test_hand_values():
    assert ce(SLOW.omega, SLOW.A) > 0 > ce(FAST.omega, FAST.A)


@pytest.mark.parametrize("rule", ["viscous", "hysteretic"])
def test_simulate_refuses_a_plan_with_a_negative_point_and_runs_a_passive_one(rule):
    with pytest.raises(ValueError) as e:
        simulate_model([SLOW, FAST], law_model(rule), n_cycles=4, samples_per_cycle=64)
    msg = str(e.value)
    assert "negative viscous c at test(s) fast (" in msg
    assert f"lowest c = {ce(FAST.omega, FAST.A):.4g} N·s/mm at ω = 200 rad/s, A = 0.5 mm" in msg
    recs = simulate_model([SLOW], law_model(rule), n_cycles=4, samples_per_cycle=64)
    assert [r.test for r in recs] == ["slow"]


def test_predict_refuses_the_negative_test_and_predicts_the_others():
    passive = AugmentedModel(BASE, [], Damping("viscous", {"c": 3.0}))
    recs = simulate_model([SLOW, FAST], passive, n_cycles=6, samples_per_cycle=64)
    with pytest.raises(ValueError) as e:
        predict(law_model(), recs)
    assert f"negative viscous c at test(s) fast (lowest c = {ce(FAST.omega, FAST.A):.4g} N·s/mm" in str(e.value)
    res = predict(law_model(), recs, tests=["slow"])
    assert [r["test"] for r in res["tests"]] == ["slow"]


def test_predict_judges_the_baseline_too():
    m = AugmentedModel(BASE, [], Damping("viscous", {"c": 3.0}))
    m.baseline = law_model()
    recs = simulate_model([FAST], m, n_cycles=6, samples_per_cycle=64)
    with pytest.raises(ValueError, match=r"^the model's baseline: the damping gives a negative viscous c"):
        predict(m, recs)


def test_dynamics_refuses_a_negative_operating_point(tmp_path):
    p = save_model(law_model(), tmp_path / "m.toml")
    with pytest.raises(ValueError) as e:
        segment_kwargs(p, pretension_N=11117.0, omega=FAST.omega, amplitude=FAST.A)
    assert (f"negative viscous c at test(s) the operating point (lowest c = {ce(FAST.omega, FAST.A):.4g} N·s/mm"
            in str(e.value))
    kw, _ = segment_kwargs(p, pretension_N=11117.0, omega=SLOW.omega, amplitude=SLOW.A)
    assert kw["damping"] == pytest.approx(ce(SLOW.omega, SLOW.A), rel=1e-12)


def test_a_constant_negative_viscous_c_is_refused_anywhere():
    m = AugmentedModel(BASE, [], Damping("viscous", {"c": -0.5}))
    with pytest.raises(ValueError, match=r"lowest c = -0.5 N·s/mm"):
        check_passive(m, [OperatingPoint("a", 1.0, 1.0, 2.0)])
    check_passive(AugmentedModel(BASE, [], Damping("viscous", {"c": 0.0})), [OperatingPoint("a", 1.0, 1.0, 2.0)])


def _feature(c: float, b_w: float) -> AugmentedModel:
    """A feature law c + b_w·(ω − 10) on the box ω ∈ [5, 15] rad/s (A not followed)."""
    return AugmentedModel(BASE, [], Damping("feature", {"c": c, "b_w": b_w, "b_A": 0.0, "w_ref": 10.0, "A_ref": 1.0,
                                                        "w_lo": 5.0, "w_hi": 15.0, "A_lo": 1.0, "A_hi": 1.0}))


@pytest.mark.parametrize("dc, refused", [(-2e-16, False), (-1e-9, True)])
def test_a_feature_law_on_its_passive_boundary_runs_and_one_below_it_is_refused(dc, refused):
    """c = 0.3·(10 − 5) + dc at ω = 5 rad/s (by hand: dc).  The terms are 1.5 and 1.5 N·s/mm, so the sum's round-off
    bound is 4·ε·3 = 2.7e-15: dc = −2e-16 (one unit in the last place of 1.5) is zero as far as the arithmetic can
    tell, −1e-9 is a negative dashpot."""
    model = _feature(1.5 + dc, 0.3)
    assert feature_c(1.5 + dc, 0.3, 0.0, 5.0, 1.0, 10.0, 1.0) < 0.0  # as the sum computes, both are below 0
    point = OperatingPoint("edge", 5.0, 1.0, 2.0, "edge")
    if refused:
        with pytest.raises(ValueError, match=r"lowest c = -1e-09 N·s/mm.*valid range >= 0"):
            check_passive(model, [point])
    else:
        check_passive(model, [point])
        assert model.damping.resolve(5.0, 1.0, 0.0).params["c"] == 0.0


def test_a_chain_line_runs_a_feature_law_at_its_passive_boundary(tmp_path):
    """dynamics takes the law one ulp below 0 at its corner as a dashpot of exactly 0 (a chain line refuses a
    negative one: the rule and the line see the same c)."""
    p = save_model(_feature(1.5 - 2e-16, 0.3), tmp_path / "m.toml")
    kw, _ = segment_kwargs(p, pretension_N=11117.0, omega=5.0, amplitude=1.0)
    assert kw["damping"] == 0.0
    ChainLine(n_links=10, n_masses=2, **kw)
