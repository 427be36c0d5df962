"""A family's interval coverage is as uncertain as its number of cases: Wilson's score interval of the share over
the cases (the parameters of one case share its data), and the calibration mark that says whether a rate outside
85–95 % is a deviation those cases can show."""
from __future__ import annotations

import math

import pytest

from chainid.gap.benchmark.paramscore import calibration_mark, coverage_by_effect, pool_scores, rate_range


def test_wilson_interval_matches_the_textbook_values():
    # Wilson (1927) / Newcombe (1998), 95 %: 8 of 10 -> 0.4902-0.9433; 0 of 10 -> 0-0.2775; 81 of 263 -> 0.2553-0.3662
    assert rate_range(0.8, 10) == pytest.approx((0.4902, 0.9433), abs=1e-4)
    assert rate_range(0.0, 10) == pytest.approx((0.0, 0.2775), abs=1e-4)
    assert rate_range(81 / 263, 263) == pytest.approx((0.2553, 0.3662), abs=1e-4)


def test_the_range_is_the_closed_form_at_another_level():
    z = 1.6448536269514722  # 90 %
    p, n = 0.75, 12.0
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z / (1 + z * z / n) * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    assert rate_range(p, n, z) == pytest.approx((centre - half, centre + half), rel=1e-12)


@pytest.mark.parametrize("rate, n", [(1.2, 10), (-0.1, 10), (0.5, 0), (math.nan, 5)])
def test_a_rate_out_of_range_or_no_trial_is_refused(rate, n):
    with pytest.raises(ValueError, match=r"rate_range: rate = .* must be in \[0, 1\] and n = .* > 0"):
        rate_range(rate, n)


def _scores(case_cover: list[list[bool]]) -> list[list[dict]]:
    """One row per case, each with a parameter per entry of its list (covered or not)."""
    return [[{"param": f"deadband.p{j}", "truth": 1.0, "estimate": 1.0, "rel_error": 0.0, "covered": c}
             for j, c in enumerate(row)] for row in case_cover]


def test_parameters_of_one_case_count_once():
    cov = coverage_by_effect(pool_scores(_scores([[True] * 4] * 4)))["deadband"]
    assert (cov["n_interval"], cov["covered"], cov["n_cases"]) == (16, 16, 4)
    # 100 % on 4 cases: Wilson's range reaches down to 51 %, so 90 % is consistent with it
    assert cov["coverage_range95"] == pytest.approx(list(rate_range(1.0, 4)), rel=1e-12)
    assert cov["coverage_range95"][0] == pytest.approx(0.5101, abs=1e-4)
    assert cov["consistent"] is True and calibration_mark(cov) == "high"


def test_a_rate_many_cases_refute_is_marked_in_capitals():
    cov = coverage_by_effect(pool_scores(_scores([[True]] * 60)))["deadband"]  # 60 of 60: 94-100 %
    assert cov["consistent"] is False and calibration_mark(cov) == "HIGH"
    low = coverage_by_effect(pool_scores(_scores([[True]] * 30 + [[False]] * 30)))["deadband"]
    assert calibration_mark(low) == "LOW"
    ok = coverage_by_effect(pool_scores(_scores([[True]] * 9 + [[False]])))["deadband"]
    assert calibration_mark(ok) == "ok"
    assert calibration_mark({"coverage": None}) == ""


def test_cases_without_an_interval_are_not_counted():
    rows = _scores([[True], [False]]) + [[{"param": "deadband.g", "truth": 1.0, "estimate": 1.1, "rel_error": 0.1,
                                            "covered": None}]]
    cov = coverage_by_effect(pool_scores(rows))["deadband"]
    assert (cov["n_interval"], cov["n_cases"], cov["coverage"]) == (2, 2, 0.5)


def test_scores_pooled_by_hand_without_a_case_count_one_case_each():
    tagged = pool_scores(_scores([[True], [True]]))["deadband.p0"]  # cases 0 and 1
    untagged = [{k: v for k, v in p.items() if k != "case"} for p in tagged] * 2  # four, from no known case
    cov = coverage_by_effect({"deadband.p0": tagged + untagged})["deadband"]
    assert (cov["n_interval"], cov["n_cases"]) == (6, 6)
