"""Estimate-vs-truth scoring of the benchmark's parameters (chainid.gap.benchmark.paramscore) by hand: the truth of
a covariate-following parameter, the normal interval from a standard deviation, the canonical names, and the
calibration table's marks and texts."""
from __future__ import annotations

import pytest

from chainid.gap.benchmark import paramscore as ps


def test_a_covariate_parameter_is_compared_with_its_law_at_the_mean_condition():
    """F_c = p0 + p1·mean(I) = 100 + 50·mean(0.2, 0.4, 0.9) = 125 N; the estimate 150 is 20 % off."""
    truth = {"effects": {"friction": {"F_c": 999.0, "x_s": 0.01}},
             "covariate": {"effect": "friction", "param": "F_c", "p0": 100.0, "p1": 50.0, "values": [0.2, 0.4, 0.9]}}
    row = {"truth": truth, "params": {"friction.F_c": 150.0, "friction.x_s": 0.012}}
    fc, xs = ps.param_scores(row, ["friction"])
    assert fc["truth"] == pytest.approx(125.0, rel=1e-12) and fc["rel_error"] == pytest.approx(0.2, rel=1e-12)
    assert xs["truth"] == 0.01  # not the covariate's parameter: its own value


def test_sd_interval_is_est_plus_minus_z90_sd_and_a_zero_truth_has_no_relative_error():
    """est 10, sd 2: [10 − 3.29, 10 + 3.29] (z₉₅ = 1.6449); truth 13.2 is inside, 13.3 outside; |err|/hw =
    3.2/3.2897.  A true 0 gives no relative error; sd 0 gives no interval."""
    def row(tv, sd=2.0):
        return {"truth": {"effects": {"slack": {"s": tv}}}, "params": {"slack.s": 10.0}, "params_sd": {"slack.s": sd}}

    (p,) = ps.param_scores(row(13.2), ["slack"])
    assert p["covered"] is True and p["err_halfwidth"] == pytest.approx(3.2 / (2 * 1.6448536), rel=1e-6)
    (p,) = ps.param_scores(row(13.3), ["slack"])
    assert p["covered"] is False
    (p,) = ps.param_scores(row(6.8), ["slack"])
    assert p["covered"] is True
    (p,) = ps.param_scores(row(0.0), ["slack"])
    assert p["rel_error"] is None
    (p,) = ps.param_scores(row(12.0, sd=0.0), ["slack"])
    assert (p["covered"], p["err_halfwidth"]) == (None, None)
    (p,) = ps.param_scores(row(-8.0), ["slack"])  # a negative truth has one: |10 − (−8)|/8
    assert p["rel_error"] == pytest.approx(2.25, rel=1e-12)


def test_error_over_half_width_uses_the_half_on_the_truths_side():
    """est 10 in [9, 14]: truth 12 is 2 of the upper half-width 4 (0.5); truth 9.5 is 0.5 of the lower 1 (0.5)."""
    for tv in (12.0, 9.5):
        row = {"truth": {"effects": {"slack": {"s": tv}}}, "params": {"slack.s": 10.0},
               "params_ci90": {"slack.s": [9.0, 14.0]}}
        (p,) = ps.param_scores(row, ["slack"])
        assert p["covered"] is True and p["err_halfwidth"] == pytest.approx(0.5, rel=1e-12)


def test_machine_compliance_scores_when_the_verdict_names_stiffness_level():
    row = {"truth": {"effects": {"machine_compliance": {"c": 2e-5}}}, "params": {"machine_compliance.c": 3e-5}}
    (p,) = ps.param_scores(row, ["stiffness_level"])
    assert p["rel_error"] == pytest.approx(0.5, rel=1e-9)
    assert ps.param_scores(row, ["machine_compliance"]) == []  # the verdict's canonical name is what counts


@pytest.mark.parametrize("rate, consistent, mark", [(0.85, False, "ok"), (0.95, False, "ok"), (0.8499, True, "low"),
                                                    (0.9501, False, "HIGH"), (0.5, False, "LOW")])
def test_calibration_mark_band_is_inclusive(rate, consistent, mark):
    assert ps.calibration_mark({"coverage": rate, "consistent": consistent}) == mark


def test_texts_of_a_rate_and_its_range():
    assert ps.range_text({"coverage_range95": [0.514, 0.996]}) == "51-100 %"
    assert ps.range_text({"coverage_range95": None}) == ""
    assert ps.pct(0.9123, 1) == "91.2 %" and ps.pct(0.9123) == "91 %" and ps.pct(None) == "n/a"


def test_coverage_lines_of_one_effect_by_hand():
    """9 of 10 intervals over 5 cases: 90 %; median relative error 0.0345 → 3.5 %; |err|/hw 0.41."""
    cov = {"friction": {"n_interval": 10, "covered": 9, "n_cases": 5, "coverage": 0.9, "coverage_range95": [0.6, 1.0],
                        "median_rel_error": 0.0345, "median_err_halfwidth": 0.4123,
                        "parts": {"profile": {"coverage": 1.0, "median_err_halfwidth": None}}}}
    lines = ps.coverage_lines(cov, "T")
    assert lines[0] == "T"
    assert lines[2] == (f"  {'friction':<20}{10:>10}{9:>9}{5:>7}{'90 %':>8}{'60-100 %':>14}{'ok':>6}{'3.5 %':>19}"
                        f"{'0.41':>10}")
    assert lines[3].endswith("|err|/hw: median |error| / half-width, 0.41 when calibrated)")
    assert lines[4] == "  each part alone, coverage (|err|/hw): friction profile 100 % (n/a)"
