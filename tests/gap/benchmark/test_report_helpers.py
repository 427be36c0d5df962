"""Small rules of the benchmark report (chainid.gap.benchmark.report): which effects a verdict names on a non-harmonic
case, which rows are scored for coverage, and the coverage title's resample counts."""
from __future__ import annotations

from chainid.gap.benchmark import report as rp


def test_named_drops_damping_law_only_off_the_harmonic_plan_unless_true():
    assert rp.named({"verdict": "friction+damping_law", "excitation": "chirp", "truth": ["friction"]}) == {"friction"}
    assert rp.named({"verdict": "friction+damping_law", "truth": ["friction"]}) == {"friction", "damping_law"}
    assert rp.named({"verdict": "friction+damping_law", "excitation": "chirp",
                     "truth": ["friction", "damping_law"]}) == {"friction", "damping_law"}


def test_row_param_scores_only_for_an_exactly_right_verdict():
    """A right verdict scores its parameters (102 vs 100: 2 %); an error, a partial verdict or no truth: none."""
    r = {"verdict": "friction", "truth": ["friction"], "true_params": {"friction.F_c": 100.0},
         "params": {"friction.F_c": 102.0}}
    (p,) = rp.row_param_scores(r)
    assert abs(p["rel_error"] - 0.02) < 1e-12
    assert rp.row_param_scores(r | {"verdict": "error: boom"}) == []
    assert rp.row_param_scores(r | {"verdict": "friction+slack"}) == []
    assert rp.row_param_scores(r | {"true_params": {}}) == []


def test_coverage_title_lists_every_resample_count_and_an_empty_table_says_so():
    cov = {"resamples": 200, "resample_counts": [50, 100, 200], "by_effect": {}}
    title, empty = rp.coverage_text({"param_coverage": cov})
    assert title.startswith("\n90 % intervals (50, 100 or 200 resamples) covering the true parameter")
    assert empty == "  no parameter scored"
    title, _ = rp.coverage_text({"param_coverage": cov | {"resample_counts": [50, 100]}})
    assert title.startswith("\n90 % intervals (50 or 100 resamples)")
    title, _ = rp.coverage_text({"param_coverage": cov | {"resample_counts": [50]}})
    assert title.startswith("\n90 % intervals (50 resamples)")
    assert rp.coverage_text({}) == []


def test_open_world_line_rates_with_one_decimal():
    r = {"open_world_outside_flagged_rate": 0.8333, "open_world_control_silent_rate": 1.0,
         "open_world_explained_silent_rate": 0.95}
    assert rp.open_world_line(r) == ("model-free check: flags a missing effect on outside cases 83.3 % (target >= 90 %)"
                                     "; silent on controls 100.0 %, on right single/pair verdicts 95.0 % (targets >= "
                                     "90 %)")
