"""``chainid benchmark-gap --generator``: sim stays the default, ode runs the ODE world, both runs each and reports
them apart; options of the sim generator are refused with ode before anything runs."""
from __future__ import annotations

import json

import pytest

from chainid.cli import main
from chainid.gap.benchmark import grid, odeworld


@pytest.fixture()
def stubs(monkeypatch):
    calls = {}

    def fake_sim(**kw):
        calls["sim"] = kw
        print("SIM RAN")
        return {"n_cases": 1, "stub": "sim"}

    def fake_ode(**kw):
        calls["ode"] = kw
        print("ODE RAN")
        return {"n_cases": 2, "stub": "ode"}
    monkeypatch.setattr(grid, "run_benchmark", fake_sim)
    monkeypatch.setattr(odeworld, "run_world", fake_ode)
    return calls


def test_sim_is_the_default_generator_with_every_excitation(stubs, capsys):
    assert main(["benchmark-gap", "--small", "--no-progress"]) == 0
    assert set(stubs) == {"sim"}
    assert stubs["sim"]["excitations"] == ("harmonic", "random", "sweep", "startup", "quake", "transfer")
    assert "SIM RAN" in capsys.readouterr().out


def test_ode_generator_runs_the_ode_world_with_seed_and_workers(stubs, tmp_path, capsys):
    out = tmp_path / "o.json"
    assert main(["benchmark-gap", "--generator", "ode", "--small", "--seed", "7", "--workers", "2",
                 "--no-progress", "--json", str(out)]) == 0
    assert set(stubs) == {"ode"}
    kw = stubs["ode"]
    assert (kw["small"], kw["seed"], kw["jobs"], kw["json_path"]) == (True, 7, 2, str(out))


def test_both_generators_run_and_one_json_holds_each_apart(stubs, tmp_path, capsys):
    out = tmp_path / "b.json"
    assert main(["benchmark-gap", "--generator", "both", "--small", "--no-progress", "--json", str(out)]) == 0
    assert stubs["sim"]["json_path"] is None and stubs["ode"]["json_path"] is None
    d = json.loads(out.read_text())
    assert d == {"generator": "both", "sim": {"n_cases": 1, "stub": "sim"}, "ode": {"n_cases": 2, "stub": "ode"}}
    text = capsys.readouterr().out
    assert text.index("== generator sim") < text.index("SIM RAN") < text.index("== generator ode") < \
        text.index("ODE RAN")


@pytest.mark.parametrize("extra", [["--chain", "din22252:18x64"], ["--excitations", "harmonic"]])
def test_ode_generator_refuses_the_sim_options_before_running(stubs, tmp_path, capsys, extra):
    out = tmp_path / "o.json"
    rc = main(["benchmark-gap", "--generator", "ode", "--small", "--json", str(out), *extra])
    r = capsys.readouterr()
    assert rc == 2 and "--chain and --excitations choose the sim generator's cases" in r.err
    assert stubs == {} and not out.exists()


def test_ode_world_through_the_cli_writes_real_rows(monkeypatch, tmp_path, capsys):
    """One fast real case (a damper under chirps, no effect), serial: the JSON carries its row, truth and score."""
    case = {"world": "ode", "family": "control", "base": "damper", "excitation": "chirp", "effects": {},
            "outside": {}, "covariate": None, "sign": 1.0, "offsets": False, "label": "control/damper/chirp/none",
            "seed": 3}
    monkeypatch.setattr(odeworld, "world_cases", lambda small, seed: [case])
    out = tmp_path / "o.json"
    assert main(["benchmark-gap", "--generator", "ode", "--scheduler", "serial", "--no-progress", "--json",
                 str(out)]) == 0
    d = json.loads(out.read_text())
    (row,) = d["rows"]
    assert d["generator"] == "ode" and d["n_cases"] == 1 and row["label"] == case["label"]
    assert row["truth"]["base"]["name"] == "damper" and len(row["truth"]["records"]) == len(
        [r for r in row["truth"]["records"] if r["kind"] == "chirp"]) >= 4
    assert row["score"]["right"] == (row["verdict"] == "none")
    assert d["families"]["control"]["n"] == 1
    assert "ODE world: 1 cases" in capsys.readouterr().out


def test_cases_runs_only_the_labels_that_contain_it(monkeypatch, capsys):
    seen = []
    monkeypatch.setattr(odeworld, "run_case", lambda c: seen.append(c["label"]) or {})
    monkeypatch.setattr("chainid.gap.benchmark.odescore.summarise", lambda rows: {"n": len(rows)})
    monkeypatch.setattr("chainid.gap.benchmark.odescore.format_table", lambda s: "TABLE")
    assert main(["benchmark-gap", "--generator", "ode", "--cases", "~table1", "--scheduler", "serial",
                 "--no-progress"]) == 0
    assert len(seen) == 8 and all(lbl.endswith("~table1") for lbl in seen)  # 7 singles and the pair
    assert sum(lbl.startswith("pair/") for lbl in seen) == 1


def test_cases_chooses_the_sim_grids_cases_by_excitation_family_and_effects(monkeypatch):
    from chainid.gap.benchmark import grid as gridmod

    seen = []
    monkeypatch.setattr("chainid.infra.parallel.run_cases", lambda fn, cases, **kw: seen.extend(cases) or [])
    monkeypatch.setattr("chainid.gap.benchmark.report.summarise", lambda rows: {})
    monkeypatch.setattr("chainid.gap.benchmark.report.format_summary", lambda s: "")
    assert main(["benchmark-gap", "--excitations", "random,sweep", "--cases", "sensor_delay", "--no-progress"]) == 0
    every = gridmod.grid(False, 0, ("random", "sweep"))
    want = [c for c in every if "sensor_delay" in c["effects"]]  # singles, pairs and the mismatch+ ones
    assert len(seen) == len(want) >= 6
    assert [(c["excitation"], c["family"], c["effects"], c["seed"]) for c in seen] == \
        [(c["excitation"], c["family"], c["effects"], c["seed"]) for c in want]
    assert {c["label"] for c in seen} >= {"random/single/sensor_delay", "sweep/pair/friction+sensor_delay"}
    seen.clear()
    assert main(["benchmark-gap", "--excitations", "random", "--cases", "random/control/", "--no-progress"]) == 0
    assert seen and all(c["family"] == "control" and c["label"] == "random/control/none" for c in seen)


@pytest.mark.parametrize("argv, msg", [
    (["--generator", "ode", "--cases", "nothing-like-this"], "--cases 'nothing-like-this' matches no case label"),
    (["--cases", "~table1"], "--cases '~table1' matches no case label of the sim grid"),
    (["--generator", "both", "--cases", "random/pair/"], "--cases 'random/pair/' matches no case label of the ODE world"),
    (["--generator", "both", "--cases", "~table1"], "--cases '~table1' matches no case label of the sim grid")])
def test_cases_that_match_no_label_of_the_chosen_world_are_refused(argv, msg, capsys):
    assert main(["benchmark-gap", "--no-progress", *argv]) == 2
    assert msg in capsys.readouterr().err
