"""The base's damping law on a held-out record beyond the training records' features: read at the edge of the
training box, as ``predict`` reads a saved law (:meth:`chainid.gap.timedomain.design.Base.law_point`), never
extrapolated.

The linear device F = 10·x + c_r·ẋ + preload under random motion, four training records in 0.5–1.5 and 1–2 Hz at
0.6 and 1.2 mm RMS, and a held-out record r4 in 3–4 Hz (its band centre about twice the training's largest).  The
truth is the law held within the training box: c_r = 0.4 + b_w·(ω̃_r − w̄) + b_A·(Ã_r − Ā), ω̃_r and Ã_r the
record's features (:func:`chainid.model.timedamping.record_features` of the noise-free motion) clipped to the
training records' range; each feature moves c by up to ±10 % over the training records.  Extrapolated linearly,
the law would put r4's c about 0.3 N·s/mm higher: some 6 N RMS on its force, 60 times its noise σ_F = 0.1 N.
"""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import sim_devices as sd
from chainid.gap.timedomain.route import build_problem
from chainid.model.timedamping import record_features

SPEC = (((0.5, 1.5), 0.6), ((0.5, 1.5), 1.2), ((1.0, 2.0), 0.6), ((1.0, 2.0), 1.2), ((3.0, 4.0), 0.9))
FS, N, C0, SIGMA_F = 200.0, 4000, 0.4, 0.1


def _records():
    t = sd.sample_times(N, FS)
    motions = [sd.multisine(N / FS, lo, hi, rms, 0.0, 40 + i) for i, ((lo, hi), rms) in enumerate(SPEC)]
    feats = np.array([record_features(t, mo(t)[0]) for mo in motions])
    W, A = feats[:4, 0], feats[:4, 1]
    b_w = 0.1 * C0 / float(W.max() - W.mean())
    b_A = 0.1 * C0 / float(A.max() - A.mean())
    w_c = np.clip(feats[:, 0], W.min(), W.max())
    A_c = np.clip(feats[:, 1], A.min(), A.max())
    c = C0 + b_w * (w_c - W.mean()) + b_A * (A_c - A.mean())
    recs = []
    for i, mo in enumerate(motions):
        x, xd, _ = mo(t)
        recs.append(sd.noisy(f"r{i}", t, x, 10.0 * x + c[i] * xd + 3.0 * i, 1e-6, SIGMA_F, i))
    return recs, feats, c


@pytest.fixture(scope="module")
def case():
    recs, feats, c = _records()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        prob = build_problem(recs, ["r4"], 0, None, None)
    return prob, feats, c


def test_the_held_out_record_lies_beyond_the_training_box(case):
    prob, feats, _ = case
    assert feats[4, 0] > 1.8 * feats[:4, 0].max()


def test_the_box_is_the_training_records_and_holds_the_held_out_features(case):
    prob, _, _ = case
    train = [d for d in prob.tdata if d.test != "r4"]
    hold = next(d for d in prob.tdata if d.test == "r4")
    assert prob.law_box["w_lo"] == min(d.omega_c for d in train)
    assert prob.law_box["w_hi"] == max(d.omega_c for d in train)
    w, A = prob.base.law_point(hold)
    assert w == prob.law_box["w_hi"] and hold.omega_c > w
    assert A == min(max(hold.A_c, prob.law_box["A_lo"]), prob.law_box["A_hi"])


def test_held_out_force_at_its_noise_with_the_law_read_at_the_box_edge(case):
    prob, _, c = case
    cand = prob.fit([])
    res = prob.evaluate([], cand.params)["res"]["r4"]
    assert math.sqrt(float(np.mean(res**2))) < 1.5 * SIGMA_F
    refs = prob.base.refs
    hold = next(d for d in prob.tdata if d.test == "r4")
    w, A = prob.base.law_point(hold)
    c_hold = cand.params["damping.c"] + cand.params["damping_law.b_w"] * (w - refs["w_ref"]) \
        + cand.params["damping_law.b_A"] * (A - refs["A_ref"])
    assert c_hold == pytest.approx(c[4], rel=0.02)
