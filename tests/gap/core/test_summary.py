"""The terminal summary and the JSON output of a diagnosis (chainid.gap.core.summary)."""
from __future__ import annotations

import numpy as np

from chainid.gap.core.summary import summary


# ---------------------------------------------------------------- summary
def _result(**baseline):
    b = {"model": "linear", "damping_law": "viscous", "nrmse_train": 0.1, "nrmse_holdout": 0.2,
         "db_over_noise": 3.0, "excess_rms_N": 5.0, "noise_sigma_N": 2.0} | baseline
    return {"baseline": b, "where": [], "ranking": [], "verdict": "none", "steps": []}


def test_summary_says_the_damping_law_reason_unless_given():
    """The baseline's damping-law reason is printed when the law was chosen (auto), not when the user gave it,
    and a result without a reason has no such line.  Bug caught: `and` → `or` in the condition."""
    assert "  damping law:" not in summary(_result())
    assert "  damping law:" not in summary(_result(damping_law_reason="given"))
    txt = summary(_result(damping_law_reason="4 training tests: a law with <= 3 coefficients"))
    assert "  damping law: 4 training tests: a law with <= 3 coefficients" in txt.splitlines()
    assert "VERDICT: none" in txt


def _summary_result(**kw):
    step0 = {"effect": "baseline", "nrmse_loto": 0.2, "nrmse_holdout": 0.25, "shrinkage": None,
             "fit_holdout_pct": 75.0, "db_over_noise": 12.34, "params": {}, "params_sd": {}}
    step1 = {"effect": "friction", "nrmse_loto": 0.05, "nrmse_holdout": 0.04, "shrinkage": 0.84,
             "fit_holdout_pct": 96.0, "db_over_noise": 1.0,
             "params": {"friction.F_c": 150.04, "spring.k": 3.0, "law.a": 1.0, "friction.x_s": None,
                        "friction.mu": 0.0123},
             "params_sd": {"friction.F_c": 3.21}, "at_bound": ["friction.mu"]}
    res = {"baseline": {"model": "chain", "damping_law": "polynomial", "nrmse_train": 0.1, "nrmse_holdout": 0.25,
                        "db_over_noise": 12.34, "excess_rms_N": 50.0, "noise_sigma_N": 4.0},
           "where": [{"finding": f"w{i}"} for i in range(10)],
           "ranking": [{"effect": f"e{i}", "nrmse_loto": 0.1 * i, "nrmse_holdout": 0.2, "shrinkage": 0.5,
                        "params": {f"e{i}.p": 1.5}} for i in range(8)],
           "confounded": [{"pair": ["friction", "hysteresis"], "separate_by": "a small test"}],
           "excluded": [{"test": "7", "reason": "not steady"}],
           "steps": [step0, step1], "stop": "no further effect shrinks it", "verdict": "friction",
           "left_nrmse_holdout": 0.04,
           "chain_text": "baseline → friction", "residual": {"db_over_noise": 1.04, "stationary": True},
           "interpretation": "dry sliding", "mechanism": "friction", "warnings": ["w!"]}
    return res | kw


def test_summary_text_by_hand():
    """Every line by hand; how much: the kept chain's held-out NRMSE 0.04 against the baseline's 0.25 (shrinkage
    1 − 0.04/0.25 = 84 %), the held-out fit 100·(1 − 0.04) = 96.0 % and the residual 10^(1.04/20) = 1.127 × the
    noise floor."""
    from chainid.gap.core.summary import summary

    lines = summary(_summary_result(), n_rank=3).splitlines()
    assert lines[0] == ("Baseline (chain, damping law: polynomial): NRMSE train 0.1, held-out 0.25 (12.3 dB over the "
                        "noise floor; systematic 50 N vs noise σ 4 N)")
    assert lines[1] == "  excluded test 7: not steady"
    assert lines[3:5] == ["WHERE the model misses (largest first):", "  - w0"]
    assert "  - w7" in lines and "  - w8" not in lines  # the first 8 findings
    assert "WHICH effects, in order (each fitted on top of the previous ones; scored leave-one-test-out):" in lines
    i = lines.index("WHICH effects, in order (each fitted on top of the previous ones; scored leave-one-test-out):")
    assert lines[i + 2] == (f"  {0:<5} {'baseline':<20} {0.2:>8.4g} {0.25:>9.4g} {75.0:>6.1f} {0.0:>6.1f}% "
                            f"{12.34:>8.1f}  ")
    # spring.*, law.* and None parameters are not shown; sd with 2 digits; a bound marked
    assert lines[i + 3].endswith("  friction.F_c=150±3.2, friction.mu=0.0123 (at bound)")
    assert f" {96.0:>6.1f} {84.0:>6.1f}% " in lines[i + 3]
    assert lines[i + 4] == "  left: 1.0 dB over the noise floor; stationary"
    assert lines[i + 5] == "  the chain stops: no further effect shrinks it"
    assert sum(".p=1.5" in ln for ln in lines) == 3  # n_rank
    assert "  confounded: friction ~ hysteresis; to separate them: a small test" in lines
    assert "VERDICT: friction — baseline → friction" in lines
    assert ("  held-out NRMSE 0.25 → 0.04 (shrinkage 84 %); fit left 96.0 % (held-out NRMSE 0.04), residual 1.13× "
            "the noise floor") in lines
    assert lines[-3:] == ["  meaning: dry sliding", "  mechanism: friction", "WARNING: w!"]


def test_summary_route_residual_and_unexplained_texts():
    from chainid.gap.core.summary import summary, waterfall

    txt = summary(_summary_result(route="time", verdict="unexplained", left_nrmse_holdout=0.123456,
                                  mechanism="unexplained", interpretation="", warnings=[]))
    assert "scored leave-one-block/test-out):" in txt
    # what is left: fit 100·(1 − 0.123456) = 87.7 %, residual 10^(1.04/20) = 1.127 × the noise floor
    assert txt.splitlines()[-1] == ("VERDICT: unexplained — no library effect passed the step rule or shrinks the "
                                    "held-out gap (or its part above the kinematic floor) by half; fit left 87.7 % "
                                    "(held-out NRMSE 0.1235), residual 1.13× the noise floor.")
    assert "mechanism:" not in txt and "meaning:" not in txt
    assert "scored leave-one-block/test-out" in summary(_summary_result(route="mixed"))
    assert "scored leave-one-test-out" in summary(_summary_result(route="phase"))
    drift = summary(_summary_result(verdict="unexplained", left_nrmse_holdout=0.2,
                                    residual={"db_over_noise": 0.0, "stationary": False, "at_noise_floor": True}))
    assert ("VERDICT: unexplained — what is left changes with time within the tests (no static effect explains "
            "that); fit left 80.0 % (held-out NRMSE 0.2), residual 1.00× the noise floor.") in drift
    assert waterfall({"steps": [], "residual": {"db_over_noise": 0.04, "stationary": False,
                                                "at_noise_floor": True}})[1] == \
        "  left: 0.0 dB over the noise floor (at the floor); NOT stationary"
    assert waterfall({"steps": [], "residual": {"db_over_noise": 2.0, "stationary": None}})[1] == \
        "  left: 2.0 dB over the noise floor; stationarity not checked"
    assert len(waterfall({"steps": []})) == 1  # no residual: the header only
    # a named verdict reports the kept chain (left_nrmse_holdout: 0.125, shrinkage 1 − 0.125/0.25 = 50 %), not the
    # last step (0.04, an over-fitted one would be there) nor the best single candidate
    best = {"nrmse_holdout": 0.1, "shrinkage": 0.6}
    assert ("  held-out NRMSE 0.25 → 0.125 (shrinkage 50 %); fit left 87.5 % (held-out NRMSE 0.125), residual 1.13× "
            "the noise floor") in summary(_summary_result(best=best, left_nrmse_holdout=0.125)).splitlines()


def test_summary_of_a_result_without_the_optional_numbers_says_n_a():
    """A result made before ``left_nrmse_holdout`` and the steps' ``fit_holdout_pct`` were in the contract (or with
    them None, a non-finite number in the JSON) is summarised with "n/a" for them, not a TypeError."""
    old = _summary_result()
    del old["left_nrmse_holdout"]
    for st in old["steps"]:
        del st["fit_holdout_pct"]
    lines = summary(old, n_rank=3).splitlines()
    assert "  held-out NRMSE 0.25 → n/a (shrinkage n/a); no held-out fit" in lines
    i = lines.index("WHICH effects, in order (each fitted on top of the previous ones; scored leave-one-test-out):")
    assert lines[i + 2] == f"  {0:<5} {'baseline':<20} {0.2:>8.4g} {0.25:>9.4g} {'n/a':>6} {0.0:>6.1f}% {12.34:>8.1f}  "
    none = summary(_summary_result(left_nrmse_holdout=None)).splitlines()
    assert "  held-out NRMSE 0.25 → n/a (shrinkage n/a); no held-out fit" in none


def test_to_json_drops_private_keys_and_non_finite_numbers():
    from chainid.gap.core.summary import to_json

    res = {"a": np.float64(1.5), "_problem": object(), "b": [np.int64(3), float("nan"), (float("inf"), 2.0)],
           "c": {"_x": 1, "y": np.float32(0.5)}, 4: "four"}
    assert to_json(res) == {"a": 1.5, "b": [3, None, [None, 2.0]], "c": {"y": 0.5}, 4: "four"}
    assert type(to_json(res)["b"][0]) is int and type(to_json(res)["c"]["y"]) is float  # numpy → Python


def test_a_none_verdict_says_how_the_residual_was_read():
    """``none`` states what was checked: the noise (both routes), or on the time route the kinematic floor or the
    base's damping law extrapolated (``none_reading``); never "consistent with the noise" for the latter two."""
    from chainid.gap.core.summary import summary

    def last(**kw):
        return [ln for ln in summary(_summary_result(verdict="none", **kw)).splitlines() if ln.startswith("VERDICT")][0]

    assert last() == "VERDICT: none — the baseline's held-out residual is consistent with the noise."
    assert last(none_reading="noise") == last()
    kin = last(none_reading="kinematic_floor")
    assert "at the kinematic floor" in kin and "consistent with the noise" not in kin
    law = last(none_reading="damping_extrapolation")
    assert "damping law read beyond the training records" in law and "consistent with the noise" not in law
