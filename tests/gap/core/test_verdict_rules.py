"""Small rules of the verdict (chainid.gap.core.verdict) at their edges: the share of the gap above the kinematic
floor, the chain cut by a route's rate check, the fallback best effect, the over-fitting and joint-support texts,
covariate terms' names and the kinematic-floor text's thresholds."""
from __future__ import annotations

import math
from types import SimpleNamespace

import pytest

from chainid.gap.core import verdict as vd
from chainid.gap.harmonic.problem import Candidate

STAT_OK = {"stationary": True, "trend_change_N": 0.0, "finding": ""}


def _path(*h: float) -> list[SimpleNamespace]:
    names = ["baseline", "a", "b", "c", "d"]
    return [SimpleNamespace(nrmse_holdout=v, names=names[1:i + 1] or ["baseline"]) for i, v in enumerate(h)]


@pytest.mark.parametrize("s, want", [(0.5, True), (0.4999, False), (0.9, True), (math.nan, False),
                                     (math.inf, False), (None, False)])
def test_floor_shrunk_needs_a_finite_share_of_at_least_one_half(s, want):
    """shrinkage_floor >= MIN_SHRINK = 0.5 (inclusive), finite, present."""
    assert vd.floor_shrunk(SimpleNamespace(shrinkage_floor=s)) is want


def test_floor_shrunk_is_false_without_the_attribute():
    assert vd.floor_shrunk(SimpleNamespace(shrinkage=0.9)) is False


def test_decide_names_a_chain_that_closes_half_the_gap_above_the_floor():
    """Shrinkage 0.2 < 0.5, but 60 % of the gap above the kinematic floor closed: named; 40 %: unexplained."""
    final = SimpleNamespace(names=["friction"], shrinkage=0.2, shrinkage_floor=0.6, at_bound=())
    assert vd.decide(False, final, dict(STAT_OK), 1.0, [None, final], {"stop": "S"}, [], []) == "friction"
    final.shrinkage_floor = 0.4
    assert vd.decide(False, final, dict(STAT_OK), 1.0, [None, final], {"stop": "S"}, [], []) == "unexplained"


def test_a_drift_is_not_material_against_a_zero_systematic_residual_when_it_is_zero():
    """Excess 0 is floored at 1e-300: a zero trend change (0 < 0.25e-300) is not material, the chain stays named."""
    final = SimpleNamespace(names=["friction"], shrinkage=0.8, at_bound=())
    stat = {"stationary": False, "trend_change_N": 0.0, "finding": "drift"}
    warn: list[str] = []
    assert vd.decide(False, final, stat, 0.0, [None, final], {"stop": "S"}, [], warn) == "friction"
    assert warn == ["drift; the static effects friction absorb part of it, but what is left drifts with time"]


def test_kept_path_trims_the_steps_before_a_rate_cut_to_their_own_minimum():
    """Held-out 0.5, 0.3, 0.35, 0.1 with the rate cut at step 3: of 0.5, 0.3, 0.35 the minimum is step 1 (kept 2,
    first over-fitted 2); cut at step 2: 0.5, 0.3 whole; no cut: the whole chain to 0.1."""
    p = _path(0.5, 0.3, 0.35, 0.1)
    ok, bad = vd.kept_path(p, {"rate_dependence": {"step": 3}})
    assert (len(ok), bad) == (2, 2)
    ok, bad = vd.kept_path(p, {"rate_dependence": {"step": 2}})
    assert (len(ok), bad) == (2, None)
    ok, bad = vd.kept_path(p, {"rate_dependence": None})
    assert (len(ok), bad) == (4, None)


def test_fallback_best_skips_the_effect_cut_as_rate_dependent():
    a, b = SimpleNamespace(names=["sensor_delay"]), SimpleNamespace(names=["friction"])
    assert vd.fallback_best([a, b], {"rate_dependence": {"name": "sensor_delay"}}) is b
    assert vd.fallback_best([a, b], {}) is a
    assert vd.fallback_best([a], {"rate_dependence": {"name": "sensor_delay"}}) is None


def test_overfit_warning_states_the_relative_rise_in_percent():
    """0.25 → 0.3 is 100·(0.3/0.25 − 1) = +20.0 %."""
    p = _path(0.4, 0.25, 0.3)
    assert vd.overfit_warning(p, 2) == ("over-fitted: step 2 (b) raised the held-out NRMSE from 0.25 to 0.3 (+20.0 %); "
                                        "the verdict and what is left are those of the chain before it")


def test_joint_notes_only_for_strict_rises_before_the_last_step():
    """An equal held-out error is no rise; the last step is the chain's end, never noted."""
    assert vd.joint_notes(_path(0.5, 0.5, 0.4)) == []
    (note,) = vd.joint_notes(_path(0.5, 0.6, 0.7))
    assert note.startswith("step 1 (a) alone raised the held-out NRMSE from 0.5 to 0.6; with the step(s) after it "
                           "the chain reaches 0.7")


def test_verdict_name_maps_covariate_terms_to_their_effects_once():
    names = ["friction", "damping.c_1@T", "spring.k@p_bar", "mass.m@a", "hysteresis.F_h@p_bar", "friction.F_c@I_A",
             "damping.c_2@T"]
    assert vd.verdict_name(names) == "friction+damping_law+stiffness_level+fixture_mass+hysteresis"


def test_none_text_by_reading():
    assert vd.none_text({"none_reading": "damping_extrapolation"}) == vd.NONE_TEXT["damping_extrapolation"]
    assert vd.none_text({"none_reading": None}) == vd.NONE_TEXT["noise"]
    assert vd.none_text({"none_reading": "other"}) == vd.NONE_TEXT["noise"]


def _res(kf: float, nf: float, db: float | None) -> dict:
    return {"kinematic_floor_N": kf, "noise_floor_N": nf, "db_over_kinematic_floor": db}


def test_kinematic_floor_text_thresholds():
    """Floor 1.01 dB over the noise (kf = nf·10^(1.01/20)): stated; a residual exactly at the floor (0 dB) reads
    +0.0 dB over it, not below; a zero noise floor or a missing number: nothing."""
    kf = 10 ** (1.01 / 20)
    assert vd.kinematic_floor_text(_res(kf, 1.0, 3.0)) == " (+3.0 dB over the kinematic floor 1.12 N)"
    assert vd.kinematic_floor_text(_res(10 ** (0.99 / 20), 1.0, 3.0)) == ""
    assert vd.kinematic_floor_text(_res(10.0, 1.0, 0.0)) == " (+0.0 dB over the kinematic floor 10 N)"
    assert vd.kinematic_floor_text(_res(10.0, 0.0, 3.0)) == ""
    assert vd.kinematic_floor_text(_res(10.0, 1.0, None)) == ""


def _cand(name, loto, hold, params=None):
    return Candidate(name, params or {}, len(params or {}), nrmse_loto=loto, nrmse_holdout=hold)


def test_contract_marks_the_rate_cut_steps_and_keeps_the_chain_before_them():
    """Rate cut at step 2 of baseline (0.8), friction (0.3), slack (0.1): kept chain = 2 steps ending at friction,
    left 0.3 → fit 100·(1 − 0.3) = 70 %; steps 2… marked rate_cut, step 2 rate_dependent; not over-fitted; the
    rejected list is cut to its first 6."""
    base, f = _cand("baseline", 0.9, 0.8), _cand("friction", 0.4, 0.3, {"friction.F_c": 12.0})
    fs = _cand("friction+slack", 0.2, 0.1, {"friction.F_c": 11.0, "slack.s": 0.05})
    rate = {"step": 2, "name": "slack"}
    fwd = {"path": [base, f, fs], "singles": [f], "stop": "S", "dropped": [], "rate_dependence": rate,
           "rejected": [{"effect": str(i)} for i in range(8)]}
    out = vd.contract(SimpleNamespace(law="viscous", law_reason="given"), SimpleNamespace(name="chain"), base, {},
                      fwd, "friction", "", {"db_over_noise": 1.0}, [], [], [], [], [], [])
    assert out["trusted_steps"] == 2 and out["overfitted"] is False and out["_best"] is f
    assert out["left_nrmse_holdout"] == 0.3 and out["fit_holdout_pct"] == pytest.approx(70.0, abs=1e-12)
    assert [st.get("rate_cut", False) for st in out["steps"]] == [False, False, True]
    assert [st.get("rate_dependent", False) for st in out["steps"]] == [False, False, True]
    assert [r["effect"] for r in out["rejected"]] == ["0", "1", "2", "3", "4", "5"]
    assert out["none_reading"] is None and out["rate_dependence"] is rate
