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
from chainid.gap.harmonic.tie import f_test, tie_damping, tie_path

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


@pytest.mark.slow
def test_without_noise_the_grids_friction_comes_back_exact(monkeypatch):
    """The harmonic benchmark's friction case (14×50 chain, 3 × 3 plan, F_c = 0.1·S, μ = x_s = 0) with its force
    noise cut to 10⁻⁵ of S: F_c within 0.01 % of the simulator's, x_s under 10⁻⁶ mm, and μ within 4 standard errors
    of its bound 0.  SE(μ) = σ_F/√(Σ r²), r the samples' μ regressor |F_k(x)|·sgn ẋ less its least-squares part on
    what every test fits besides (1, x, ẋ, sgn ẋ, x², x³: the spring's shape, c_e, F_c), σ_F the simulated force
    noise: about 9·10⁻⁸ over the 9 tests' samples.  The low F_c of the noisy grid is the noise's, through those
    bounds (:mod:`chainid.gap.harmonic.tie`), not the model's."""
    import chainid.records.simulate as simulate_module
    from chainid.gap.benchmark.grid import run_case, selected_cases
    from chainid.model.base import ChainModel

    seen: dict = {}
    real = simulate_module.simulate

    def keep(*args, **kwargs):
        seen["records"], seen["noise_F"] = real(*args, **kwargs), kwargs["noise_F"]
        return seen["records"]

    monkeypatch.setattr(simulate_module, "simulate", keep)
    case = next(c for c in selected_cases(False, 0, ("harmonic",), None, "harmonic/single/friction")
                if c["levels"] == [1.0] and c["noise"] == 0.01 and c["chain"] == "14x50" and c["plan"] == "grid3x3")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        row = run_case(case | {"noise": 1e-5, "resamples": 0})
    assert row["verdict"] == "friction"
    truth = row["true_params"]["friction.F_c"]
    assert row["params"]["friction.F_c"] == pytest.approx(truth, rel=1e-4)
    chain, rr = ChainModel(), 0.0
    for r in seen["records"]:
        xd = np.gradient(r.x, r.t)
        z = np.abs(chain.force(r.x)) * np.sign(xd)
        X = np.column_stack([np.ones_like(r.x), r.x, xd, np.sign(xd), r.x**2, r.x**3])
        res = z - X @ np.linalg.lstsq(X, z, rcond=None)[0]
        rr += float(res @ res)
    se_mu = seen["noise_F"] / np.sqrt(rr)
    assert 0.0 <= row["params"]["friction.mu"] < 4.0 * se_mu and row["params"]["friction.x_s"] < 1e-6
