"""How far the 90 % intervals of the time route can be trusted (``diagnose(..., resamples=N)``).

One friction case — the linear device + 2·sgn(ẋ) N on the true velocity, 5 records of 2 000 samples (0.5–4 Hz),
r4 held out — simulated with 20 noise realisations (:mod:`recovery_cases`): the interval
``steps[-1]["params_ci90"]["friction.F_c"]`` must cover the truth in at least 15 of 20.  The refit a resample makes
(:func:`chainid.gap.timedomain.resampling.refit`: shapes polished from the full fit) must agree with a brute-force
refit from scratch on the same multiplicities (``prob.fit(names, weights=mult)``) within 2 %, and the 90 %
interval over 40 such refits must be the brute-force refits' (each end within 2 % of its width).

The library is restricted to ``friction`` (one effect at most): the intervals, not the selection, are under test.
"""
from __future__ import annotations

import warnings

import numpy as np
import pytest

import recovery_cases as rc
from chainid.gap.diagnose import diagnose

pytestmark = pytest.mark.slow

F_C = 2.0
N_REAL, NEED = 20, 15


def _friction_records(seed: int) -> list:
    return rc.linear_random(lambda mo, t: F_C * np.sign(mo(t)[1]), n=2000, band=(0.5, 4.0), seed=seed)


def _diagnose(seed: int, resamples: int) -> dict:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return diagnose(_friction_records(seed), ["r4"], None, quiet=True, effects=["friction"], max_combo=1,
                        resamples=resamples, seed=seed)


def test_ninety_percent_interval_covers_the_truth_in_15_of_20_realisations():
    covered = missed = 0
    for seed in range(N_REAL):
        ci = _diagnose(seed, 100)["steps"][-1]["params_ci90"]["friction.F_c"]
        if ci[0] <= F_C <= ci[1]:
            covered += 1
        else:
            missed += 1
        if covered >= NEED or missed > N_REAL - NEED:  # decided
            break
    assert covered >= NEED, (covered, missed)


def test_resample_refit_agrees_with_a_refit_from_scratch():
    from chainid.gap.timedomain import resampling

    res = _diagnose(0, 0)
    assert res["verdict"] == "friction", res["chain_text"]
    prob, cand = res["_problem"], res["_path"][-1]
    rng = np.random.default_rng(123)
    for _ in range(3):
        mult = resampling.draw(prob, rng)
        quick = resampling.refit(prob, cand, mult)
        full = prob.fit(cand.names, weights=mult).params
        for k in ("friction.F_c", "damping.c", "spring.k"):
            assert quick[k] == pytest.approx(full[k], rel=0.02), (k, quick[k], full[k])


def test_percentile_interval_agrees_with_one_from_brute_force_refits():
    """The 90 % interval of F_c from the resampling's refits (shapes polished from the full fit; before the
    diagnosis recentres them on its estimate, a shift the same for every refit) against the one
    from refits from scratch (``prob.fit(names, weights=mult)``) on the same 40 draws: each end within 2 % of the
    brute-force interval's width, and the widths within 2 % (observed: the same to 8 digits).  The time sampling's
    bias, which every resample shares, is in neither: the coverage test above takes it in (the diagnosis widens
    the interval by it)."""
    from chainid.gap.timedomain import resampling

    res = _diagnose(1, 0)
    assert res["verdict"] == "friction", res["chain_text"]
    prob, cand = res["_problem"], res["_path"][-1]
    rng = np.random.default_rng(7)
    quick, brute = [], []
    for _ in range(40):
        mult = resampling.draw(prob, rng)
        quick.append(resampling.refit(prob, cand, mult)["friction.F_c"])
        brute.append(prob.fit(cand.names, weights=mult).params["friction.F_c"])
    q, b = np.percentile(quick, [5, 95]), np.percentile(brute, [5, 95])
    width = b[1] - b[0]
    assert width > 0
    assert abs(q[0] - b[0]) <= 0.02 * width and abs(q[1] - b[1]) <= 0.02 * width, (q, b)
    assert (q[1] - q[0]) == pytest.approx(width, rel=0.02)


def test_a_resample_refits_the_law_but_states_no_interval_for_its_references():
    """The law's w_ref, A_ref and box are fixed references of the fit (the model file carries them), not estimates:
    a resample's refit returns the law's coefficients without them, so no 90 % interval is stated for them.  On the
    identity resample the refit is the full fit."""
    from chainid.gap.timedomain import resampling
    from chainid.gap.timedomain.route import build_problem
    from chainid.model.timedamping import BOX_KEYS

    recs = rc.linear_random(None, n=2000, band=(0.5, 4.0), seed=0, sigma_x=1e-7, sigma_F=0.1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        prob = build_problem(recs, ["r4"], 0, None, None)
    cand = prob.fit([])
    refs = {"damping_law.w_ref", "damping_law.A_ref", *(f"damping_law.{k}" for k in BOX_KEYS)}
    assert refs <= set(cand.params)
    got = resampling.refit(prob, cand, resampling.identity(prob))
    assert not refs & set(got)
    assert {"damping.c", "damping_law.b_w", "damping_law.b_A", "spring.k"} <= set(got)
    for k in ("damping.c", "damping_law.b_w", "spring.k"):
        assert got[k] == pytest.approx(cand.params[k], rel=1e-6, abs=1e-12), k
