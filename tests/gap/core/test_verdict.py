"""The verdict and the JSON contract (chainid.gap.core.verdict): unexplained drift, parameters at their bounds,
the ranking and the best chain."""
from __future__ import annotations

from types import SimpleNamespace

from chainid.gap.core import verdict as vd


STAT_OK = {"stationary": True, "trend_change_N": 0.0, "finding": ""}


# ---------------------------------------------------------------- verdict.decide
def _decide(consistent, final, best):
    warn: list[str] = []
    v = vd.decide(consistent, final, dict(STAT_OK), 1.0, [], {"stop": "STOP"}, [], warn, best=best)
    return v, warn


def test_no_effect_warning_only_when_the_verdict_is_unexplained():
    """'no effect passed the step rule' is said only for an `unexplained` verdict with no final step and a best
    candidate (documented in decide).  Bug caught: `and` → `or` (the warning on a `none` verdict)."""
    best = SimpleNamespace(names=("friction",), shrinkage=0.9)
    assert _decide(True, None, best) == ("none", [])  # the baseline is at the noise: nothing to warn about
    v, warn = _decide(False, None, best)
    assert v == "unexplained" and warn == ["no effect passed the step rule (STOP)"]
    assert _decide(False, None, None) == ("unexplained", [])  # no candidate at all: no step rule was tried
    final = SimpleNamespace(names=("friction", "slack"), shrinkage=vd.MIN_SHRINK)
    assert _decide(False, final, best) == ("friction+slack", [])
    short = SimpleNamespace(names=("friction",), shrinkage=0.99 * vd.MIN_SHRINK)
    assert _decide(False, short, best) == ("unexplained", [])


def test_contract_ranking_best_and_chain_text_by_hand():
    """The JSON contract: ranking = the single effects and the chain's multi-effect steps, by LOTO NRMSE; best
    = the chain's last step (else the best single); left NRMSE = the last step's (else the baseline's);
    chain_text = the step texts joined by arrows and the dB left; private keys carry the objects."""
    from chainid.gap.harmonic.problem import Candidate
    from chainid.gap.core.verdict import contract

    def cand(name, loto, hold, params=None):
        c = Candidate(name, params or {}, len(params or {}), nrmse_loto=loto, nrmse_holdout=hold)
        return c

    base = cand("baseline", 0.9, 0.8)
    f = cand("friction", 0.4, 0.3, {"friction.F_c": 12.0})
    s = cand("slack", 0.5, 0.6, {"slack.s": 0.1})
    fs = cand("friction+slack", 0.2, 0.1, {"friction.F_c": 11.0, "slack.s": 0.05})
    prob = SimpleNamespace(law="viscous", law_reason="given")
    model = SimpleNamespace(name="chain")
    fwd = {"path": [base, f, fs], "singles": [s, f], "stop": "S", "dropped": []}
    out = contract(prob, model, base, {"noise_sigma_N": 2.0}, fwd, "friction+slack", "", {"db_over_noise": 1.26},
                   [], [], [], [], ["h"], [])
    assert [r["effect"] for r in out["ranking"]] == ["friction+slack", "friction", "slack"]
    assert out["best"]["effect"] == "friction+slack" and out["left_nrmse_holdout"] == 0.1
    assert [st["effect"] for st in out["steps"]] == ["baseline", "friction", "slack"]
    # each step names its newest effect with that effect's parameters at the step's fit
    assert out["chain_text"] == ("baseline [held-out NRMSE 0.8] → friction F_c = 12 N [held-out NRMSE 0.3] → "
                                 "slack s = 0.05 mm [held-out NRMSE 0.1] → residual 1.3 dB over noise")
    assert out["baseline"]["model"] == "chain" and out["baseline"]["damping_law"] == "viscous"
    assert out["baseline"]["noise_sigma_N"] == 2.0 and out["mechanism"] == "friction+displacement offset"
    assert out["_best"] is fs and out["_path"] == [base, f, fs] and out["_problem"] is prob
    none = contract(prob, model, base, {}, {"path": [base], "singles": [s, f], "stop": "S", "dropped": []}, "none",
                    "", {"db_over_noise": 0.0}, [], [], [], [], ["h"], [])
    assert none["best"]["effect"] == "friction" and none["left_nrmse_holdout"] == 0.8
    assert none["steps"][0]["effect"] == "baseline" and len(none["steps"]) == 1
    empty = contract(prob, model, base, {}, {"path": [base], "singles": [], "stop": "S", "dropped": []}, "none",
                     "", {"db_over_noise": 0.0}, [], [], [], [], ["h"], [])
    assert empty["best"] is None and empty["_best"] is None


def _nonstat(change):
    return {"stationary": False, "trend_change_N": change, "finding": "non-stationary: X"}


def test_verdict_a_drift_of_a_quarter_of_the_residual_is_unexplained():
    """`unexplained` when what is left drifts by at least NONSTAT_FRACTION = 1/4 of the baseline's systematic
    residual (8 N here: 2 N is the limit); a smaller drift keeps the named chain with a warning; the finding goes
    first in `where`."""
    from chainid.gap.core import verdict as vd

    final = SimpleNamespace(names=("friction",), shrinkage=0.8, at_bound=())
    for change, want in ((2.0, "unexplained"), (1.99, "friction")):
        where, warn = [{"finding": "old"}], []
        v = vd.decide(False, final, _nonstat(change), 8.0, [None, final], {"stop": "S"}, where, warn)
        assert v == want
        assert where[0] == {"finding": "non-stationary: X", "kind": "nonstationary", "trend_change_N": change,
                            "score": change} and where[1] == {"finding": "old"}
        msg = ("non-stationary: X; the static effects friction absorb part of it, but what is left drifts with "
               "time")
        if want == "unexplained":
            msg += " (trend change 2 N over the window vs systematic residual 8 N: no confident name)"
        assert warn == [msg]
    # the rule is relative: a small device's 0.08 N residual with a 0.02 N drift is the same case scaled by 1/100
    for change, want in ((0.02, "unexplained"), (0.0199, "friction")):
        assert vd.decide(False, final, _nonstat(change), 0.08, [None, final], {"stop": "S"}, [], []) == want
    # no chain: the drift is all there is
    warn = []
    assert vd.decide(False, None, _nonstat(0.1), 8.0, [None], {"stop": "S"}, [], warn) == "unexplained"
    assert warn == ["non-stationary: X; no static effect can explain it"]
    # the baseline at the noise floor: `none`, no drift warning (the finding is still listed)
    warn, where = [], []
    assert vd.decide(True, final, _nonstat(5.0), 8.0, [None, final], {"stop": "S"}, where, warn) == "none"
    assert warn == [] and where[0]["kind"] == "nonstationary"


def test_verdict_warns_of_each_step_with_a_parameter_at_its_bound():
    from chainid.gap.core import verdict as vd

    s1 = SimpleNamespace(name="friction", at_bound=("friction.x_s",))
    s2 = SimpleNamespace(name="slack", at_bound=())
    s3 = SimpleNamespace(name="backlash", at_bound=("backlash.b", "backlash.k"), names=("friction", "slack",
                         "backlash"), shrinkage=0.9)
    warn = []
    stat = {"stationary": True, "trend_change_N": 0.0, "finding": ""}
    assert vd.decide(False, s3, stat, 1.0, [s1, s1, s2, s3], {"stop": "S"}, [], warn) == "friction+slack+backlash"
    tail = ("at the bound of their physical range; the effect's form may not match the data there (read the value "
            "as a limit, not an estimate)")
    # path[0] is the baseline: not warned about even if it had a bound
    assert warn == [f"friction: parameter(s) friction.x_s {tail}", f"backlash: parameter(s) backlash.b, backlash.k {tail}"]


def test_a_chain_cut_as_over_fitted_is_not_said_to_have_had_no_step():
    """A step that passed the step rule and was cut because it raised the held-out error is not "no effect passed
    the step rule": that warning is for a chain with no step at all; the cut has its own over-fitting warning."""
    base = SimpleNamespace(names=(), nrmse_holdout=0.24)
    cut = SimpleNamespace(names=("hysteresis",), nrmse_holdout=0.32, shrinkage=-0.33, at_bound=())
    warn: list[str] = []
    v = vd.decide(False, None, dict(STAT_OK), 1.0, [base, cut], {"stop": "STOP"}, [], warn, best=cut)
    assert v == "unexplained" and warn == []


def test_the_summary_names_the_cut_step_and_a_kept_rising_step_reads_kept():
    from chainid.gap.core.summary import summary
    from chainid.gap.harmonic.problem import Candidate
    from chainid.gap.core.verdict import contract

    def cand(name, loto, hold, params=None):
        return Candidate(name, params or {}, len(params or {}), nrmse_loto=loto, nrmse_holdout=hold)

    prob, model = SimpleNamespace(law="viscous", law_reason="given"), SimpleNamespace(name="linear")
    base = cand("baseline", 0.63, 0.24)
    h = cand("hysteresis", 0.16, 0.32, {"hysteresis.F_h": 6.5})
    (base.shrinkage, base.db_holdout), (h.shrinkage, h.db_holdout) = (0.0, 26.8), (1 - 0.32 / 0.24, 29.2)
    noise = {"noise_sigma_N": 0.1, "db_over_noise": 26.8, "excess_rms_N": 2.2, "chi2_ratio": 480.0}
    res = contract(prob, model, base, noise, {"path": [base, h],
                   "singles": [h], "stop": "S", "dropped": []}, "unexplained", "", {"db_over_noise": 26.8}, [], [],
                   [], [], ["h"], [])
    text = summary(res)
    assert ("VERDICT: unexplained — hysteresis passed the step rule on the training data but did not hold on the "
            "held-out data (held-out NRMSE 0.24 → 0.32): over-fitted, not kept") in text
    h.nrmse_holdout = float("nan")  # a held-out score that could not be computed: "n/a", no crash
    res = contract(prob, model, base, noise, {"path": [base, h], "singles": [h], "stop": "S", "dropped": []},
                   "unexplained", "", {"db_over_noise": 26.8}, [], [], [], [], ["h"], [])
    assert "(held-out NRMSE 0.24 → n/a): over-fitted, not kept" in summary(res)
    h.nrmse_holdout = 0.32
    # a rising step the next one recovers is kept, and its text says so (not "not in the verdict")
    d = cand("damping_law", 0.14, 0.09, {"damping_law.b_w": -3.0})
    res = contract(prob, model, base, {"noise_sigma_N": 0.1}, {"path": [base, h, d], "singles": [h, d], "stop": "S",
                   "dropped": []}, "hysteresis+damping_law", "", {"db_over_noise": 18.6}, [], [], [], [], ["h"], [])
    assert "hysteresis F_h = 6.5 N [held-out NRMSE 0.32] [raised the held-out error alone; kept: the step(s) after " \
           "it take it lower] → damping_law" in res["chain_text"]
    assert "not in the verdict" not in res["chain_text"]


def test_a_resampled_diagnosis_prints_its_intervals_and_shares_not_the_jack_knife():
    """With resamples the terminal shows each parameter's 90 % resampled interval and how often each step is
    chosen, in the waterfall and in the VERDICT line; without, ± the jack-knife standard deviation (labelled)."""
    from chainid.gap.core.resample import attach
    from chainid.gap.core.summary import summary
    from chainid.gap.harmonic.problem import Candidate
    from chainid.gap.core.verdict import contract

    base = Candidate("baseline", {}, 0, nrmse_loto=0.9, nrmse_holdout=0.8)
    f = Candidate("friction", {"friction.F_c": 12.0}, 1, nrmse_loto=0.2, nrmse_holdout=0.1)
    f.param_sd = {"friction.F_c": 0.01}
    (base.shrinkage, base.db_holdout), (f.shrinkage, f.db_holdout) = (0.0, 20.0), (0.875, 1.0)
    noise = {"noise_sigma_N": 1.0, "db_over_noise": 20.0, "excess_rms_N": 10.0, "chi2_ratio": 100.0}

    def result():
        return contract(SimpleNamespace(law="viscous", law_reason="given"), SimpleNamespace(name="chain"), base,
                        noise, {"path": [base, f], "singles": [f], "stop": "S", "dropped": []}, "friction", "",
                        {"db_over_noise": 1.0}, [], [], [], [], ["h"], [])

    plain = summary(result())
    assert "parameters ± jack-knife standard deviation" in plain and "friction.F_c=12±0.01" in plain
    res = result()
    attach(res, {"resamples": 200, "steps": [{"effect": "baseline", "params_ci90": {}},
                                             {"effect": "friction", "params_ci90": {"friction.F_c": [9.5, 14.25]},
                                              "stability": 0.97}]})
    text = summary(res)
    assert "friction.F_c=12 [9.5, 14.25]; chosen in 97 % of resamples" in text
    assert "[90 % interval over the resamples]" in text and "±0.01" not in text
    assert "friction F_c = 12 [9.5, 14.25] N" in res["chain_text"]
    # a step cut as over-fitted is not resampled: its ± is the jack-knife's, and the line says so
    s = Candidate("slack", {"friction.F_c": 12.0, "slack.s": 0.1}, 2, nrmse_loto=0.15, nrmse_holdout=0.2)
    s.param_sd, s.shrinkage, s.db_holdout = {"slack.s": 0.02}, 0.75, 3.0
    res = contract(SimpleNamespace(law="viscous", law_reason="given"), SimpleNamespace(name="chain"), base, noise,
                   {"path": [base, f, s], "singles": [f, s], "stop": "S", "dropped": []}, "friction", "",
                   {"db_over_noise": 1.0}, [], [], [], [], ["h"], [])
    attach(res, {"resamples": 200, "steps": [{"effect": "baseline", "params_ci90": {}},
                                             {"effect": "friction", "params_ci90": {"friction.F_c": [9.5, 14.25]},
                                              "stability": 0.97}]})
    line = next(ln for ln in summary(res).splitlines() if ln.startswith("  2     slack"))
    assert "slack.s=0.1±0.02" in line and "(± jack-knife: not resampled)" in line
