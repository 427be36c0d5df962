"""A hysteresis whose loop changes with the speed is not kept (:mod:`chainid.gap.timedomain.ratecheck`).

Six records of a linear device F = 10·x + 0.2·ẋ + preload, each a chirp 0.2 → 2 Hz (amplitudes 0.6–1.35 mm), r5
held out.  Two added forces, each simulated apart from the code under test (:mod:`sim_devices`):

* a Dahl hysteresis (Bouc–Wen with n = 1, r = 1), F_h = 5 N, x_h = 0.1 mm: rate-independent by its form, so its
  parameters on the slow and the fast blocks are the same (rate exponent 0);
* a Maxwell branch (spring k_m = 3 N/mm in series with a dashpot, τ = 3 s; outside the library).  For ẋ ≠ 0 its
  force obeys dq/dx = (k_m·τ·|ẋ| − q)/(τ·|ẋ|): a Dahl loop with F_h = k_m·τ·|ẋ| and x_h = τ·|ẋ|, both in
  proportion to the speed (rate exponent 1).  Here τ·|ẋ| (6–17 mm) is far beyond the stroke, the regime in which
  the relaxation passes for a hysteresis loop.
"""
from __future__ import annotations

import functools
import math
from types import SimpleNamespace

import numpy as np
import pytest

import recovery_cases as rc
import sim_devices as sd
from chainid.gap.core.summary import summary
from chainid.gap.timedomain.ratecheck import MIN_EXPONENT, block_stats, rate_cut, rate_exponent, rate_test
from chainid.gap.diagnose import diagnose
from chainid.gap.timedomain.route import build_problem

FS, N, OVER = 200.0, 4000, 4
K_M, TAU = 3.0, 3.0
F_H, X_H = 5.0, 0.1
DF_S, V_S = 3.0, 2.0  # a Stribeck peak beside the Dahl loop: friction that weakens with the speed


@functools.lru_cache(maxsize=None)
def _records(kind: str) -> list:
    t = sd.sample_times(N, FS)
    recs = []
    for i in range(6):
        mo = sd.chirp(0.2, 2.0, 1.0, N / FS - 1.0, 0.6 + 0.15 * i, 1.0)
        x, xd, _ = mo(t)
        tf, xf, _ = sd.fine_path(mo, t, OVER)
        extra = (sd.maxwell_force(tf, xf, K_M, TAU) if kind == "maxwell"
                 else F_H * sd.bouc_wen_z(xf, X_H, 1.0, 1.0))[::OVER]
        if kind == "dahl+stribeck":
            extra = extra + sd.stribeck_force(xd, 0.0, DF_S, V_S)
        F = rc.K_LIN * x + rc.C_LIN * xd + 3.0 * i + extra
        recs.append(sd.noisy(f"r{i}", t, x, F, rc.SX_LIN, rc.SF_LIN, i))
    return recs


@pytest.fixture(scope="module")
def fitted():
    out = {}
    for kind in ("dahl", "maxwell"):
        prob = build_problem(_records(kind), ["r5"], 0, None)
        out[kind] = (prob, prob.fit(["hysteresis"]))
    return out


def test_block_stats_are_the_rms_speed_and_stroke_of_each_block(fitted):
    prob, _ = fitted["dahl"]
    v, st = block_stats(prob)
    d = prob.tdata[2]
    off = sum(dd.n_blocks for dd in prob.tdata[:2])
    for b in range(d.n_blocks):
        seg, x = d.xd[d.block == b], d.x[d.block == b]
        assert v[off + b] == pytest.approx(math.sqrt(np.mean(seg**2)), rel=1e-12)
        assert st[off + b] == pytest.approx(math.sqrt(np.mean((x - x.mean()) ** 2)), rel=1e-12)


def test_a_dahl_loop_has_the_same_parameters_on_slow_and_fast_blocks(fitted):
    prob, cand = fitted["dahl"]
    assert cand.params["hysteresis.F_h"] == pytest.approx(F_H, rel=0.02)  # the fit is the truth: a fair null
    t = rate_test(prob, cand, "hysteresis")
    assert t is not None and t["v_fast_mm_s"] / t["v_slow_mm_s"] > 2.0  # the chirps resolve the rate
    for k in ("hysteresis.F_h", "hysteresis.x_h"):
        assert abs(t["exponent"][k]) <= 0.05, t  # rate-independent: exponent 0
    assert t["dependent"] == []


def test_a_maxwell_relaxation_fitted_as_hysteresis_scales_with_the_speed(fitted):
    prob, cand = fitted["maxwell"]
    t = rate_test(prob, cand, "hysteresis")
    assert t is not None
    for k in ("hysteresis.F_h", "hysteresis.x_h"):
        assert MIN_EXPONENT <= t["exponent"][k] <= 1.3, t  # the Maxwell loop: exponent 1
        assert t["on_fast"][k] > 1.5 * t["on_slow"][k]
    assert set(t["dependent"]) == {"hysteresis.F_h", "hysteresis.x_h"}


def test_the_exponent_is_the_speed_slope_of_a_plane_through_zero_and_its_z_the_scatter_about_it():
    ev = np.array([1.0, 0.5, -0.5, 0.2, -0.3, 0.4])
    es = np.array([0.1, -0.4, 0.3, 0.5, 0.2, -0.1])
    p, z = rate_exponent(ev, es, 0.8 * ev + 0.3 * es)
    assert p == pytest.approx(0.8, rel=1e-12) and z > 1e12  # no scatter: z unbounded (rounding aside)
    L = 0.8 * ev + 0.3 * es + np.array([0.05, -0.03, 0.02, -0.04, 0.01, 0.03])
    X = np.column_stack([ev, es])
    beta, rss, *_ = np.linalg.lstsq(X, L, rcond=None)  # another method: the SVD solution
    cov = rss[0] / (6 - 2) * np.linalg.inv(X.T @ X)
    p, z = rate_exponent(ev, es, L)
    assert p == pytest.approx(beta[0], rel=1e-10)
    assert z == pytest.approx(abs(beta[0]) / math.sqrt(cov[0, 0]), rel=1e-10)
    assert math.isnan(rate_exponent(ev, 2.0 * ev, L)[0])  # speed and stroke go together: not separable
    assert math.isnan(rate_exponent(ev[:3], es[:3], L[:3])[0])  # three splits: too few to judge


def test_the_loop_is_judged_beside_the_chains_other_effects():
    """Dahl loop + Stribeck friction: the Dahl fit alone takes up the friction's fall with the speed and reads as
    rate-dependent; in the chain's last fit, beside the Stribeck term, it is rate-independent and kept."""
    prob = build_problem(_records("dahl+stribeck"), ["r5"], 0, None)
    alone, both = prob.fit(["hysteresis"]), prob.fit(["hysteresis", "stribeck"])
    assert rate_test(prob, alone, "hysteresis")["dependent"]  # the case tests something
    t = rate_test(prob, both, "hysteresis")
    assert t["dependent"] == [] and all(abs(p) <= 0.1 for p in t["exponent"].values()), t
    step, finding, checks = rate_cut(prob, [SimpleNamespace(names=[]), alone, both])
    assert step is None and finding is None
    (row,) = checks  # the loop was checked, and judged rate-independent
    assert row["effect"] == "hysteresis" and row["step"] == 1 and row["judged"] and row["dependent"] == []


def test_speeds_too_alike_to_resolve_a_rate_are_not_judged():
    t = sd.sample_times(N, FS)
    recs = []
    for i in range(4):
        mo = sd.sine(1.0, 1.0)
        x, xd, _ = mo(t)
        recs.append(sd.noisy(f"r{i}", t, x, rc.K_LIN * x + rc.C_LIN * xd + 2.0 * np.tanh(xd / 0.5), rc.SX_LIN,
                             rc.SF_LIN, i))
    prob = build_problem(recs, ["r3"], 0, None)
    assert rate_test(prob, prob.fit(["hysteresis"]), "hysteresis") is None


@pytest.mark.parametrize("kind", ["maxwell", "dahl"])
def test_the_diagnosis_keeps_a_dahl_loop_and_cuts_a_relaxation(kind):
    res = diagnose(_records(kind), ["r5"], None, effects=["hysteresis"], quiet=True, uncertainty=False)
    if kind == "dahl":
        assert res["verdict"] == "hysteresis" and res["rate_dependence"] is None
        assert [c["effect"] for c in res["rate_checks"]] == ["hysteresis"] and res["rate_checks"][0]["judged"]
        return
    rd = res["rate_dependence"]
    assert res["verdict"] == "unexplained" and res["trusted_steps"] == 1 and not res["overfitted"]
    assert rd["step"] == 1 and rd["effect"] == "hysteresis" and rd["exponent"] >= MIN_EXPONENT
    assert res["where"][0]["kind"] == "rate_dependence"
    assert res["steps"][1]["rate_dependent"] is True
    assert res["best"] is None or "hysteresis" not in res["best"]["effect"]  # the cut effect is not "best"
    assert res["model"]["effects"] == []  # the model found (the file --save-model writes) is the baseline
    text = summary(res)
    assert "<< changes with the speed: rate-dependent, not kept" in text  # the waterfall's step
    assert "changes with the speed" in text.split("VERDICT:")[1]
    assert "[changes with the speed: rate-dependent, not kept]" in res["chain_text"]


def test_the_resamples_cut_the_same_effect():
    """The resampling replays the step rule on each resample; the effect cut as rate-dependent is cut from every
    replayed chain too, so the kept chain (the baseline alone) is what they choose."""
    res = diagnose(_records("maxwell"), ["r5"], None, effects=["hysteresis"], quiet=True, uncertainty=False,
                   resamples=20)
    assert res["rate_dependence"] is not None
    assert res["stability"]["same_chain"] >= 0.9, res["stability"]["chains"]


def test_a_loop_whose_amplitude_follows_an_operating_condition_is_checked_as_its_effect(monkeypatch):
    """A chain names an effect whose amplitude follows a covariate ``hysteresis@p``: the check reads it as a
    hysteresis, and the finding keeps the chain's name (what the resamples and the fallback leave out)."""
    from chainid.gap.timedomain import ratecheck

    seen = []
    read = {"v_slow_mm_s": 1.0, "v_fast_mm_s": 2.0, "on_slow": {"hysteresis.F_h": 1.0},
            "on_fast": {"hysteresis.F_h": 2.0}, "log_ratio": {"hysteresis.F_h": math.log(2.0)},
            "exponent": {"hysteresis.F_h": 1.0}, "z": {"hysteresis.F_h": 5.0}, "dependent": ["hysteresis.F_h"]}
    monkeypatch.setattr(ratecheck, "rate_test", lambda prob, cand, effect: seen.append(effect) or read)
    path = [SimpleNamespace(names=[]), SimpleNamespace(names=["friction"]),
            SimpleNamespace(names=["friction", "hysteresis@p"])]
    step, finding, checks = rate_cut(None, path)
    assert seen == ["hysteresis"] and step == 2
    assert finding["effect"] == "hysteresis" and finding["name"] == "hysteresis@p"
    assert [c["name"] for c in checks] == ["hysteresis@p"]


def test_z_values_go_to_json_as_none_for_not_computed_and_one_million_for_no_scatter():
    from chainid.gap.timedomain.ratecheck import _json_z

    got = _json_z({"a": math.nan, "b": math.inf, "c": 2.5, "d": 3e7})
    assert got == {"a": None, "b": 1e6, "c": 2.5, "d": 1e6}


def test_the_exponent_is_read_from_four_splits_without_the_unread_ones():
    """Four finite splits are enough (three are not); a split whose parameter was not read (NaN) is left out: the
    exponent is then numpy's least-squares slope over the other four, through 0."""
    ev = np.array([1.0, 0.5, -0.5, 0.2, -0.3])
    es = np.array([0.1, -0.4, 0.3, 0.5, 0.2])
    L = 0.8 * ev + 0.3 * es + np.array([0.05, -0.03, 0.02, math.nan, 0.01])
    ok = np.isfinite(L)
    beta, *_ = np.linalg.lstsq(np.column_stack([ev[ok], es[ok]]), L[ok], rcond=None)
    p, z = rate_exponent(ev, es, L)
    assert p == pytest.approx(beta[0], rel=1e-10) and math.isfinite(z)
    L3 = L.copy()
    L3[0] = math.nan  # three finite splits left: not enough to read an exponent
    assert all(math.isnan(v) for v in rate_exponent(ev, es, L3))


@pytest.mark.parametrize("c, judged", [(0.94, True), (0.96, False)])
def test_speed_and_stroke_ratios_alike_beyond_095_are_not_separated(c, judged):
    """ℓ_v = (1, 0, 1, 0, 1, 0), ℓ_s = (c, s, c, s, c, s) with s = √(1 − c²): their correlation through 0 is
    3c/√(3·3) = c; the plane is fitted at 0.94 and refused at 0.96 (MAX_CORRELATION = 0.95)."""
    s = math.sqrt(1.0 - c * c)
    ev = np.array([1.0, 0.0] * 3)
    es = np.array([c, s] * 3)
    L = 0.7 * ev + np.array([0.01, -0.02, 0.03, 0.0, -0.01, 0.02])
    p, _ = rate_exponent(ev, es, L)
    assert math.isfinite(p) is judged


def test_no_speed_spread_no_exponent():
    """ℓ_v all 0 (Σℓ_v² = 0): no exponent, without dividing by zero."""
    ev = np.zeros(5)
    es = np.array([0.1, -0.4, 0.3, 0.5, 0.2])
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert all(math.isnan(v) for v in rate_exponent(ev, es, es))


def test_log_ratio_is_the_log_of_the_second_over_the_first_for_positive_values_only():
    from chainid.gap.timedomain.ratecheck import _log_ratio

    assert _log_ratio(2.0, 6.0) == pytest.approx(math.log(3.0), rel=1e-15)
    assert all(math.isnan(_log_ratio(a, b)) for a, b in ((0.0, 1.0), (1.0, 0.0), (-1.0, -2.0)))


def test_random_halves_are_distinct_partitions_other_than_the_speed_split():
    """Blocks 0 … 3 split 2 + 2 have three partitions; the speed split {0, 1} | {2, 3} is taken, so at most two
    random halves exist, each a different partition, named by the half holding block 0; eight blocks give the
    ten asked for, each half of four blocks, sorted."""
    from chainid.gap.timedomain.ratecheck import N_RANDOM, _random_halves

    got = _random_halves(np.arange(4), np.array([0, 1]), 10)
    parts = {frozenset(h.tolist()) if 0 in h else frozenset({0, 1, 2, 3} - set(h.tolist())) for h in got}
    assert len(got) == 2 and parts == {frozenset({0, 2}), frozenset({0, 3})}
    got = _random_halves(np.arange(8), np.arange(4), N_RANDOM)
    assert N_RANDOM == 10 and len(got) == 10
    assert all(h.size == 4 and np.all(np.diff(h) > 0) for h in got)
    keys = {frozenset(h.tolist()) if 0 in h else frozenset(set(range(8)) - set(h.tolist())) for h in got}
    assert len(keys) == 10 and frozenset(range(4)) not in keys


def test_an_empty_block_has_no_speed_and_no_stroke():
    """Blocks 0 and 2 of a record hold samples, block 1 none: its RMS speed and stroke are 0; the others are
    √mean(ẋ²) and the standard deviation of x, by hand."""
    d = SimpleNamespace(n_blocks=3, block=np.array([0, 0, 2, 2]), xd=np.array([3.0, -4.0, 1.0, 1.0]),
                        x=np.array([1.0, 3.0, 5.0, 5.0]))
    v, st = block_stats(SimpleNamespace(tdata=[d]))
    np.testing.assert_allclose(v, [math.sqrt(12.5), 0.0, 1.0], rtol=1e-15)
    np.testing.assert_allclose(st, [1.0, 0.0, 0.0], rtol=1e-15)


def _read(z_fh, z_xh, p):
    return {"v_slow_mm_s": 2.0, "v_fast_mm_s": 5.0, "on_slow": {"hysteresis.F_h": 1.5, "hysteresis.x_h": 0.1},
            "on_fast": {"hysteresis.F_h": 3.0, "hysteresis.x_h": 0.12}, "exponent": {"hysteresis.F_h": p,
                                                                                    "hysteresis.x_h": 0.2},
            "z": {"hysteresis.F_h": z_fh, "hysteresis.x_h": z_xh}, "dependent": ["hysteresis.F_h", "hysteresis.x_h"]}


@pytest.mark.parametrize("p, grows", [(0.76, True), (-0.76, False)])
def test_the_finding_reads_the_parameter_with_the_largest_z_and_the_exponents_sign(p, grows):
    """F_h with z 7.5 against x_h with z 3: F_h is named; speeds 2 and 5 mm/s give ×2.50; an unbounded z of x_h
    would be written 1e6, a finite one as it is; a positive exponent is a loop that grows with the speed."""
    from chainid.gap.timedomain.ratecheck import _finding

    f = _finding(3, "hysteresis", "hysteresis@p", _read(7.5, 3.0, p))
    assert f["parameter"] == "hysteresis.F_h" and f["z"] == 7.5 and f["score"] == 7.5 and f["step"] == 3
    assert f["speed_ratio"] == pytest.approx(2.5, rel=1e-15) and f["exponent"] == p and f["name"] == "hysteresis@p"
    assert f["finding"].startswith(
        "hysteresis (step 3) is not rate-independent as its form says: refitted on the slower and faster halves of "
        "the training blocks (RMS speed 2 vs 5 mm/s, ×2.50), hysteresis.F_h goes from 1.5 to 3; over these and 10 "
        f"random halves its rate exponent is {p:.2f} (z 7.5, the stroke's part apart): the loop ")
    assert ("grows with the speed" in f["finding"]) is grows and ("shrinks" in f["finding"]) is not grows
    assert _finding(1, "hysteresis", "hysteresis", _read(2.0, math.inf, p))["z_all"]["hysteresis.x_h"] == 1e6


def test_the_chain_is_cut_at_the_earliest_step_that_added_a_rate_dependent_loop(monkeypatch):
    """Both loops of the last fit are rate-dependent: the cut is at step 1 (the hysteresis, added first), not at
    step 2 (the Bouc–Wen); a loop the blocks cannot judge is a row with ``judged`` False and no cut; a chain of the
    baseline alone has no checks."""
    from chainid.gap.timedomain import ratecheck

    monkeypatch.setattr(ratecheck, "rate_test", lambda prob, cand, effect: _read(5.0, 1.0, 1.0))
    path = [SimpleNamespace(names=[]), SimpleNamespace(names=["hysteresis"]),
            SimpleNamespace(names=["hysteresis", "bouc_wen"])]
    step, finding, rows = rate_cut(None, path)
    assert step == 1 and finding["effect"] == "hysteresis" and [r["step"] for r in rows] == [1, 2]
    assert rows[0]["speed_ratio"] == pytest.approx(2.5) and rows[0]["z"]["hysteresis.F_h"] == 5.0
    monkeypatch.setattr(ratecheck, "rate_test", lambda prob, cand, effect: None)
    step, finding, rows = rate_cut(None, path)
    assert (step, finding) == (None, None) and [r["judged"] for r in rows] == [False, False]
    assert "dependent" not in rows[0]
    assert rate_cut(None, path[:1]) == (None, None, [])
