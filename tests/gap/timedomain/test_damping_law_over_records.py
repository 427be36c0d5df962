"""The time-domain damping law: a linear device F = 10·x + c_r·ẋ + preload whose viscous c varies by about ±20 %
over random records as c_r = c0 + b_w·(ω_r − w̄) + b_A·(A_r − Ā) — ω_r the band centre of the record's
displacement (the power-weighted mean angular frequency of its lines, computed here from the lines themselves),
A_r half its range (from the noise-free motion).  The paper's c_e(ω, A) is the base model's damping, so the base
carries the law (:class:`chainid.gap.timedomain.design.Base`): the diagnosis is ``none`` (nothing beyond the base
differs), its law's slopes b_w, b_A and the per-record c they give within 5 %, the held-out record's c predicted
by the law; with ``damping_law="viscous"`` (one c for every record) the law is what differs, named as the effect
``damping_law``.

Five records of 4 000 samples at 200 Hz (20 s): bands 0.5–1.5 and 1.5–3 Hz crossed with RMS 0.6 and 1.2 mm (the
held-out r4: 1–2.2 Hz, 0.9 mm); σ_x = 1 µm, σ_F = 0.1 N.  ``grid``: lines on the record's own frequency grid, 4 bins
apart (the band centre of the finite record is that of its lines); ``random``: 12 lines drawn anywhere in the band.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import recovery_cases as rc
import sim_devices as sd

pytestmark = pytest.mark.slow

SPEC = (((0.5, 1.5), 0.6), ((0.5, 1.5), 1.2), ((1.5, 3.0), 0.6), ((1.5, 3.0), 1.2), ((1.0, 2.2), 0.9))
FS, N = 200.0, 4000
C0 = 0.4


def _law_set(grid: bool):
    t = sd.sample_times(N, FS)
    T = N / FS
    motions, W, A = [], [], []
    for i, (band, rms) in enumerate(SPEC):
        rng = np.random.default_rng(70 + i)
        if grid:
            f = np.arange(math.ceil(band[0] * T), math.floor(band[1] * T) + 1, 4) / T
        else:
            f = np.sort(rng.uniform(band[0], band[1], 12))
        a = np.full(f.size, rms * math.sqrt(2.0 / f.size))
        mo = sd.sines(f, a, rng.uniform(0.0, 2 * np.pi, f.size))
        motions.append(mo)
        W.append(rc.band_centre(f, a))
        A.append(0.5 * float(np.ptp(mo(t)[0])))
    W, A = np.array(W), np.array(A)
    b_w = 0.1 * C0 / float(W.max() - W.mean())  # each feature moves c by up to ±10 %
    b_A = 0.1 * C0 / float(A.max() - A.mean())
    c = C0 + b_w * (W - W.mean()) + b_A * (A - A.mean())
    recs = []
    for i, mo in enumerate(motions):
        x, xd, _ = mo(t)
        recs.append(sd.noisy(f"r{i}", t, x, rc.K_LIN * x + c[i] * xd + 3.0 * i, rc.SX_LIN, rc.SF_LIN, i))
    return recs, {"b_w": b_w, "b_A": b_A, "c": dict(zip([r.test for r in recs], c))}


def _diagnosed(grid: bool, law: str = "auto"):
    truth = _law_set(grid)[1]
    res = rc.diagnosed(f"law_{'grid' if grid else 'random'}_{law}", lambda: (_law_set(grid)[0], ["r4"], None),
                       damping_law=law)[0]
    return res, truth


def _per_record_c(res: dict) -> dict[str, float]:
    """c_r = c + b_w·(ω_r − w_ref) + b_A·(A_r − A_ref) from the fitted law and the record features reported."""
    p = rc.final_params(res)
    return {t["test"]: p["damping.c"] + p["damping_law.b_w"] * (t["omega_c"] - p["damping_law.w_ref"])
            + p["damping_law.b_A"] * (t["A"] - p["damping_law.A_ref"]) for t in res["tests"]}


def test_the_set_spans_plus_minus_20_percent_of_damping():
    c = np.array(list(_law_set(True)[1]["c"].values()))
    assert 0.15 <= (c.max() - c.min()) / (2 * C0) <= 0.25


@pytest.mark.parametrize("grid", [True, False], ids=["grid_lines", "random_lines"])
def test_the_base_carries_the_law_and_per_record_damping_within_5_percent(grid):
    res, truth = _diagnosed(grid)
    assert res["verdict"] == "none", res["chain_text"]
    assert res["baseline"]["damping_law"] == "feature"
    got = _per_record_c(res)
    for test, c in truth["c"].items():
        assert rc.rel_err(got[test], c) <= 0.05, (test, got[test], c)


def test_damping_law_slopes_within_5_percent_on_grid_lines():
    res, truth = _diagnosed(True)
    p = rc.final_params(res)
    assert rc.rel_err(p["damping_law.b_w"], truth["b_w"]) <= 0.05, (p, truth)
    assert rc.rel_err(p["damping_law.b_A"], truth["b_A"]) <= 0.05, (p, truth)


@pytest.mark.xfail(strict=True, reason=(
    "12 random lines per band, 20 s, lines off the record's frequency grid: the band centre the diagnosis reads (the "
    "periodogram of the finite record, leakage included) is not the lines' power-weighted mean the simulation "
    "defines the law on, so b_w = 0.01198 against 0.01094 (+9.5 %; +12 % with a Hann window); the per-record c is "
    "within 3 %, and on lines on the grid the slopes are within 0.1 %"))
def test_damping_law_slopes_within_5_percent_on_random_lines():
    res, truth = _diagnosed(False)
    p = rc.final_params(res)
    assert rc.rel_err(p["damping_law.b_w"], truth["b_w"]) <= 0.05, (p, truth)
    assert rc.rel_err(p["damping_law.b_A"], truth["b_A"]) <= 0.05, (p, truth)


def test_one_viscous_c_leaves_the_law_above_the_noise():
    """The same grid-line set with one c for every record (``damping_law="viscous"``): the ±20 % spread of the
    records' damping is what differs from that base, and the selection names it as the effect ``damping_law``."""
    res, _ = _diagnosed(True, "viscous")
    assert res["baseline"]["damping_law"] == "viscous"
    assert res["verdict"] == "damping_law", res["chain_text"]
