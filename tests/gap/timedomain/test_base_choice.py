"""What the time route's base carries from its training records (:mod:`chainid.gap.timedomain.basechoice`).

Records at different operating conditions — the linear device with a Coulomb friction (1 + 2·i)·sgn(ẋ) at coil
currents i = 0 … 1 A (:func:`recovery_cases.covariate_friction_records`) — keep one c in the base: the condition
moves each record's damping and its features alike, so the law over the features (``damping_law``) and the
dashpot following the condition (``damping.c@i``) are steps.  The same records without their covariate carry
the law in the base (their features separate it).
"""
from __future__ import annotations

import warnings
from dataclasses import replace
from types import SimpleNamespace

import numpy as np

import recovery_cases as rc
from chainid.gap.timedomain.basechoice import MIN_LAW_RECORDS, distinct_covariates, law_choice
from chainid.gap.timedomain.route import build_problem


def _problem(recs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return build_problem(recs, ["r2"], 0, None, None)


def test_records_at_different_conditions_keep_one_c_in_the_base():
    prob = _problem(rc.covariate_friction_records())
    assert prob.covariates == ["i"]
    assert not prob.base.law and prob.law == "viscous"
    assert "operating condition i" in prob.law_reason and "damping.c@i" in prob.law_reason
    offered = prob.applicable()
    assert any(n.split("@")[0] == "damping_law" for n in offered), offered
    assert "damping.c@i" in prob.covariate_terms()


def test_the_same_records_without_their_condition_carry_the_law():
    recs = [replace(r, covariates={}) for r in rc.covariate_friction_records()]
    prob = _problem(recs)
    assert prob.covariates == []
    assert prob.base.law and prob.law == "feature"
    assert not any(n.split("@")[0] == "damping_law" for n in prob.applicable())


def test_law_choice_reasons():
    assert law_choice(True, "auto", 4, ["p_bar"])[0] == "feature"
    assert law_choice(False, "viscous", 4, ["p_bar"]) == ("viscous", "given")
    law, why = law_choice(False, "auto", 3, ["p_bar", "T"])
    assert law == "viscous" and "operating condition p_bar, T" in why and "damping.c@p_bar" in why
    law, why = law_choice(False, "auto", 2)
    assert law == "viscous" and f"fewer than {MIN_LAW_RECORDS} training records" in why


def test_a_set_and_a_measured_condition_are_one_condition():
    recs = [SimpleNamespace(covariates={"p_bar": p, "p_mean": 0.98 * p + 0.01, "T": 20.0})
            for p in (1.0, 3.0, 5.0, 7.0)]
    assert distinct_covariates(recs, ["p_bar", "p_mean", "T"]) == ["p_bar"]


def _recs(**cols):
    n = len(next(iter(cols.values())))
    return [SimpleNamespace(covariates={k: v[i] for k, v in cols.items()}) for i in range(n)]


def test_a_covariate_falling_as_another_rises_is_the_same_condition():
    """p_mean = 10 − 2·p_bar exactly: correlation −1, |r| > 0.999, so one condition (the sign does not matter)."""
    recs = _recs(p_bar=[1.0, 2.0, 4.0, 5.0], p_mean=[8.0, 6.0, 2.0, 0.0])
    assert distinct_covariates(recs, ["p_bar", "p_mean"]) == ["p_bar"]


def test_a_covariate_not_known_for_every_record_or_constant_is_not_a_condition():
    """A NaN in one record, or the same value in all, does not make an operating condition; a loosely related one
    (correlation 0.98 by numpy) is a condition of its own."""
    recs = _recs(i=[0.0, 0.5, 1.0, 1.5], p=[1.0, float("nan"), 2.0, 3.0], T=[20.0] * 4, q=[0.1, 0.5, 1.2, 1.4])
    assert abs(np.corrcoef([0.0, 0.5, 1.0, 1.5], [0.1, 0.5, 1.2, 1.4])[0, 1] - 0.98) < 0.01
    assert distinct_covariates(recs, ["p", "T", "i", "q"]) == ["i", "q"]
