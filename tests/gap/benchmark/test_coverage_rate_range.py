"""A family's interval coverage is as uncertain as its number of cases: the exact (Clopper–Pearson) interval of
the share over the cases (the parameters of one case share its data), and the calibration mark that says whether
a rate outside 85–95 % is a deviation those cases can show."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.gap.benchmark.paramscore import calibration_mark, coverage_by_effect, pool_scores, rate_range


def test_exact_interval_matches_the_textbook_values():
    # Clopper & Pearson (1934), 95 %: 8 of 10 -> 0.4439-0.9748, the Beta quantiles B(0.025; 8, 3), B(0.975; 9, 2)
    assert rate_range(0.8, 10) == pytest.approx((0.4439, 0.9748), abs=1e-4)
    # another implementation: scipy's exact binomial test
    from scipy.stats import binomtest

    for k, n in ((81, 263), (3, 7), (29, 32)):
        ci = binomtest(k, n).proportion_ci(confidence_level=0.95, method="exact")
        assert rate_range(k / n, n) == pytest.approx((ci.low, ci.high), rel=1e-9)


@pytest.mark.parametrize("n", [1, 4, 10, 60])
def test_all_or_none_of_the_cases_have_the_closed_form(n):
    """k = n: lo = (α/2)^(1/n), hi = 1; k = 0: lo = 0, hi = 1 − (α/2)^(1/n); at 95 % and at 90 %."""
    for level in (0.95, 0.90):
        a2 = (1 - level) / 2
        assert rate_range(1.0, n, level) == pytest.approx((a2 ** (1 / n), 1.0), rel=1e-9)
        assert rate_range(0.0, n, level) == pytest.approx((0.0, 1 - a2 ** (1 / n)), rel=1e-9)


def test_a_share_pooled_over_cases_moves_the_range_continuously():
    """A family's share of intervals over its cases gives a k that need not be whole (bouc_wen: 17 of 20 intervals
    over 5 cases, k = 4.25): both ends rise with k, and meet the whole-k values at the integers."""
    n = 5
    ks = np.linspace(0.0, n, 501)
    lo, hi = np.array([rate_range(k / n, n) for k in ks]).T
    assert np.all(np.diff(lo) >= 0) and np.all(np.diff(hi) >= 0)
    for k in range(n + 1):
        for eps in (1e-9, -1e-9):
            if 0 <= k + eps <= n:
                assert rate_range((k + eps) / n, n) == pytest.approx(rate_range(k / n, n), abs=1e-6)


def test_one_missed_case_does_not_refute_ninety_percent():
    """0 of 1 happens one time in ten for a calibrated interval: its range reaches 97.5 % and the mark is
    ``low``, not ``LOW`` (Wilson's 0–79 % would have called it refuted)."""
    lo, hi = rate_range(0.0, 1)
    assert (lo, hi) == pytest.approx((0.0, 0.975), abs=1e-12)
    cov = coverage_by_effect(pool_scores(_scores([[False]])))["deadband"]
    assert cov["consistent"] is True and calibration_mark(cov) == "low"


@pytest.mark.parametrize("rate, n, level", [(1.2, 10, 0.95), (-0.1, 10, 0.95), (0.5, 0, 0.95), (math.nan, 5, 0.95),
                                           (0.5, 10, 1.0), (0.5, 10, 0.0)])
def test_a_rate_out_of_range_or_no_trial_is_refused(rate, n, level):
    with pytest.raises(ValueError, match=r"rate_range: rate = .* must be in \[0, 1\] and n = .* > 0 \(level"):
        rate_range(rate, n, level)


def _scores(case_cover: list[list[bool]]) -> list[list[dict]]:
    """One row per case, each with a parameter per entry of its list (covered or not)."""
    return [[{"param": f"deadband.p{j}", "truth": 1.0, "estimate": 1.0, "rel_error": 0.0, "covered": c}
             for j, c in enumerate(row)] for row in case_cover]


def test_parameters_of_one_case_count_once():
    cov = coverage_by_effect(pool_scores(_scores([[True] * 4] * 4)))["deadband"]
    assert (cov["n_interval"], cov["covered"], cov["n_cases"]) == (16, 16, 4)
    # 100 % on 4 cases: the exact range reaches down to 0.025^(1/4) = 39.8 %, so 90 % is consistent with it
    assert cov["coverage_range95"] == pytest.approx([0.025 ** 0.25, 1.0], rel=1e-9)
    assert cov["consistent"] is True and calibration_mark(cov) == "high"


def test_a_rate_many_cases_refute_is_marked_in_capitals():
    cov = coverage_by_effect(pool_scores(_scores([[True]] * 60)))["deadband"]  # 60 of 60: 94.0-100 %
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
