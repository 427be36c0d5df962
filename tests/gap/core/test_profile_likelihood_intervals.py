"""Profile-likelihood 90 % intervals (chainid.gap.core.profile) against closed forms and Monte Carlo coverage."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import least_squares
from scipy.stats import chi2 as chi2_dist

from chainid.gap.core import profile as P


def _line(seed: int, n: int = 50, sigma_true: float = 0.5, sigma_told: float = 0.5):
    """y = a + b·t + noise; the χ² and the refit with b (or a) held, in closed form."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 1.0, n)
    y = 1.0 + 2.0 * t + rng.normal(0.0, sigma_true, n)

    def chi2(p):
        return float(np.sum((y - p["a"] - p["b"] * t) ** 2) / sigma_told**2)

    def refit(key, v, start):
        if key == "b":
            return {"a": float(np.mean(y - v * t)), "b": v}
        return {"a": v, "b": float(np.sum((y - v) * t) / np.sum(t * t))}

    X = np.column_stack([np.ones(n), t])
    a, b = np.linalg.lstsq(X, y, rcond=None)[0]
    cov = sigma_told**2 * np.linalg.inv(X.T @ X)
    return {"a": float(a), "b": float(b)}, cov, chi2, refit, n


@pytest.mark.parametrize("first_step", [1.0, 1e-3, 300.0], ids=["step_se", "step_se_over_1000", "step_300_se"])
def test_linear_model_interval_is_the_closed_form_whatever_the_first_step(first_step):
    # a linear model's profile is exactly quadratic, so the edge interpolated on √Δχ² is the closed form
    # est ± √q₉₀·se·s to rounding, whether the first step is the standard error, far smaller (the doublings reach
    # the crossing) or 300 times wider (the bisections, up to BISECT_MAX, bring an inside point in)
    est, cov, chi2, refit, n = _line(1)
    se = math.sqrt(cov[1, 1])
    r = P.profile_interval("b", est, (-100.0, 100.0), first_step * se, chi2, refit, n, 2)
    half = math.sqrt(P.Q90) * se * max(1.0, math.sqrt(chi2(est) / (n - 2)))  # 1.645·se (·s when χ² > n − p)
    for edge, exact in ((r["ci90"][0], est["b"] - half), (r["ci90"][1], est["b"] + half)):
        assert edge == pytest.approx(exact, abs=1e-9 * se)
    assert not r["to_bound"]


def test_crossing_is_exact_on_a_quadratic_and_stays_in_its_bracket():
    # Δχ² = (v/2)²: Δ = 1 at v = 2, Δ = 9 at v = 6; the level 4 is crossed at v = 4
    assert P.crossing((2.0, 1.0, 6.0, 9.0), 0.0, 4.0) == pytest.approx(4.0, rel=1e-15)
    # on the negative side too, and from the estimate itself (Δ_in = 0)
    assert P.crossing((0.0, 0.0, -6.0, 9.0), 0.0, 4.0) == pytest.approx(-4.0, rel=1e-15)
    # a profile steeper than quadratic beyond the bracket's inside end: the edge still lies inside the bracket
    v = P.crossing((1.0, 0.25, 2.0, 100.0), 0.0, 4.0)
    assert 1.0 < v < 2.0
    # χ²_min fell below the inside end's level, or the outside end is not outside: no crossing
    assert P.crossing((2.0, 1.0, 6.0, 9.0), -4.0, 4.0) is None
    assert P.crossing((2.0, 1.0, 6.0, 3.0), 0.0, 4.0) is None


def test_quantile_is_chi2_one_dof_90_percent():
    assert P.Q90 == pytest.approx(chi2_dist.ppf(0.9, 1), rel=1e-12)


def test_residual_in_excess_of_its_noise_widens_the_interval_by_its_rms_ratio():
    # noise twice the σ the χ² is weighted with: s² = χ²/(n − p) ≈ 4, the interval ≈ twice as wide
    est, cov, chi2, refit, n = _line(2, n=400, sigma_true=1.0, sigma_told=0.5)
    se = math.sqrt(cov[1, 1])
    r = P.profile_interval("b", est, (-100.0, 100.0), se, chi2, refit, n, 2)
    s = math.sqrt(chi2(est) / (n - 2))
    assert 1.8 < s < 2.2
    width = r["ci90"][1] - r["ci90"][0]
    assert width == pytest.approx(2 * math.sqrt(P.Q90) * se * s, abs=2 * se * s / 8)


def test_interval_stops_at_a_bound_and_says_so():
    est, cov, chi2, refit, n = _line(3)
    lo = est["b"] - 0.2 * math.sqrt(cov[1, 1])  # a bound well inside the interval
    r = P.profile_interval("b", est, (lo, 100.0), math.sqrt(cov[1, 1]), chi2, refit, n, 2)
    assert r["ci90"][0] == lo and r["to_bound"] == ["low"]


def test_level_needs_more_residuals_than_fitted_values():
    with pytest.raises(ValueError, match="n = 3 residuals for p = 3"):
        P.level(3.0, 3, 3)


def _decay(seed: int):
    """y = A·exp(−t/τ) + noise on few points: a nonlinear, weakly identified τ (the linearised interval is skewed)."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 3.0, 12)
    A, tau, sig = 1.0, 0.8, 0.08
    y = A * np.exp(-t / tau) + rng.normal(0.0, sig, t.size)

    def chi2(p):
        return float(np.sum((y - p["A"] * np.exp(-t / p["tau"])) ** 2) / sig**2)

    def refit(key, v, start):
        e = np.exp(-t / v)
        return {"tau": v, "A": float(y @ e / (e @ e))}

    r = least_squares(lambda u: (y - u[0] * np.exp(-t / u[1])) / sig, [1.0, 1.0], bounds=([0, 0.05], [10, 10]))
    return {"A": float(r.x[0]), "tau": float(r.x[1])}, chi2, refit, t.size


def test_profile_interval_of_a_nonlinear_parameter_covers_its_truth_nine_times_in_ten():
    covered = []
    for seed in range(300):
        est, chi2, refit, n = _decay(seed)
        r = P.profile_interval("tau", est, (0.05, 10.0), 0.05, chi2, refit, n, 2)
        covered.append(r["ci90"][0] <= 0.8 <= r["ci90"][1])
    # 300 draws of a calibrated 90 % interval: 0.90 ± 0.017 (1 sd); the s² inflation (χ²/(n − p) > 1 in half the
    # draws) widens it a little, so the band is 0.85–0.97
    assert 0.85 <= np.mean(covered) <= 0.97


def test_a_lower_chi2_met_on_the_scan_becomes_the_minimum():
    est, cov, chi2, refit, n = _line(4)
    se = math.sqrt(cov[1, 1])
    off = dict(est, b=est["b"] + 1.0 * se, a=refit("b", est["b"] + 1.0 * se, est)["a"])  # a start off the optimum
    r = P.profile_interval("b", off, (-100.0, 100.0), se, chi2, refit, n, 2)
    assert r["chi2_min"] == pytest.approx(chi2(est), abs=chi2(off) - chi2(est))
    assert r["chi2_min"] < chi2(off)
    assert r["ci90"][0] < est["b"] < r["ci90"][1]


def test_projection_takes_the_width_a_partner_profile_found():
    # parameter u's own profile points stay at u = 0 (its refits could not move it); v's profile found a point
    # inside the level with u = 3: u's interval takes it in, a point outside the level does not count
    pts = [(10.0, {"u": 0.0, "v": 0.0}), (11.0, {"u": 3.0, "v": 1.0}), (20.0, {"u": 9.0, "v": 2.0})]
    out = P.project(pts, ["u", "v"], n=100, p=2)
    assert out == {"u": [0.0, 3.0], "v": [0.0, 1.0]}


def test_merge_without_a_count_of_units_is_the_union_of_both_intervals():
    got, union = P.merge({"a": [1.0, 2.0], "b": [0.0, 1.0]}, {"a": {"ci90": [1.5, 2.5]}, "c": {"ci90": [3.0, 4.0]}})
    assert got == {"a": [1.0, 2.5], "b": [0.0, 1.0], "c": [3.0, 4.0]}
    assert union == {"a": True}  # c has no resampled interval to merge with


@pytest.mark.parametrize("ratio, m, heterogeneous", [(1.2, 9, False), (1.5, 9, True), (1.2, 51, True),
                                                      (1.0, None, True), (1.0, 1, True)])
def test_units_are_heterogeneous_beyond_the_scatter_of_a_spread_read_from_m_units(ratio, m, heterogeneous):
    # the threshold 1 + 1.6449/√(2(m − 1)): 1.4112 at m = 9, 1.1645 at m = 51; without m (or m < 2) nothing can
    # show the units alike
    assert P.heterogeneous([0.0, ratio], [3.0, 4.0], m) is heterogeneous


@pytest.mark.parametrize("ratio, heterogeneous", [(1.3506, False), (1.3508, True)])
def test_the_heterogeneity_threshold_at_twelve_units_is_1_3507(ratio, heterogeneous):
    # 1 + 1.6448536/√22 = 1 + 1.6448536/4.6904158 = 1.3506840 (by hand): just below and just above it
    assert P.heterogeneous([0.0, ratio], [0.0, 1.0], 12) is heterogeneous


def test_merge_stops_a_widened_edge_at_the_bound_and_holds_the_estimate():
    # alike units (widths 0.25 and 0.3 at m = 12): the profile [0, 0.3] widened down by the bias 0.05 would reach
    # −0.05, a negative play; it stops at the bound 0
    got, union = P.merge({"b": [0.0, 0.3]}, {"b": {"ci90": [0.0, 0.3]}}, {"b": [0.05, 0.3]}, units=12,
                         bounds={"b": (0.0, math.inf)})
    assert got["b"] == [0.0, 0.3] and union == {"b": False}
    # a profile centred on a lower χ² than the fit's estimate (0, at its bound) still holds the reported estimate
    got, _ = P.merge({"b": [-0.1, 0.1]}, {"b": {"ci90": [0.035, 0.365]}}, units=12, estimates={"b": 0.0},
                     bounds={"b": (0.0, 1.0)})
    assert got["b"] == [0.0, 0.365]


def test_a_profile_without_a_finite_chi2_is_left_out_of_the_merge():
    got, union = P.merge({"a": [1.0, 2.0]}, {"a": {"ci90": [math.nan, math.nan]}, "c": {"ci90": [math.nan, 1.0]}})
    assert got == {"a": [1.0, 2.0]} and union == {}


def test_a_nan_chi2_at_the_estimate_still_gives_the_closed_form_interval():
    # a failed evaluation exactly at the start (NaN): the search before the scan finds finite points and the scan
    # reads the edges against them, the straight line's est ± √q₉₀·se·s to 0.01 se
    est, cov, chi2, refit, n = _line(4)
    se = math.sqrt(cov[1, 1])

    def flaky(q):
        return math.nan if q["b"] == est["b"] else chi2(q)

    r = P.profile_interval("b", est, (-100.0, 100.0), se, flaky, refit, n, 2)
    half = math.sqrt(P.Q90) * se * max(1.0, math.sqrt(chi2(est) / (n - 2)))
    assert r["ci90"] == pytest.approx([est["b"] - half, est["b"] + half], abs=0.01 * se)


def test_merge_of_alike_units_is_the_profile_widened_by_the_resampling_biases():
    # percentile [1, 2], widened low by a bias of 0.2 to [0.8, 2]; the profile [1.1, 2.1] is as wide as the
    # percentile interval (ratio 1 < 1.4112 at m = 9): reported [1.1 − 0.2, 2.1], not the union [0.8, 2.1]
    got, union = P.merge({"a": [0.8, 2.0]}, {"a": {"ci90": [1.1, 2.1]}}, {"a": [1.0, 2.0]}, units=9)
    assert got["a"] == pytest.approx([0.9, 2.1], abs=1e-12) and union == {"a": False}
    # heterogeneous units (percentile width 3 against 1): the union
    got, union = P.merge({"a": [-0.5, 3.0]}, {"a": {"ci90": [1.0, 2.0]}}, {"a": [0.0, 3.0]}, units=9)
    assert got["a"] == [-0.5, 3.0] and union == {"a": True}
    # the harmonic route has no widening: alike units give the profile alone
    got, _ = P.merge({"a": [1.0, 2.0]}, {"a": {"ci90": [1.2, 2.2]}}, units=9)
    assert got["a"] == [1.2, 2.2]


def test_the_least_chi2_near_a_start_off_the_optimum_is_found_before_the_scan():
    # a start 0.6 se off the optimum (χ² 0.36 above it): the first scan steps (±1 se) meet χ² 0.16 and 2.56 above it
    # and would read the edges √(2.7055 + 0.16) = 1.693 (times s) se out instead of 1.645 (times s); the search
    # before the scan finds the optimum to well within 0.01 se, so both edges are the closed form est ± √q₉₀·se·s
    est, cov, chi2, refit, n = _line(4)
    se = math.sqrt(cov[1, 1])
    off = refit("b", est["b"] + 0.6 * se, est)
    r = P.profile_interval("b", off, (-100.0, 100.0), se, chi2, refit, n, 2)
    half = math.sqrt(P.Q90) * se * max(1.0, math.sqrt(chi2(est) / (n - 2)))
    assert r["ci90"] == pytest.approx([est["b"] - half, est["b"] + half], abs=0.01 * se)
    assert r["chi2_min"] == pytest.approx(chi2(est), abs=1e-3)


@pytest.mark.parametrize("first_step", [1.0, 30.0, 300.0])
def test_a_quartic_profile_is_read_within_its_bracket_whatever_the_first_step(first_step):
    # χ²_p(v) = v⁴ (one parameter, no partner): the level 2.7055 is crossed at ±2.7055^¼ = ±1.2825.  The bracket is
    # bisected until it is an eighth of its inside end's distance, so the √-interpolated edge (exact only for a
    # quadratic) is within 1 % of the crossing even when the first step is 300 times the interval
    def chi2(q):
        return q["v"] ** 4

    r = P.profile_interval("v", {"v": 0.0}, (-1e3, 1e3), first_step * 1.2825, chi2, lambda k, v, s: {"v": v},
                           100, 1)
    edge = P.Q90 ** 0.25
    assert r["ci90"][0] == pytest.approx(-edge, rel=0.01) and r["ci90"][1] == pytest.approx(edge, rel=0.01)


def test_a_failed_refit_counts_as_outside_the_level():
    # a straight line's profile, with every refit at |b − b̂| in (0.8, 1.2)·se failing (NaN χ²): those points are
    # outside, so the scan stops short of them and never reads a NaN as an edge
    est, cov, chi2, refit, n = _line(1)
    se = math.sqrt(cov[1, 1])

    def flaky(p):
        return math.nan if 0.8 * se < abs(p["b"] - est["b"]) < 1.2 * se else chi2(p)

    r = P.profile_interval("b", est, (-100.0, 100.0), se, flaky, refit, n, 2)
    assert all(math.isfinite(v) for v in r["ci90"])
    assert est["b"] - 1.2 * se < r["ci90"][0] < est["b"] and est["b"] < r["ci90"][1] < est["b"] + 1.2 * se
