"""A step's c_e tied to its damping law (:mod:`chainid.gap.harmonic.tie`).

Linear device F = 10·x + c_r·ẋ + 2·sgn(ẋ) on the six sine tests of :data:`recovery_cases.HARMONIC_PAIRS` (test h3
held out): with one c_r = 0.2 N·s/mm for every test the tie to the law is kept; with c_r scattered from test to test
(0.1 … 0.4 N·s/mm in no order of ω or A: a damping no law of (ω, A) follows) the F test refutes it.
"""
from __future__ import annotations

import copy
import warnings

import numpy as np
import pytest

import recovery_cases as rc
from chainid.gap.core.selection import baseline_candidate
from chainid.gap.diagnose import fit_linear_model
from chainid.gap.harmonic import law_choice as L
from chainid.gap.harmonic.prepare import prepare_test
from chainid.gap.harmonic.problem import Problem
from chainid.gap.core.profile import problem_hooks, profile_interval
from chainid.gap.harmonic import resampling
from chainid.gap.harmonic.tie import f_test, profile_hooks, tie_damping, tie_path

#: per-test dashpots scattered about 0.2 N·s/mm (test order of HARMONIC_PAIRS)
SCATTER = (0.0, 0.2, -0.1, 0.15, -0.15, 0.05)


def _friction_problem(scatter: float):
    def force(mo, t, f, A):
        x, xd, _ = mo(t)
        c = rc.C_LIN + scatter * SCATTER[rc.HARMONIC_PAIRS.index((f, A))]
        return rc.K_LIN * x + c * xd + 2.0 * np.sign(xd)

    recs = rc.harmonic_set(force)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        prob = Problem([prepare_test(r) for r in recs], fit_linear_model(recs, ["h3"], 0.0), ["h3"], fit_mass=True)
    base = baseline_candidate(prob)
    cand = prob.score(prob.fit(["friction"]), ["friction"], base.nrmse_holdout)
    return prob, cand, base


def test_f_statistic_against_a_hand_computation_and_the_table():
    """Δχ² = 10 over 4 released values, χ² = 137 on 137 degrees of freedom: F = 2.5; F₀.₉₅(4, 137) = 2.438 by
    interpolation in 120/ν between the table's 2.447 (ν = 120) and 2.372 (ν = ∞)."""
    stat, crit = f_test(137.0, 147.0, 148, 11, 7)
    assert stat == pytest.approx(2.5, rel=1e-12)
    assert crit == pytest.approx(2.438, abs=0.005)


def test_nothing_released_is_no_test():
    stat, crit = f_test(100.0, 90.0, 50, 5, 5)
    assert stat == float("inf") and crit == 0.0


@pytest.mark.slow
def test_a_tie_the_tests_allow_gives_the_point_estimate_only():
    """The step scored with the device's law (one c; the selection's LOTO choice here is viscous+coulomb, which
    takes part of the friction's first harmonic and is not tied to: next test)."""
    prob, cand, base = _friction_problem(0.0)
    prob.score(cand, ["friction"], base.nrmse_holdout, laws=["viscous"])
    n_free = prob.train_chi2(["friction"], cand.params)[2]
    before = dict(cand.params)
    tied = tie_damping(prob, cand, base.nrmse_holdout)
    assert tied is not None and tied is not cand and cand.params == before  # a scored copy; the fit left as it was
    assert tied.tied_law == "viscous" and tied.params["friction.F_c"] == pytest.approx(2.0, rel=0.03)
    # the point estimate's alone: later fits (jack-knife, resamples, profiles) leave each test's c_e free
    assert prob.ties == {} and prob.train_chi2(["friction"], tied.params)[2] == n_free


@pytest.mark.slow
def test_a_law_that_varies_with_the_test_is_not_tied_to():
    """viscous+coulomb: its Coulomb term 4·F_f/(π·ω·A) is the friction's first harmonic itself."""
    prob, cand, base = _friction_problem(0.0)
    assert cand.law == "viscous+coulomb"
    assert tie_damping(prob, cand, base.nrmse_holdout) is None and prob.ties == {}


@pytest.mark.slow
def test_a_tie_refuted_by_per_test_damping_is_not_kept():
    prob, cand, base = _friction_problem(1.0)
    prob.score(cand, ["friction"], base.nrmse_holdout, laws=["viscous"])
    assert tie_damping(prob, cand, base.nrmse_holdout) is None and prob.ties == {}


@pytest.mark.slow
def test_a_tie_under_which_the_step_would_not_be_taken_is_undone():
    """The chain baseline → friction, its step rule numbers recomputed against the step as reported.  A baseline
    as good as the tied step (its LOTO NRMSE and per-test errors the tied step's own) makes the tied step
    immaterial: the tie is undone and the step is reported as fitted."""
    prob, cand, base = _friction_problem(0.0)
    prob.score(cand, ["friction"], base.nrmse_holdout, laws=["viscous"])
    kept = tie_path(prob, [base, cand], base.nrmse_holdout)
    assert kept[1].tied_law == "viscous" and kept[1].step_test["relative_gain"] > 0.1
    twin = copy.copy(base)
    twin.nrmse_loto, twin.loto_num = kept[1].nrmse_loto, dict(kept[1].loto_num)
    undone = tie_path(prob, [twin, cand], base.nrmse_holdout)
    assert undone[1].tied_law == "" and prob.ties == {} and undone[1].params == cand.params


def _tied_friction():
    prob, cand, base = _friction_problem(0.0)
    prob.score(cand, ["friction"], base.nrmse_holdout, laws=["viscous"])
    return prob, cand, tie_damping(prob, cand, base.nrmse_holdout)


@pytest.mark.slow
def test_a_tied_steps_profile_counts_the_laws_coefficients_and_reads_the_tied_chi2():
    """Fitted values of the tied χ²: the 5 parameters (k, x_ref, m, F_c, x_s) and the viscous law's one
    coefficient (6), against one c_e per training test (5 + 5) for the free fit; its χ² is the tied one, which is
    never below the free one (each test's own c_e is the free minimum); no tie is left behind."""
    prob, cand, tied = _tied_friction()
    hooks, free = profile_hooks(prob, tied), problem_hooks(prob, cand)
    assert (hooks["p"], free["p"]) == (5 + 1, 5 + len(prob.train)) and len(prob.train) == 5
    with prob.tied(["friction"], "viscous"):
        direct = prob.train_chi2(["friction"], tied.params)[0]
    assert hooks["chi2"](tied.params) == pytest.approx(direct, rel=1e-12)
    assert direct > free["chi2"](tied.params)
    assert prob.ties == {}


@pytest.mark.slow
def test_a_resample_refit_polishes_each_step_as_it_was_estimated():
    """On the data as they are (every test once) the tied step's refit stays at the tied F_c (1.989 N) and the
    free candidate's at the free one (1.963 N): 0.025 N apart, 100 times the tolerance."""
    prob, cand, tied = _tied_friction()
    ones = np.ones(len(prob.train))
    f_tied, f_free = tied.params["friction.F_c"], cand.params["friction.F_c"]
    assert abs(f_tied - f_free) > 0.02
    assert resampling.refit(prob, tied, ones)["friction.F_c"] == pytest.approx(f_tied, abs=2e-4)
    assert resampling.refit(prob, cand, ones)["friction.F_c"] == pytest.approx(f_free, abs=2e-4)
    assert prob.ties == {}


@pytest.mark.slow
def test_the_tie_narrows_the_profile_of_a_dissipative_effect_and_both_hold_the_truth():
    """With c_e tied, the friction's first harmonic 4·F_c/(π·ω·A) is the friction's again instead of being shared
    with a free c_e per test: F_c's 90 % profile interval is at least a quarter narrower (0.070 N against
    0.116 N here), and both hold the true 2 N."""
    prob, cand, tied = _tied_friction()
    widths = []
    for c, hooks in ((cand, problem_hooks(prob, cand)), (tied, profile_hooks(prob, tied))):
        k = "friction.F_c"
        lo, hi = profile_interval(k, dict(c.params), hooks["bounds"][k], 0.01, hooks["chi2"], hooks["refit"],
                                  hooks["n"], hooks["p"])["ci90"]
        assert lo <= 2.0 <= hi
        widths.append(hi - lo)
    assert widths[1] < 0.75 * widths[0]
