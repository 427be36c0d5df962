"""The time route's base damping chosen by leave-one-record-out (:mod:`chainid.gap.timedomain.lawchoice`).

Independent references: each fold refitted by ``numpy.linalg.lstsq`` on the stacked columns of the linear device
written out here (x, ẍ·1e-3, ẋ and (ω_r − w̄)·ẋ, (A_r − Ā)·ẋ, each minus its mean over the record), and the
one-standard-error rule by hand.  Records: the linear device of ``recovery_cases`` (k = 10 N/mm, preloads per record)
under random motion of distinct bands and amplitudes; σ_x = 1 µm, σ_F = 0.1 N.
"""
from __future__ import annotations

import math
import re
import warnings

import numpy as np
import pytest

import recovery_cases as rc
import sim_devices as sd
from chainid.gap.timedomain.lawchoice import better
from chainid.gap.timedomain.route import build_problem

SPEC = (((0.5, 1.5), 0.6), ((0.5, 1.5), 1.2), ((1.5, 3.0), 0.6), ((1.5, 3.0), 1.2), ((1.0, 2.2), 0.9))
FS, N = 200.0, 4000


def _records(c_of):
    """Five records; record i's dashpot c_of(i, ω_i, A_i) [N·s/mm] (ω_i its band centre [rad/s], A_i half range)."""
    t = sd.sample_times(N, FS)
    recs = []
    for i, (band, rms) in enumerate(SPEC):
        rng = np.random.default_rng(90 + i)
        f = np.sort(rng.uniform(band[0], band[1], 12))
        a = np.full(f.size, rms * math.sqrt(2.0 / f.size))
        mo = sd.sines(f, a, rng.uniform(0.0, 2 * np.pi, f.size))
        x, xd, _ = mo(t)
        c = c_of(i, rc.band_centre(f, a), 0.5 * float(np.ptp(x)))
        recs.append(sd.noisy(f"r{i}", t, x, rc.K_LIN * x + c * xd + 3.0 * i, rc.SX_LIN, rc.SF_LIN, i))
    return recs


def _problem(recs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return build_problem(recs, ["r4"], 0, None, None)


def _lstsq_loo(prob, feats):
    """Per training record, its χ² predicted from the other training records' fit (unbounded least squares on the
    fit subsets; the bounds do not bind on these records)."""
    train = [d for d in prob.tdata if prob.train_mask(d.test).any()]
    w_ref, A_ref = np.mean([d.omega_c for d in train]), np.mean([d.A_c for d in train])
    cols = {}
    for d in train:
        idx, lead = prob._fit[d.test]
        keep = np.ones(idx.size, bool) if lead is None else ~lead
        x, xd, xdd = d.x[idx], d.xd[idx], d.xdd[idx]
        M = [x, xdd * 1e-3, xd] + [xd * (d.omega_c - w_ref)] * ("w" in feats) + [xd * (d.A_c - A_ref)] * ("A" in feats)
        M, y = np.column_stack(M)[keep], np.asarray(d.F, float)[idx][keep]
        cols[d.test] = (M - M.mean(axis=0), y - y.mean(), d.sigma)
    out = []
    for d in train:
        Ms = [cols[e.test] for e in train if e is not d]
        a = np.linalg.lstsq(np.vstack([m / s for m, _, s in Ms]), np.concatenate([y / s for _, y, s in Ms]),
                            rcond=None)[0]
        M, y, s = cols[d.test]
        out.append(float(np.sum((y - M @ a) ** 2) / s**2))
    return np.array(out)


def test_the_one_standard_error_rule_by_hand():
    # paired differences 3, 4, 5: sum 12 > √3·1 = 1.73 → better; 3, −2, 1: sum 2 < √3·2.52 = 4.36 → not
    assert better(np.array([7.0, 6.0, 5.0]), np.array([10.0, 10.0, 10.0]))
    assert not better(np.array([7.0, 12.0, 9.0]), np.array([10.0, 10.0, 10.0]))


def test_a_dashpot_that_follows_the_band_is_chosen_and_scored_as_refits_score_it():
    """c_r = 0.4·(1 + 0.5·(ω_r − 9)/9): the law over ω (or over ω and A) predicts a left-out record far better than
    one c; each candidate's summed χ² is that of the hand-built refits (to the 4 digits the reason prints)."""
    prob = _problem(_records(lambda i, w, A: 0.4 * (1.0 + 0.5 * (w - 9.0) / 9.0)))
    assert prob.base.law and "w" in prob.base.law_features
    for feats, label in (((), "one c"), (("w",), "law over ω")):
        got = float(re.search(f"{label} ([0-9.e+-]+)", prob.law_reason).group(1))
        assert got == pytest.approx(float(_lstsq_loo(prob, feats).sum()), rel=1e-3)  # 4 digits printed
    assert _lstsq_loo(prob, ("w",)).sum() < 0.5 * _lstsq_loo(prob, ()).sum()


def test_dashpots_that_scatter_about_one_value_keep_one_c():
    """c_r = 0.4·(1 ± 2 %), the signs +, −, −, + over the training records r0 … r3 (bands low, low, high, high;
    amplitudes low, high, low, high): a scatter with no linear trend in either feature.  No law beats one c by a
    standard error."""
    jitter = (0.02, -0.02, -0.02, 0.02, 0.0)
    prob = _problem(_records(lambda i, w, A: 0.4 * (1.0 + jitter[i])))
    assert not prob.base.law and prob.law == "viscous"
    assert "no law over the records' features predicts a left-out record better than one c" in prob.law_reason


def test_a_resample_refits_the_law_but_reports_no_interval_for_its_references():
    """The law's w_ref, A_ref and box are fixed references of the fit (the model file carries them), not estimates:
    a resample's refit returns the law's coefficients without them, so no 90 % interval is printed for them."""
    from chainid.gap.timedomain import resampling

    prob = _problem(_records(lambda i, w, A: 0.4 * (1.0 + 0.5 * (w - 9.0) / 9.0)))
    cand = prob.fit([])
    refs = {"damping_law.w_ref", "damping_law.A_ref", "damping_law.w_lo", "damping_law.w_hi"}
    assert refs <= set(cand.params)
    got = resampling.refit(prob, cand, resampling.identity(prob))
    assert not refs & set(got) and {"damping.c", "damping_law.b_w"} <= set(got)
    assert got["damping_law.b_w"] == pytest.approx(cand.params["damping_law.b_w"], rel=1e-6)
