"""Issue 20 §5: behaviours of the gap package (stationarity, damping law choice, verdict, interpretation, summary,
transfer and parameter keys) that the mutation runs found unpinned (seed 22 and own seeds).

Each test checks a documented behaviour against a hand computation or the documented contract; the expensive
parts (simulation, diagnosis) are replaced by recorders where the test is about what the benchmark hands them.
Units: mm, N, s.
"""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest



# ---------------------------------------------------------------- stationarity: the pooling rule by hand

def _cycles(slope: float, n: int = 10) -> dict[str, np.ndarray]:
    t = np.arange(n, dtype=float)  # one cycle a second
    return {"t": t, "mean": slope * t, "a": np.zeros(n), "b": np.zeros(n), "xm": np.full(n, 2.0),
            "xa": np.full(n, 0.1)}


def _tests(slopes):
    return [SimpleNamespace(test=f"T{i}", sigma=1.0, cycles=_cycles(s)) for i, s in enumerate(slopes)]


def test_stationarity_a_trend_in_a_quarter_of_the_tests_by_hand():
    """Noise-free lines: the scatter is 0, so the standard error is the floor σ·sqrt(1/n) = 1 N (no cycle counts
    given: n = 1) over sqrt(Σ(t − t̄)²) = sqrt(82.5) for t = 0 … 9 s; slope 5 N/s: z = 5·sqrt(82.5) = 45.4,
    change 5·9 = 45 N.  One trending test in 4 is a quarter (non-stationary), one in 5 is not."""
    from chainid.gap.core import stationarity

    z = 5.0 * math.sqrt(82.5)
    res = stationarity.check(_tests([5.0, 0.0, 0.0, 0.0]))
    assert res["stationary"] is False
    assert res["z"] == pytest.approx(z, rel=1e-9)
    q = res["by_quantity"]["mean"]
    assert q["n_tests"] == 1 and q["max_z"] == pytest.approx(z, rel=1e-9)
    assert q["change_N"] == pytest.approx(math.sqrt(45.0 ** 2 / 4), rel=1e-9)  # RMS over the 4 tests: 22.5 N
    assert res["trend_change_N"] == pytest.approx(22.5, rel=1e-9)  # a and b flat: only the mean counts
    assert res["by_quantity"]["a"] == {"max_z": 0.0, "change_N": 0.0, "n_tests": 0}
    assert res["finding"].startswith(
        "non-stationary: the mean force trends over the cycles in 1 of 4 tests (change over the window 22.5 N "
        "RMS over tests, up to 45.4 standard errors)")
    assert [r["n_cycles"] for r in res["tests"]] == [10] * 4
    res5 = stationarity.check(_tests([5.0, 0.0, 0.0, 0.0, 0.0]))
    assert res5["stationary"] is True and res5["finding"].startswith("the force is stationary")
    assert res5["by_quantity"]["mean"]["change_N"] == pytest.approx(45.0 / math.sqrt(5), rel=1e-9)
    # two in 5 (ceil(0.25 · 5) = 2) is enough again
    assert stationarity.check(_tests([5.0, -5.0, 0.0, 0.0, 0.0]))["stationary"] is False


@pytest.mark.parametrize("z,stationary", [(3.9, True), (4.1, False)])
def test_stationarity_threshold_is_four_standard_errors(z, stationary):
    from chainid.gap.core import stationarity

    res = stationarity.check(_tests([z / math.sqrt(82.5)]))
    assert res["z"] == pytest.approx(z, rel=1e-9)
    assert res["stationary"] is stationary
    assert res["trend_change_N"] == pytest.approx(0.0 if stationary else 9 * z / math.sqrt(82.5), rel=1e-9)


def test_stationarity_floor_of_a_harmonic_amplitude_uses_the_cycle_counts():
    """A harmonic amplitude's floor is σ·sqrt(2/n) with n the mean samples per cycle: σ = 2 N, n = 50 →
    0.4 N; a slope 0.1 N/s of b over t = 0 … 9: z = 0.1·sqrt(82.5)/0.4."""
    from chainid.gap.core import stationarity

    cy = _cycles(0.0) | {"b": 0.1 * np.arange(10.0), "n": np.full(10, 50.0)}
    res = stationarity.check([SimpleNamespace(test="T", sigma=2.0, cycles=cy)])
    assert res["tests"][0]["b"]["z"] == pytest.approx(0.1 * math.sqrt(82.5) / 0.4, rel=1e-9)
    assert res["tests"][0]["b"]["change_N"] == pytest.approx(0.9, rel=1e-9)


def test_trend_uses_the_covariate_from_six_cycles_on():
    """y = 3·t + 10·cov exactly: with ≥ 6 cycles the covariate is fitted and the slope is 3 N/s exactly; with 5
    it is not (too few cycles for three coefficients and a scatter), and the slope is the plain line's."""
    from chainid.gap.core import stationarity

    cov = np.array([0.3, -0.1, 0.7, 0.2, -0.4, 0.5])
    for n in (5, 6):
        t, c = np.arange(n, dtype=float), cov[:n]
        y = 3.0 * t + 10.0 * c
        sl, se, chg = stationarity.trend(t, y, c)
        plain = float(np.polyfit(t, y, 1)[0])
        assert sl == pytest.approx(3.0 if n == 6 else plain, rel=1e-9, abs=1e-12)
        assert chg == pytest.approx(abs(sl) * (n - 1), rel=1e-12)
        if n == 5:
            assert plain != pytest.approx(3.0, rel=1e-3)  # the two readings differ
    assert stationarity.trend(np.arange(2.0), np.arange(2.0)) == (0.0, math.inf, 0.0)  # fewer than 3 cycles
    assert stationarity.trend(np.zeros(4), np.arange(4.0)) == (0.0, math.inf, 0.0)  # no time span
    none = stationarity.check(_tests([]) + [SimpleNamespace(test="S", sigma=1.0, cycles=_cycles(1.0, n=3))])
    assert none["stationary"] is None
    assert none["finding"] == "stationarity not checked: no test has >= 4 whole steady cycles"


# ---------------------------------------------------------------- damping law choice

def test_law_choice_leave_one_out_errors_and_ties_by_hand():
    """c_e = 0.5 + noise-free scatter d_i: the viscous law's LOO prediction of test i is the mean of the others,
    so its error is n/(n − 1)·(c_i − c̄) and its LOO RMS n/(n − 1)·std(c).  A Coulomb-exact set
    c = 4·F_f/(π·ω·A) is fitted with zero error by coulomb and by viscous+coulomb: the tie goes to the law with
    fewer coefficients."""
    from chainid.gap.harmonic.law_choice import choose

    w = np.array([1.0, 2.0, 4.0, 1.0, 2.0, 4.0, 3.0])
    A = np.array([0.1, 0.1, 0.1, 0.3, 0.3, 0.3, 0.2])
    ke = np.full(7, 5000.0)
    c = 0.5 + np.array([0.01, -0.02, 0.03, 0.0, -0.01, 0.02, -0.03])
    best, errs = choose(w, A, ke, c, ["viscous"])
    assert best == "viscous" and errs["viscous"] == pytest.approx(7 / 6 * np.std(c), rel=1e-9)
    cc = 4 * 20.0 / (np.pi * w * A)
    best, errs = choose(w, A, ke, cc, ["viscous+coulomb", "viscous", "coulomb", "hysteretic"])
    assert best == "coulomb" and errs["coulomb"] < 1e-9 and errs["viscous+coulomb"] < 1e-9
    assert errs["viscous"] > 10 and errs["hysteretic"] > 1  # c spans 21 … 255 N·s/mm
    ch = 0.02 * ke / w  # structural, eta = 0.02
    assert choose(w, A, ke, ch, ["viscous", "coulomb", "hysteretic", "viscous+hysteretic"])[0] == "hysteretic"
    with pytest.raises(ValueError, match="no damping law has fewer coefficients than the training tests"):
        choose(w, A, ke, c, [])


# ---------------------------------------------------------------- verdict: drift and bounds (module docstring)

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


# ---------------------------------------------------------------- interpret: the engineer's words

def test_step_texts_by_hand():
    from chainid.gap.core.interpret import step_text

    assert step_text({"effect": "baseline", "params": {}, "nrmse_holdout": 0.12345}) == \
        "baseline [held-out NRMSE 0.123]"
    assert step_text({"effect": "baseline", "params": {}, "nrmse_holdout": None}) == "baseline"
    # scale 0.79: −21 %; its sd 0.0123 → 2 significant digits
    assert step_text({"effect": "stiffness_level", "params": {"stiffness_level.scale": 0.79},
                      "params_sd": {"stiffness_level.scale": 0.0123}}) == "stiffness level -21 % (EA × 0.79 ± 0.012)"
    assert step_text({"effect": "contact_law", "params": {"contact_law.scale": 1.5, "contact_law.beta": 0.5}}) == \
        "contact law: Hertz compliance × 1.5, exponent 0.5 (Hertz 0.667)"
    # units per parameter; a zero, infinite or missing sd is not shown; other effects' parameters left out
    txt = step_text({"effect": "friction", "params": {"friction.F_c": 150.04, "friction.mu": 0.012,
                                                       "slack.s": 0.3},
                     "params_sd": {"friction.F_c": 0.0, "friction.mu": float("inf")}, "nrmse_holdout": 0.05})
    assert txt == "friction F_c = 150 N, mu = 0.012 [held-out NRMSE 0.05]"
    assert step_text({"effect": "sensor_delay", "params": {"sensor_delay.tau": 0.0021},
                      "params_sd": {"sensor_delay.tau": 0.0001}}) == "sensor_delay tau = 0.0021 ± 0.0001 s"
    assert step_text({"effect": "slack", "params": {"slack.s": None}}) == "slack s = ? mm"


def test_mechanism_joins_families_once_and_separating_test_of_stiffness_pairs():
    from chainid.gap.core.interpret import mechanism, separating_test

    assert mechanism("stiffness_level+machine_compliance+sensor_delay", "") == "stiffness+instrumentation"
    assert mechanism("friction+hysteresis", "Dahl friction (x_h << A)") == "friction"
    assert mechanism("damping_law+backlash", "") == "damping form+play"
    assert separating_test("slack", "contact_law").startswith("tests over a wider mean-load range x0")
    assert separating_test("damping_law", "backlash").startswith("tests over a wider amplitude range at fixed ω")
    assert separating_test("friction", "backlash").startswith("tests over a wider amplitude range at fixed ω")


def test_interpretation_dahl_and_stiffness_level_by_hand():
    """Dahl friction when x_h < A_min/2; a stiffness level s on a model with a linear coefficient c_lin [mm/N] is
    a series compliance c_lin·(1/s − 1)."""
    from chainid.gap.core.interpret import interpretation

    prob = SimpleNamespace(data=[SimpleNamespace(A=0.3), SimpleNamespace(A=0.1)],
                           model=SimpleNamespace(coefficients=[2e-5, 1.0]))
    base = SimpleNamespace(names=(), params={})
    fin = SimpleNamespace(names=("hysteresis",), params={"hysteresis.x_h": 0.0499})
    assert interpretation([base, fin], prob, "hysteresis") == (
        "Dahl-type hysteresis with transition travel x_h = 0.0499 mm << A (>= 0.1 mm): rate-independent "
        "frictional sliding with smooth pre-sliding (Dahl friction)")
    assert interpretation([base, SimpleNamespace(names=("hysteresis",), params={"hysteresis.x_h": 0.05})],
                          prob, "hysteresis") == ""  # x_h = A_min/2 is not << A
    assert interpretation([base], prob, "none") == ""
    lvl = SimpleNamespace(names=("stiffness_level",), params={"stiffness_level.scale": 0.8})
    # 2e-5 · (1/0.8 − 1) = +5e-6 mm/N; 20 % softer
    assert interpretation([base, lvl], prob, "stiffness_level") == (
        "the chain is 20 % softer in its linear (bar) term than the derivation; equivalently a series compliance "
        "of +5e-06 mm/N (test machine, fixtures, a larger contact flattening)")
    up = SimpleNamespace(names=("stiffness_level",), params={"stiffness_level.scale": 1.25})
    assert "25 % stiffer" in interpretation([base, up], prob, "x") and "-4e-06 mm/N" in interpretation(
        [base, up], prob, "x")
    lin = SimpleNamespace(data=prob.data, model=SimpleNamespace())  # no coefficients: a linear spring
    assert interpretation([base, lvl], lin, "stiffness_level") == ""


def test_step_dict_is_the_json_contract_of_a_step():
    from chainid.gap.core.interpret import step_dict

    c = SimpleNamespace(names=("friction", "slack"), params={"spring.k": 1.0, "friction.F_c": 3.0, "slack.s": 0.1},
                        param_sd={"friction.F_c": float("nan"), "slack.s": 0.01, "spring.k": 0.5}, law="viscous",
                        nrmse_loto=0.1, nrmse_holdout=float("inf"), shrinkage=0.7, db_holdout=3.0,
                        step_test={"z": 4.5, "relative_gain": 0.3}, at_bound=("slack.s",))
    assert step_dict(c, 2) == {
        "effect": "slack", "effects": ("friction", "slack"), "params": {"friction.F_c": 3.0, "slack.s": 0.1},
        "params_sd": {"friction.F_c": None, "slack.s": 0.01}, "damping_law": "viscous", "nrmse_loto": 0.1,
        "nrmse_holdout": None, "shrinkage": 0.7, "db_over_noise": 3.0, "z_loto": 4.5, "relative_gain_loto": 0.3,
        "at_bound": ["slack.s"]}
    c.step_test = {}
    d = step_dict(c, 0)
    assert d["effect"] == "baseline" and d["z_loto"] is None and d["relative_gain_loto"] is None


# ---------------------------------------------------------------- summary: the terminal text and the JSON contract

def _summary_result(**kw):
    step0 = {"effect": "baseline", "nrmse_loto": 0.2, "nrmse_holdout": 0.25, "shrinkage": None,
             "db_over_noise": 12.34, "params": {}, "params_sd": {}}
    step1 = {"effect": "friction", "nrmse_loto": 0.05, "nrmse_holdout": 0.04, "shrinkage": 0.84,
             "db_over_noise": 1.0, "params": {"friction.F_c": 150.04, "spring.k": 3.0, "law.a": 1.0,
                                              "friction.x_s": None, "friction.mu": 0.0123},
             "params_sd": {"friction.F_c": 3.21}, "at_bound": ["friction.mu"]}
    res = {"baseline": {"model": "chain", "damping_law": "polynomial", "nrmse_train": 0.1, "nrmse_holdout": 0.25,
                        "db_over_noise": 12.34, "excess_rms_N": 50.0, "noise_sigma_N": 4.0},
           "where": [{"finding": f"w{i}"} for i in range(10)],
           "ranking": [{"effect": f"e{i}", "nrmse_loto": 0.1 * i, "nrmse_holdout": 0.2, "shrinkage": 0.5,
                        "params": {f"e{i}.p": 1.5}} for i in range(8)],
           "confounded": [{"pair": ["friction", "hysteresis"], "separate_by": "a small test"}],
           "excluded": [{"test": "7", "reason": "not steady"}],
           "steps": [step0, step1], "stop": "no further effect shrinks it", "verdict": "friction",
           "chain_text": "baseline → friction", "residual": {"db_over_noise": 1.04, "stationary": True},
           "interpretation": "dry sliding", "mechanism": "friction", "warnings": ["w!"]}
    return res | kw


def test_summary_text_by_hand():
    from chainid.gap.core.summary import summary

    lines = summary(_summary_result(), n_rank=3).splitlines()
    assert lines[0] == ("Baseline (chain, damping law: polynomial): NRMSE train 0.1, held-out 0.25 (12.3 dB over the "
                        "noise floor; systematic 50 N vs noise σ 4 N)")
    assert lines[1] == "  excluded test 7: not steady"
    assert lines[3:5] == ["WHERE the model misses (largest first):", "  - w0"]
    assert "  - w7" in lines and "  - w8" not in lines  # the first 8 findings
    assert "WHICH effects, in order (each fitted on top of the previous ones; scored leave-one-test-out):" in lines
    i = lines.index("WHICH effects, in order (each fitted on top of the previous ones; scored leave-one-test-out):")
    assert lines[i + 2] == f"  {0:<5} {'baseline':<20} {0.2:>8.4g} {0.25:>9.4g} {0.0:>6.1f}% {12.34:>8.1f}  "
    # spring.*, law.* and None parameters are not shown; sd with 2 digits; a bound marked
    assert lines[i + 3].endswith("  friction.F_c=150±3.2, friction.mu=0.0123 (at bound)")
    assert f"{84.0:>6.1f}%" in lines[i + 3]
    assert lines[i + 4] == "  left: 1.0 dB over the noise floor; stationary"
    assert lines[i + 5] == "  the chain stops: no further effect shrinks it"
    assert sum(".p=1.5" in ln for ln in lines) == 3  # n_rank
    assert "  confounded: friction ~ hysteresis; to separate them: a small test" in lines
    assert "VERDICT: friction — baseline → friction" in lines
    assert "  held-out NRMSE 0.25 → 0.04 (shrinkage 84 %)" in lines
    assert lines[-3:] == ["  meaning: dry sliding", "  mechanism: friction", "WARNING: w!"]


def test_summary_route_residual_and_unexplained_texts():
    from chainid.gap.core.summary import summary, waterfall

    txt = summary(_summary_result(route="time", verdict="unexplained", left_nrmse_holdout=0.123456,
                                  mechanism="unexplained", interpretation="", warnings=[]))
    assert "scored leave-one-block/test-out):" in txt
    assert txt.splitlines()[-1] == ("VERDICT: unexplained — no library effect passed the step rule or shrinks the "
                                    "held-out gap by half; held-out NRMSE left 0.1235.")
    assert "mechanism:" not in txt and "meaning:" not in txt
    assert "scored leave-one-block/test-out" in summary(_summary_result(route="mixed"))
    assert "scored leave-one-test-out" in summary(_summary_result(route="phase"))
    drift = summary(_summary_result(verdict="unexplained", left_nrmse_holdout=0.2,
                                    residual={"db_over_noise": 0.0, "stationary": False, "at_noise_floor": True}))
    assert ("VERDICT: unexplained — what is left changes with time within the tests (no static effect explains "
            "that); held-out NRMSE left 0.2.") in drift
    assert waterfall({"steps": [], "residual": {"db_over_noise": 0.04, "stationary": False,
                                                "at_noise_floor": True}})[1] == \
        "  left: 0.0 dB over the noise floor (at the floor); NOT stationary"
    assert waterfall({"steps": [], "residual": {"db_over_noise": 2.0, "stationary": None}})[1] == \
        "  left: 2.0 dB over the noise floor; stationarity not checked"
    assert len(waterfall({"steps": []})) == 1  # no residual: the header only
    # a named verdict without steps falls back on the best candidate
    best = {"nrmse_holdout": 0.1, "shrinkage": 0.6}
    assert "  held-out NRMSE 0.25 → 0.1 (shrinkage 60 %)" in summary(_summary_result(steps=[], best=best))


def test_to_json_drops_private_keys_and_non_finite_numbers():
    from chainid.gap.core.summary import to_json

    res = {"a": np.float64(1.5), "_problem": object(), "b": [np.int64(3), float("nan"), (float("inf"), 2.0)],
           "c": {"_x": 1, "y": np.float32(0.5)}, 4: "four"}
    assert to_json(res) == {"a": 1.5, "b": [3, None, [None, 2.0]], "c": {"y": 0.5}, 4: "four"}
    assert type(to_json(res)["b"][0]) is int and type(to_json(res)["c"]["y"]) is float  # numpy → Python


# ---------------------------------------------------------------- transfer: pooling and the transfer rule by hand

def _fake_scores(monkeypatch, model_r2):
    """Per (candidate, record) SSEs: baseline b, model m, after the linear refit br/mr, variance v; the model's
    squared residual r2 against the noise floor f2 over n samples of σ = 1 N."""
    from chainid.gap import transfer as tr

    table = {("r1", "base"): (100.0, 64.0), ("r1", "final"): (16.0, 25.0),
             ("r2", "base"): (300.0, 100.0), ("r2", "final"): (20.0, 20.0)}
    var = {"r1": 400.0, "r2": 600.0}

    def score(prob, cand, rec, n_bins, steady_tol):  # noqa: ANN001
        sse, sse_r = table[(rec.test, cand.tag)]
        return {"route": "time" if rec.test == "r1" else "harmonic", "sse": sse, "sse_refit": sse_r,
                "var": var[rec.test], "r2": model_r2[rec.test], "f2": 100.0, "n": 100, "sigma": 1.0}

    monkeypatch.setattr(tr, "_score", score)
    base = SimpleNamespace(names=(), tag="base")
    final = SimpleNamespace(names=("friction", "slack"), tag="final")
    recs = [SimpleNamespace(test="r1"), SimpleNamespace(test="r2")]
    return tr, base, final, recs


def test_transfer_pooled_numbers_and_rule_by_hand(monkeypatch):
    """Per record NRMSE = sqrt(SSE/var); pooled over records sqrt(ΣSSE/Σvar): baseline sqrt(400/1000), model
    sqrt(36/1000) (shrinkage 1 − sqrt(36/400) = 0.7); refit sqrt(164/1000) → sqrt(45/1000) (shrinkage
    1 − sqrt(45/164) = 0.476 < 0.5).  The model leaves r2/f2 = (4000/200)/(200/200) = 20 (13.0 dB, not at the
    floor): it does NOT transfer.  At its noise floor (r2 = f2) the same numbers transfer."""
    tr, base, final, recs = _fake_scores(monkeypatch, {"r1": 1000.0, "r2": 3000.0})
    out = tr.transfer({"_problem": None, "_path": [base, final]}, recs)
    r1 = out["tests"][0]
    assert r1["test"] == "r1" and r1["route"] == "time"
    assert (r1["nrmse_baseline"], r1["nrmse_model"]) == (pytest.approx(0.5), pytest.approx(0.2))
    assert (r1["nrmse_baseline_refit"], r1["nrmse_model_refit"]) == (pytest.approx(0.4), pytest.approx(0.25))
    assert (r1["shrinkage"], r1["shrinkage_refit"]) == (pytest.approx(0.6), pytest.approx(0.375))
    p = out["pooled"]
    assert p["nrmse_baseline"] == pytest.approx(math.sqrt(0.4)) and p["nrmse_model"] == pytest.approx(math.sqrt(0.036))
    assert p["shrinkage"] == pytest.approx(0.7)
    assert p["shrinkage_refit"] == pytest.approx(1 - math.sqrt(45 / 164))
    assert p["model_db_over_noise"] == pytest.approx(10 * math.log10(20.0))
    assert p["model_at_noise_floor"] is False and out["transfers"] is False and out["chain"] == "friction+slack"
    assert out["verdict_text"] == (
        "the chain friction+slack does NOT transfer to the other set (2 harmonic/time record(s)): pooled NRMSE "
        "baseline 0.632 → model 0.19 (shrinkage 70 %); with offset, stiffness and viscous term refitted per record "
        "0.405 → 0.212 (shrinkage 48 %); the model leaves 13.0 dB over the other set's noise; it transfers when the "
        "first reaches 50 % and the second does too or the model is at the noise floor")
    tr, base, final, recs = _fake_scores(monkeypatch, {"r1": 100.0, "r2": 100.0})
    out = tr.transfer({"_problem": None, "_path": [base, final]}, recs)
    assert out["pooled"]["model_at_noise_floor"] is True and out["transfers"] is True
    assert "TRANSFERS" in out["verdict_text"] and "noise (at its noise floor)" in out["verdict_text"]


def test_transfer_without_a_named_effect_and_without_records(monkeypatch):
    tr, base, final, recs = _fake_scores(monkeypatch, {"r1": 100.0, "r2": 100.0})
    out = tr.transfer({"_problem": None, "_path": [base]}, recs)
    assert out["transfers"] is False and out["chain"] == "baseline"
    assert out["pooled"]["shrinkage"] == 0.0  # the model is the baseline
    assert out["verdict_text"] == ("no effect was named on the fitting set; on the other set the baseline leaves "
                                   "NRMSE 0.632 (0.405 after the linear refit)")
    with pytest.raises(ValueError, match="--validate: the other set has no records"):
        tr.transfer({"_problem": None, "_path": [base, final]}, [])


def test_transfer_refit_removes_offset_stiffness_and_viscous_terms():
    """F − F_model = 3 + 2·x − 0.5·ẋ + e with e orthogonal to 1, x, ẋ: the refit leaves e (weights 1)."""
    from chainid.gap import transfer as tr

    n = 64
    psi = 2 * np.pi * np.arange(n) / n
    x, v = np.sin(psi), np.cos(psi)
    e = np.sin(3 * psi)  # orthogonal to 1, sin ψ, cos ψ over whole periods
    Fm = np.linspace(0, 1, n)
    np.testing.assert_allclose(tr._refit(Fm + 3 + 2 * x - 0.5 * v + e, Fm, x, v), e, atol=1e-12)
    np.testing.assert_allclose(tr._refit(Fm + 3 + 2 * x - 0.5 * v + e, Fm, x, v, np.ones(n)), e, atol=1e-12)


# ---------------------------------------------------------------- problem: parameter keys and bounds

def test_problem_keys_spring_bounds_and_no_damping_law_parameters_by_hand():
    """A linear baseline re-fits its spring: k in [0, max(10·k0, 10·F_scale/x_scale)], x_ref within ± 2·x_scale;
    ``damping_law`` has no fitted effect parameters (its law coefficients are the damping fit's), also when its
    name is a string built at run time (read from a command line), not the interned literal."""
    from chainid.gap.harmonic.problem import Problem
    from chainid.model.effects import EFFECT_NAMES, make_effect

    effects = {n: make_effect(n, 100.0, 0.5, 10.0) for n in EFFECT_NAMES}
    fake = SimpleNamespace(_spring_start=lambda: {"spring.k": 30.0, "spring.x_ref": 1.0}, x_scale=0.5,
                           F_scale=100.0, effects=effects)
    law = "".join(["damping", "_law"])
    keys, lo, hi, x0 = Problem._keys(fake, [law, "friction"])
    fr = effects["friction"]
    assert keys == ["spring.k", "spring.x_ref"] + [f"friction.{k}" for k in fr.param_names]
    # 10·k0 = 300 < 10·F/x = 2000
    assert lo[:2] == [0.0, 1.0 - 2 * 0.5] and hi[:2] == [2000.0, 1.0 + 2 * 0.5] and x0[:2] == [30.0, 1.0]
    assert lo[2:] == [b[0] for b in fr.bounds] and hi[2:] == [b[1] for b in fr.bounds]
    assert x0[2:] == list(fr.x0_guess)
    fake.effects, fake.F_scale = effects, 1.0  # 10·k0 = 300 > 10·1/0.5 = 20
    assert Problem._keys(fake, [])[2] == [300.0, 2.0]
    fake._spring_start = lambda: {}  # a chain baseline: no spring parameters
    assert Problem._keys(fake, [law]) == ([], [], [], [])


def test_validate_record_too_short_for_the_time_domain(monkeypatch):
    from chainid.gap.timedomain.data import MIN_SAMPLES
    from chainid.records.record import Record

    tr, base, final, _ = _fake_scores(monkeypatch, {"r1": 1.0, "r2": 1.0})
    monkeypatch.undo()
    t = np.arange(20) / 100.0
    short = Record("v", t, 2.0 + 0.1 * np.sin(8 * t), 1000.0 + 10 * np.sin(8 * t))
    with pytest.raises(ValueError, match=rf"--validate: test 'v' has 20 samples; need >= {MIN_SAMPLES}"):
        tr.transfer({"_problem": None, "_path": [base, final]}, [short])
