"""The time route's profile likelihood: its χ² is counted against the records' own force noise, and a fit with a
parameter held keeps it and refits the rest.

Reference: the linear device with nothing else (its base model exact), force noise σ_F = 0.1 N and a nearly
noise-free displacement, so the training residual is the force noise: χ²/(cells − p) must be 1 within 4 of its
standard deviations, √(2/(cells − p)); and Coulomb friction 2·sgn(ẋ) N, whose profile interval must cover it.
"""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import recovery_cases as rc
from chainid.gap.core.profile import problem_hooks, profile_interval
from chainid.gap.timedomain.route import build_problem


def _problem(extra=None, seed=0):
    recs = rc.linear_random(extra, n=2000, band=(0.5, 4.0), seed=seed, sigma_x=1e-7, sigma_F=0.1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return build_problem(recs, ["r4"], 0, None, None)


def test_chi2_of_the_exact_model_is_its_noise_cells():
    prob = _problem()
    c = prob.fit([])
    chi, n, p = prob.train_chi2([], c.params)
    # k, m of the linear device and its dashpot's law over the records' features, c, b_w, b_A (offsets are nuisance)
    assert n == prob.n_cells("train") and p == 5
    assert abs(chi / (n - p) - 1.0) < 4 * math.sqrt(2.0 / (n - p))


def test_held_amplitude_keeps_its_value_and_costs_chi2():
    prob = _problem()
    c = prob.fit([])
    v = 1.05 * c.params["damping.c"]
    held = prob.fit([], fix={"damping.c": v}).params
    assert held["damping.c"] == v
    assert prob.train_chi2([], held)[0] > prob.train_chi2([], c.params)[0]


def test_fix_of_a_parameter_that_is_not_fitted_is_refused():
    prob = _problem()
    with pytest.raises(ValueError, match=r"fix: \['friction.nope'\] are not fitted parameters of friction"):
        prob.fit(["friction"], fix={"friction.nope": 1.0})


def test_profile_interval_of_coulomb_friction_covers_it():
    prob = _problem(lambda mo, t: 2.0 * np.sign(mo(t)[1]), seed=1)
    c = prob.fit(["friction"])
    h = problem_hooks(prob, c)
    r = profile_interval("friction.F_c", dict(c.params), h["bounds"]["friction.F_c"], 0.01, h["chi2"], h["refit"],
                         h["n"], h["p"])
    lo, hi = r["ci90"]
    assert lo < c.params["friction.F_c"] < hi
    assert lo <= 2.0 <= hi
    assert hi - lo < 0.05 * 2.0  # an informative interval, not the bounds
