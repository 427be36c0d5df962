"""Pieces of the terminal summary (chainid.gap.core.summary): "n/a" at the column's width, a parameter's spread
and bound mark, what is left in noise units, the waterfall's marks and the reasons of an ``unexplained`` verdict."""
from __future__ import annotations

import math

from chainid.gap.core import summary as sm


def test_g_says_n_a_at_the_width_of_the_spec():
    assert sm._g(None, ">9.4g") == "      n/a"  # 9 wide
    assert sm._g(math.nan, ">6.1f") == "   n/a"
    assert sm._g(math.inf, ".4g") == "n/a"
    assert sm._g(0.123456, ">9.4g") == "   0.1235"


def test_params_zero_estimate_unmoved_by_resamples_is_at_bound():
    """v = 0 with sd = 0: "(at bound)" and no spread; v = 0 with sd 0.1 is an estimate; an interval wins over sd;
    a non-zero v with sd 0 is a spread the refits did not resolve, not a certainty."""
    assert sm._params({"a.x": 0.0}, {"a.x": 0.0}) == "a.x=0 (at bound)"
    assert sm._params({"a.x": 0.0}, {"a.x": 0.1}) == "a.x=0±0.1"
    assert sm._params({"a.x": 2.0}, {"a.x": 0.0}) == "a.x=2 (sd not resolved)"  # never ±0
    assert sm._params({"a.x": 2.0}, {"a.x": 0.1234}) == "a.x=2±0.12"  # two significant digits
    assert sm._params({"a.x": 2.0}, {"a.x": 0.1}, ci={"a.x": [1.5, 2.5]}) == "a.x=2 [1.5, 2.5]"
    assert sm._params({"a.x": 2.0}, {"a.x": 0.1}, ("a.x",), {"a.x": [1.5, 2.5]}) == "a.x=2 (at bound)"


def test_left_residual_in_noise_units_or_unknown():
    """db 6.0206 → 10^(6.0206/20) = 2.00× the floor; a missing or non-finite dB: "unknown vs noise"."""
    assert sm._left({"left_nrmse_holdout": 0.25, "residual": {"db_over_noise": 6.0206}}) == (
        "fit left 75.0 % (held-out NRMSE 0.25), residual 2.00× the noise floor")
    for r in ({}, {"db_over_noise": math.nan}):
        assert sm._left({"left_nrmse_holdout": 0.25, "residual": r}).endswith("residual unknown vs noise")
    assert sm._left({"left_nrmse_holdout": math.nan}) == "no held-out fit"


def _step(effect, **kw):
    return {"effect": effect, "nrmse_loto": 0.2, "nrmse_holdout": 0.2, "shrinkage": None, "db_over_noise": 1.0,
            "params": {}} | kw


def test_waterfall_marks_a_rising_step_by_whether_it_is_kept():
    """trusted_steps = 2: a rise at step 1 (< 2) is kept, at step 2 (>= 2) over-fitted; rate marks override."""
    steps = [_step("baseline"), _step("a", worsened_holdout=True), _step("b", worsened_holdout=True)]
    lines = sm.waterfall({"steps": steps, "trusted_steps": 2})
    assert lines[2].endswith("  << raised the held-out error alone (kept: the next step(s) take it lower)")
    assert lines[3].endswith("  << raised the held-out error: over-fitted")
    steps = [_step("baseline"), _step("a", rate_cut=True, rate_dependent=True), _step("b", rate_cut=True)]
    lines = sm.waterfall({"steps": steps, "trusted_steps": 1})
    assert lines[2].endswith("  << changes with the speed: rate-dependent, not kept (see where)")
    assert lines[3].endswith("  << after a rate-dependent step: not kept")
    assert " 0.0% " in lines[2]  # shrinkage None prints as 0


def _unexplained(**kw):
    b = {"model": "m", "damping_law": "viscous", "nrmse_train": 0.1, "nrmse_holdout": 0.24, "db_over_noise": 3.0,
         "excess_rms_N": 5.0, "noise_sigma_N": 2.0}
    return {"baseline": b, "where": [], "ranking": [], "verdict": "unexplained", "steps": [],
            "residual": {"db_over_noise": 0.0, "stationary": True}} | kw


def test_unexplained_by_a_rate_dependent_first_step_names_its_exponent():
    rd = {"step": 1, "effect": "hysteresis", "parameter": "F_h", "exponent": 0.456}
    assert sm._unexplained_why(_unexplained(rate_dependence=rd)) == (
        "hysteresis passed the step rule, but its F_h changes with the speed (∝ v^0.46) where its form is "
        "rate-independent: it stands in for a rate-dependent mechanism outside the library")
    # a rate cut at a later step leaves a first step that explains: not this reason
    assert "changes with the speed" not in sm._unexplained_why(_unexplained(rate_dependence=rd | {"step": 2}))


def test_unexplained_by_over_fitting_only_when_no_step_is_kept():
    cut = _step("hysteresis", nrmse_holdout=0.32)
    res = _unexplained(overfitted=True, trusted_steps=1, steps=[_step("baseline"), cut])
    assert sm._unexplained_why(res).startswith("hysteresis passed the step rule on the training data but did not "
                                               "hold on the held-out data (held-out NRMSE 0.24 → 0.32)")
    res["trusted_steps"] = 2
    assert sm._unexplained_why(res) == "no library effect passed the step rule or shrinks the held-out gap by half"


def test_named_lines_state_the_share_of_the_gap_above_the_kinematic_floor():
    """Baseline 0.25 → 0.1: shrinkage 1 − 0.1/0.25 = 60 %; 0.734 of the gap above the floor prints 73 %."""
    res = _unexplained(verdict="friction", chain_text="c", left_nrmse_holdout=0.1,
                       residual={"db_over_noise": 0.0, "shrinkage_above_kinematic_floor": 0.734})
    res["baseline"]["nrmse_holdout"] = 0.25
    assert sm._named_lines(res)[1] == ("  held-out NRMSE 0.25 → 0.1 (shrinkage 60 %; 73 % of the gap above the "
                                       "kinematic floor, the part a model could close); fit left 90.0 % (held-out "
                                       "NRMSE 0.1), residual 1.00× the noise floor")
    res["residual"]["shrinkage_above_kinematic_floor"] = math.nan
    assert "kinematic floor" not in sm._named_lines(res)[1]


def test_params_says_an_unmoved_sd_is_not_resolved():
    """An sd of None (the refits did not move the parameter) prints "(sd not resolved)", never ±0; on an estimate
    of 0 it is the bound; an interval still wins."""
    assert sm._params({"a.x": 1e-5}, {"a.x": None}) == "a.x=1e-05 (sd not resolved)"
    assert sm._params({"a.x": 0.0}, {"a.x": None}) == "a.x=0 (at bound)"
    assert sm._params({"a.x": 2.0}, {"a.x": None}, (), {"a.x": [1.5, 2.5]}) == "a.x=2 [1.5, 2.5]"
