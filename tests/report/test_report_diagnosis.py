"""The Markdown of one diagnosis (chainid.report.diagnosis) from a hand-made result and from its JSON."""
from __future__ import annotations

import json

from chainid.report.diagnosis import diagnosis_markdown


def _res(verdict="friction", **kw):
    tests = [
        {"test": "1", "split": "train", "omega": 1.0, "x0": 2.2, "A": 0.1, "nrmse_before": 0.05, "nrmse_after": 0.01},
        {"test": "2", "split": "train", "omega": 2.0, "x0": 2.2, "A": 0.3, "nrmse_before": 0.04, "nrmse_after": 0.02},
        # held out: omega 2.2 is outside 2.0 + 5 % of 2.0 = 2.1; A 0.31 is inside 0.3 + 0.015
        {"test": "3", "split": "holdout", "omega": 2.2, "x0": 2.2, "A": 0.31, "nrmse_before": 0.06,
         "nrmse_after": None},
        {"test": "4", "split": "holdout", "omega": 2.09, "x0": 2.2, "A": 0.05, "nrmse_before": 0.03,
         "nrmse_after": 0.01},
    ]
    res = {
        "baseline": {"model": "chain", "nrmse_train": 0.0451, "nrmse_holdout": 0.06012, "excess_rms_N": 123.456,
                     "noise_sigma_N": 7.0, "db_over_noise": 24.94},
        "holdout": ["3", "4"],
        "where": [{"finding": f"finding {i}"} for i in range(8)],
        "ranking": [
            {"effect": "friction", "params": {"friction.F_c": 150.04, "law.a": 1.0, "friction.mu": None},
             "nrmse_loto": 0.012346, "nrmse_holdout": 0.01, "shrinkage": 0.8337, "damping_law": "polynomial"},
            {"effect": "damping_law", "params": {}, "nrmse_loto": None, "nrmse_holdout": 0.05, "shrinkage": None,
             "damping_law": "power"},
        ],
        "confounded": [{"pair": ["friction", "backlash"], "separate_by": "a larger amplitude"}],
        "verdict": verdict,
        "best": {"effect": "friction", "params": {"friction.F_c": 150.04}, "params_sd": {"friction.F_c": 3.21},
                 "nrmse_holdout": 0.01, "shrinkage": 0.8337},
        "left_nrmse_holdout": 0.0432,
        "interpretation": "dry friction",
        "warnings": ["w1"],
        "tests": tests,
    }
    res.update(kw)
    return res


def test_diagnosis_markdown_of_a_hand_made_result():
    md = diagnosis_markdown(_res(), "figures/x", "json/x.json", n_where=3, n_rank=2)
    assert ("**Baseline** (chain, damping law Eq. 21 fitted on the training tests): NRMSE train 0.0451, held-out "
            "0.06012; systematic held-out residual 123.5 N against a noise σ of 7 N (24.9 dB over the noise floor "
            "of the cycle means). Held out: 3, 4.") in md
    assert "- finding 2\n" in md and "finding 3" not in md  # n_where = 3
    # held-out 3: omega 2.2 > 2.0 + 0.05 * 2.0 = 2.1 (extrapolated); A 0.31 <= 0.3 + 0.015 (inside); test 4:
    # omega 2.09 inside, A 0.05 < 0.1 - 0.015
    assert ("- held-out test 3 is an extrapolation (ω = 2.2 rad/s outside the training 1–2 rad/s): its baseline "
            "error includes the damping law's extrapolation error") in md
    assert "- held-out test 4 is an extrapolation (A = 0.05 mm outside the training 0.1–0.3 mm)" in md
    assert "| friction | friction.F_c = 150 | 0.01235 | 0.01 | 83.4 % |" in md
    assert "| damping_law | c_e law power | – | 0.05 | – |" in md
    assert "Confounded: friction and backlash fit equally well; to separate them: a larger amplitude." in md
    assert ("**Verdict: friction** (friction.F_c = 150 ± 3.2) — held-out NRMSE 0.06012 → 0.01 (shrinkage 83 %)."
            in md)
    assert "Meaning: dry friction." in md and "> Warning: w1" in md
    assert "| 3 | holdout | 2.2 | 2.2 | 0.31 | 0.06 | – |" in md
    assert "| 1 | train | 1 | 2.2 | 0.1 | 0.05 | 0.01 |" in md
    assert "JSON: `json/x.json`." in md and "![held-out loops](figures/x/loops.png)" in md


def test_diagnosis_markdown_of_a_result_read_back_from_json():
    """A result saved as JSON and read back (new string objects) renders the same Markdown."""
    res = _res()
    assert diagnosis_markdown(json.loads(json.dumps(res)), "f", "j") == diagnosis_markdown(res, "f", "j")


def test_diagnosis_markdown_verdicts_none_and_unexplained():
    md = diagnosis_markdown(_res("none", confounded=[], warnings=[], interpretation=None), "f", "j")
    assert "**Verdict: none** — the baseline's held-out residual is consistent with the noise." in md
    assert "Confounded" not in md and "Warning" not in md and "Meaning" not in md
    md = diagnosis_markdown(_res("unexplained"), "f", "j")
    assert ("**Verdict: unexplained** — no library effect halves the held-out gap (best friction: shrinkage 83 %, "
            "held-out NRMSE left 0.0432).") in md
    md = diagnosis_markdown(_res("unexplained", best=None), "f", "j")
    assert "(best –: shrinkage 0 %" in md
    # all six findings by default, none extrapolated when the held-out tests are inside the training range
    tests = [dict(t, omega=1.5, A=0.2) if t["split"] == "holdout" else t for t in _res()["tests"]]
    md = diagnosis_markdown(_res(tests=tests), "f", "j")
    assert "- finding 5\n" in md and "finding 6" not in md and "extrapolation" not in md


def test_diagnosis_markdown_verdict_of_an_effect_named_after_unexplained():
    """A verdict is "none", "unexplained" or the named effect chain; an effect whose name sorts after
    "unexplained" (viscous_excess) is a named verdict with its parameters, not the unexplained text."""
    best = {"effect": "viscous_excess", "params": {"viscous_excess.c": 0.25}, "nrmse_holdout": 0.02,
            "shrinkage": 0.6673}
    md = diagnosis_markdown(_res("viscous_excess", best=best), "f", "j")
    assert ("**Verdict: viscous_excess** (viscous_excess.c = 0.25) — held-out NRMSE 0.06012 → 0.02 (shrinkage "
            "67 %).") in md
    assert "Verdict: unexplained" not in md
