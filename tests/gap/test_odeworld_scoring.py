"""The ODE world's scoring on hand-made results: the right verdict per family, parameter errors and interval
coverage, the rates of a summary; the runner's reading of a diagnosis result; the families; and the world's
independence from the project's simulator (no import of its effect operators or motion programs)."""
from __future__ import annotations

import ast
import importlib
from pathlib import Path

import pytest

from chainid.gap.benchmark import odescore as sc
from chainid.gap.benchmark import odeworld as ow
from chainid.gap.benchmark.odefamilies import world_cases

BENCH = Path(__file__).resolve().parents[2] / "chainid" / "gap" / "benchmark"


def _row(family: str, effects: dict, verdict: str, shrinkage=None, snr=10.0, **kw):
    return {"family": family, "effects": effects, "verdict": verdict, "shrinkage": shrinkage, "snr": snr,
            "base": kw.pop("base", "chain14"), "excitation": kw.pop("excitation", "noise"), "seconds": 1.0,
            "sim_seconds": 0.5, **kw}


@pytest.mark.parametrize("family, effects, verdict, shrinkage, right", [
    ("single", {"friction": 1.0}, "friction", 0.8, True),
    ("single", {"friction": 1.0}, "friction+slack", 0.8, True),          # first of two
    ("single", {"friction": 1.0}, "slack+friction", 0.8, False),         # named, but not first
    ("single", {"stiffness_level": 1.0}, "machine_compliance", 0.9, True),  # the same physics
    ("single", {"friction": 1.0}, "unexplained", None, False),
    ("pair", {"friction": 1.0, "sensor_delay": 1.0}, "sensor_delay+hysteresis+friction", 0.9, True),
    ("pair", {"friction": 1.0, "sensor_delay": 1.0}, "friction", 0.9, False),
    ("control", {}, "none", None, True),
    ("control", {}, "backlash", 0.7, False),
    ("outside", {}, "unexplained", 0.2, True),
    ("outside", {}, "hysteresis", 0.3, True),                            # weak: shrinkage below 50 %
    ("outside", {}, "hysteresis", 0.6, False),                           # named with confidence
    ("outside", {}, "error: ValueError: x", None, False),
    ("covariate", {"friction": 1.0}, "friction", 0.6, True),
])
def test_right_verdict_per_family(family, effects, verdict, shrinkage, right):
    assert sc.score_row(_row(family, effects, verdict, shrinkage))["right"] is right


@pytest.mark.parametrize("effects, verdict, base_law, right", [
    ({"damping_law": 1.0}, "none", "feature", True),                    # the base's law is the truth's
    ({"damping_law": 1.0}, "hysteresis", "feature", False),             # something beyond it named
    ({"damping_law": 1.0}, "none", "viscous", False),                   # one c: the law must be named
    ({"damping_law": 1.0}, "damping_law", "viscous", True),
    ({"backlash": 1.0, "damping_law": 1.0}, "backlash", "feature", True),
    ({"backlash": 1.0, "damping_law": 1.0}, "none", "feature", False),
    ({"backlash": 1.0, "damping_law": 1.0}, "backlash", "viscous", False),
    ({"damping_law": 1.0}, "none", "polynomial", True),                 # the harmonic route's Eq. 21 carries it
    ({"damping_law": 1.0}, "friction", "polynomial", False),
    ({"damping_law": 1.0}, "none", "hysteretic", False),                # c_e = h/ω, of ω alone: must be named
])
def test_a_base_carrying_the_damping_law_reports_it(effects, verdict, base_law, right):
    """A base whose dashpot follows the records' ω and A (the time route's feature law, the harmonic route's Eq. 21)
    carries a ``damping_law`` truth itself: alone it is right as ``none``, in a pair by the other effect; a base
    with one c, or a law of one variable, must name it."""
    fam = "single" if len(effects) == 1 else "pair"
    assert sc.score_row(_row(fam, effects, verdict, 0.8, base_law=base_law))["right"] is right


def test_parameter_error_and_interval_coverage_by_sd_and_by_ci90():
    truth = {"effects": {"friction": {"F_c": 40.0, "dF": 0.0, "x_s": 0.002}, "sensor_delay": {"tau": -0.004}}}
    row = _row("pair", {"friction": 1.0, "sensor_delay": 1.0}, "friction+sensor_delay", 0.9, truth=truth,
               params={"friction.F_c": 42.0, "friction.x_s": 0.0025, "sensor_delay.tau": -0.0041, "damping.c": 3.0},
               params_sd={"friction.F_c": 1.0, "friction.x_s": 0.0001},
               params_ci90={"sensor_delay.tau": [-0.0045, -0.0039]})
    got = {p["param"]: p for p in sc.score_row(row)["params"]}
    assert set(got) == {"friction.F_c", "friction.x_s", "sensor_delay.tau"}  # dF not estimated: not scored
    assert got["friction.F_c"]["rel_error"] == pytest.approx(2.0 / 40.0)
    assert got["friction.F_c"]["covered"] is False        # |2| > 1.645·1
    assert got["friction.x_s"]["rel_error"] == pytest.approx(0.25)
    assert got["friction.x_s"]["covered"] is False        # 0.0005 > 1.645·0.0001
    assert got["sensor_delay.tau"]["rel_error"] == pytest.approx(0.0001 / 0.004)
    assert got["sensor_delay.tau"]["covered"] is True     # −0.004 in [−0.0045, −0.0039]
    row["params_sd"]["friction.F_c"] = 1.3                # 2 <= 1.645·1.3 = 2.14
    assert {p["param"]: p for p in sc.score_row(row)["params"]}["friction.F_c"]["covered"] is True


def test_a_covariate_parameter_is_scored_against_its_law_at_the_mean_condition():
    truth = {"effects": {"friction": {"F_c": 10.0, "x_s": 0.01}},
             "covariate": {"effect": "friction", "param": "F_c", "p0": 10.0, "p1": 5.0, "values": [0, 1, 2, 3]}}
    row = _row("covariate", {"friction": 1.0}, "friction", 0.7, truth=truth, params={"friction.F_c": 18.0})
    (p,) = sc.score_row(row)["params"]
    assert p["truth"] == pytest.approx(10.0 + 5.0 * 1.5) and p["rel_error"] == pytest.approx(0.5 / 17.5)
    assert p["covered"] is None  # no interval reported


def test_summary_rates_per_family_strong_subset_and_breakdowns():
    rows = [_row("single", {"friction": 1.0}, "friction", 0.8, snr=10.0, base="chain14"),
            _row("single", {"friction": 1.0}, "unexplained", None, snr=1.0, base="damper"),
            _row("single", {"hysteresis": 1.0}, "hysteresis", 0.7, snr=2.0, base="damper", excitation="chirp"),
            _row("control", {}, "none", None, snr=0.1), _row("control", {}, "friction", 0.6, snr=5.0),
            _row("control", {}, "error: RuntimeError: x", None, snr=float("nan"))]
    for r in rows:
        r["score"] = sc.score_row(r)
    s = sc.summarise(rows)
    f = s["families"]["single"]
    assert (f["n"], f["right"], f["rate"]) == (3, 2, pytest.approx(2 / 3))
    assert (f["strong"]["n"], f["strong"]["right"]) == (1, 1)  # snr >= 3 only
    assert f["by_base"] == {"chain14": {"n": 1, "right": 1, "rate": 1.0}, "damper": {"n": 2, "right": 1, "rate": 0.5}}
    assert f["by_excitation"]["chirp"] == {"n": 1, "right": 1, "rate": 1.0}
    c = s["families"]["control"]
    assert (c["n"], c["right"], c["verdicts"]) == (3, 1, {"none": 1, "friction": 1, "error": 1})
    assert (c["strong"]["n"], c["strong"]["right"]) == (1, 0)  # the NaN snr of the error is not strong
    assert len(s["errors"]) == 1 and len(s["misses"]) == 3
    text = sc.format_table(s)
    assert "single" in text and "67 % (2/3)" in text and "100 % (1/1)" in text
    md = sc.markdown_table(s)
    assert "| control | 33 % (1/3) | 0 % (0/1) |" in md
    assert "| family | chain14 | damper |" in md and "| single | 1/1 | 1/2 |" in md and "| control | 1/3 | – |" in md


def test_run_case_reads_the_diagnosis_result_and_scores_it(monkeypatch):
    """A stand-in diagnosis (the real one is not under test here) returns a hand-made result."""
    dg = importlib.import_module("chainid.gap.diagnose")  # the package binds the name to the function

    seen = {}

    def fake(records, holdout, model, **kw):
        seen.update(n=len(records), holdout=list(holdout), model=model, kw=kw)
        return {"verdict": "friction", "baseline": {"excess_rms_N": 30.0, "noise_sigma_N": 3.0,
                                                    "damping_law": "feature"},
                "steps": [{"effect": "baseline", "params": {}, "shrinkage": 0.0},
                          {"effect": "friction", "params": {"friction.F_c": 1.0}, "params_sd": {"friction.F_c": 0.1},
                           "shrinkage": 0.75}], "route": "time", "excluded": []}
    monkeypatch.setattr(dg, "diagnose", fake)
    case = {"family": "single", "base": "damper", "excitation": "chirp", "effects": {"friction": 1.0},
            "outside": {}, "covariate": None, "sign": 1.0, "seed": 3, "label": "t"}
    row = ow.run_case(case)
    assert row["verdict"] == "friction" and row["snr"] == pytest.approx(10.0) and row["shrinkage"] == 0.75
    assert row["base_law"] == "feature"
    assert seen["model"] is None and seen["kw"]["uncertainty"] is False and seen["holdout"] == row["holdout"]
    assert seen["n"] == len(row["truth"]["records"]) and 4 <= seen["n"] <= 8
    assert row["score"]["right"] is True
    (p,) = row["score"]["params"]
    F_c = row["truth"]["effects"]["friction"]["F_c"]
    assert p["rel_error"] == pytest.approx(abs(1.0 - F_c) / F_c)


def test_run_case_scores_the_verdicts_chain_not_a_step_after_the_held_out_minimum(monkeypatch):
    """A third step whose held-out error grew is out of the verdict (``trusted_steps`` = 2): the row's parameters and
    intervals are the friction step's, fitted without the over-fitted slack."""
    dg = importlib.import_module("chainid.gap.diagnose")
    steps = [{"effect": "baseline", "params": {}, "shrinkage": 0.0},
             {"effect": "friction", "params": {"friction.F_c": 1.0}, "params_ci90": {"friction.F_c": [0.9, 1.1]},
              "shrinkage": 0.75},
             {"effect": "slack", "params": {"friction.F_c": 5.0, "slack.s": 0.1},
              "params_ci90": {"friction.F_c": [4.0, 6.0]}, "shrinkage": 0.70}]
    monkeypatch.setattr(dg, "diagnose", lambda *a, **kw: {
        "verdict": "friction", "baseline": {"excess_rms_N": 30.0, "noise_sigma_N": 3.0}, "steps": steps,
        "trusted_steps": 2, "route": "time", "excluded": [],
        "stability": {"steps": [{}, {"params_ci90_resampled": {"friction.F_c": [0.95, 1.05]}},
                                {"params_ci90_resampled": {"friction.F_c": [4.5, 5.5]}}]}})
    case = {"family": "single", "base": "damper", "excitation": "chirp", "effects": {"friction": 1.0},
            "outside": {}, "covariate": None, "sign": 1.0, "seed": 3, "label": "t"}
    row = ow.run_case(case)
    assert row["params"] == {"friction.F_c": 1.0} and row["params_ci90"] == {"friction.F_c": [0.9, 1.1]}
    assert row["params_ci90_parts"] == {"resampled": {"friction.F_c": [0.95, 1.05]}}
    assert row["steps"] == ["friction", "slack"] and row["shrinkage"] == 0.70  # the chain as run is still shown


def test_run_case_gives_a_chain_its_chain_model_and_turns_a_crash_into_an_error_row(monkeypatch):
    dg = importlib.import_module("chainid.gap.diagnose")  # the package binds the name to the function
    from chainid.model.base import ChainModel

    def crash(records, holdout, model, **kw):
        assert isinstance(model, ChainModel) and model.chain.d == 18.0 and model.chain.pitch == 64.0
        raise RuntimeError("boom")
    monkeypatch.setattr(dg, "diagnose", crash)
    case = {"family": "control", "base": "chain18", "excitation": "noise", "effects": {}, "outside": {},
            "covariate": None, "sign": 1.0, "seed": 2, "label": "t"}
    row = ow.run_case(case)
    assert row["verdict"] == "error: RuntimeError: boom" and row["score"] == {
        "right": False, "named": [], "error": True, "params": []}


def test_families_hold_every_family_and_the_small_set_is_a_subset_of_labels_and_seeds():
    full, small = world_cases(False, 0), world_cases(True, 0)
    assert {c["family"] for c in full} == set(sc.FAMILIES) == {c["family"] for c in small}
    assert len(small) == 12 and len({c["label"] for c in full}) == len(full)
    by_label = {c["label"]: c["seed"] for c in full}
    assert all(by_label[c["label"]] == c["seed"] for c in small if c["label"] in by_label)
    lags = [c for c in full if "sensor_delay" in c["effects"]]
    assert {c["sign"] for c in lags} == {1.0, -1.0}  # force lag and displacement lag
    assert all(c["base"] in ("chain14", "chain18") for c in full
               if set(c["effects"]) & {"stiffness_level", "contact_law", "slack"})
    assert all(c["base"] not in ("chain14", "chain18") for c in full if set(c["effects"]) & {"hardening", "deadband"})
    assert world_cases(False, 5)[0]["seed"] == full[0]["seed"] + 5 * 10**7  # its own block (benchmark.seeds)
    with pytest.raises(ValueError, match=r"seed = -1 is out of range; valid range: an integer >= 0"):
        world_cases(True, -1)


def test_the_world_imports_none_of_the_projects_simulator():
    banned = {"chainid.model.effects", "chainid.model.operators", "chainid.records.simulate",
              "chainid.records.excitation"}
    files = sorted(BENCH.glob("ode*.py"))
    assert len(files) >= 6
    for f in files:
        for node in ast.walk(ast.parse(f.read_text())):
            mods = ([node.module or ""] + [f"{node.module}.{a.name}" for a in node.names]
                    if isinstance(node, ast.ImportFrom) else
                    [a.name for a in node.names] if isinstance(node, ast.Import) else [])
            assert not banned & set(mods), f"{f.name} imports {banned & set(mods)}"


def test_open_world_rates_and_which_finding_flagged_the_outside_cases():
    """Flags on outside cases (and by which finding: the learner's ``state``, a ``time`` trend, ``chatter``),
    silence on controls and on right verdicts, counted by hand."""
    def ow_row(family, effects, verdict, kinds, **kw):
        r = _row(family, effects, verdict, 0.8, **kw)
        r["open_world"] = {"missing_effect": bool(kinds), "kinds": kinds, "predictable_share": 0.3}
        r["score"] = sc.score_row(r)
        return r

    rows = [ow_row("outside", {}, "unexplained", ["state"], outside={"relaxation": 1.0}),
            ow_row("outside", {}, "unexplained", ["time"], outside={"drift": 1.0}),
            ow_row("outside", {}, "none", ["state", "chatter"], outside={"chatter": 1.0}),
            ow_row("outside", {}, "unexplained", [], outside={"relaxation": 2.0}, snr=0.3),  # at the noise
            ow_row("control", {}, "none", []), ow_row("control", {}, "none", ["time"]),
            ow_row("single", {"friction": 1.0}, "friction", []), ow_row("pair", {"friction": 1, "slack": 1},
                                                                        "friction+slack", []),
            ow_row("single", {"friction": 1.0}, "hysteresis", ["state"])]  # wrong: not among the explained
    got = sc.open_world_rates(rows)
    assert (got["outside_flagged"], got["outside_n"]) == (0.75, 4)
    assert (got["outside_flagged_strong"], got["outside_strong_n"]) == (1.0, 3)  # residual >= 3 σ
    assert got["outside_by_kind"] == {"state": 2, "time": 1, "chatter": 1}
    assert (got["control_silent"], got["control_n"], got["explained_silent"], got["explained_n"]) == (0.5, 2, 1.0, 2)
    summary = sc.summarise(rows)
    assert ("flags outside cases 75 % of 4 (by finding: state 2, time 1, chatter 1) (100 % of 3 with residual >= 3 σ)"
            in sc.format_table(summary))
    del rows[0]["open_world"]["kinds"]  # a row written before the findings were recorded
    assert sc.open_world_rates(rows)["outside_by_kind"] is None
    from chainid.gap.benchmark.openworldscore import open_world_row

    assert open_world_row({"open_world": {"missing_effect": True, "kinds": ["time"], "predictable_share": 0.1}}) == {
        "missing_effect": True, "kinds": ["time"], "predictable_share": 0.1}
    # the learner's finding does not count where what is left is at the noise floor (chainid.gap.core.openworld)
    assert open_world_row({"open_world": {"missing_effect": True, "kinds": ["state", "time"], "at_noise_floor": True,
                                          "predictable_share": 0.2}})["kinds"] == ["time"]


@pytest.mark.parametrize("verdict, base_law, right", [
    ("none", "feature", True), ("unexplained", "feature", True), ("damping_law", "polynomial", True),
    ("hysteresis", "feature", False),        # a wrong effect named for the curvature the base leaves
    ("unexplained", "viscous", False),       # one c in the base: the law must be named
])
def test_a_table1_law_the_base_only_approximates_is_right_when_nothing_else_is_named(verdict, base_law, right):
    row = _row("single", {"damping_law": 1.0}, verdict, 0.8, base_law=base_law, law_form="table1")
    assert sc.score_row(row)["right"] is right
    lin = _row("single", {"damping_law": 1.0}, "unexplained", 0.8, base_law="feature")  # the world's law is linear:
    assert sc.score_row(lin)["right"] is False                                          # the base fits it exactly
