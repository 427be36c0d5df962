"""``chainid diagnose``: excluded tests, the documented defaults (--max-combo, --steady-tol), --model linear, the
model files of the explanation chain (--save-model, --save-steps) checked before it runs and their provenance."""
from __future__ import annotations

import json
import re

import numpy as np
import pytest

from chainid.cli import main
from chainid.cli.model import save_models, step_paths
from chainid.gap.benchmark.grid import grid3x3_plan
from chainid.model.augmented import AugmentedModel
from chainid.model.base import ChainModel, LinearModel
from chainid.model.laws import PolynomialLaw
from chainid.model.modelfile import load_model
from chainid.records.files import write_records
from chainid.records.simulate import TestSpec, simulate, simulate_test

from repo_paths import REPO


MODEL = ChainModel()


LAW = PolynomialLaw([0.5, 1.0, 100.0, 20.0, 50.0])


COMMANDS_PAGE = REPO / "docs" / "reference" / "commands.md"


def _data(tmp_path, with_short=True):
    recs = simulate(grid3x3_plan(prefix=""), MODEL, LAW, n_cycles=6, samples_per_cycle=64, noise_F=20.0, seed=4)
    if with_short:  # 0.7 of a cycle: no whole steady cycle, and too short for the time-domain route
        recs.append(simulate_test(TestSpec("short", 2.0, 2.0, 0.2), MODEL, LAW, n_cycles=0.7, samples_per_cycle=64,
                                  noise_F=20.0, rng=np.random.default_rng(3)))
    p = tmp_path / "d.csv"
    write_records(p, recs)
    return p


def test_cli_diagnose_excludes_an_unusable_test(tmp_path, capsys):
    """The CLI names the excluded test on stderr (one line) and in the JSON, and still answers; ``--strict``
    makes it an error (exit 2, one line naming the test).  Bugs caught: the exclusion silent on the CLI, the
    strict flag not passed through, the JSON's ``excluded`` empty."""
    data = _data(tmp_path)
    out = tmp_path / "r.json"
    assert main(["diagnose", "--resamples", "0", str(data), "--holdout", "3,7,11", "--max-combo", "1", "--json", str(out)]) == 0
    err = capsys.readouterr().err
    lines = [ln for ln in err.splitlines() if "excluded" in ln]
    assert len(lines) == 1 and "short" in lines[0]
    doc = json.loads(out.read_text())
    assert [e["test"] for e in doc["excluded"]] == ["short"] and doc["excluded"][0]["reason"]
    assert "short" not in [t["test"] for t in doc.get("tests", [])]
    assert main(["diagnose", "--resamples", "0", str(data), "--holdout", "3,7,11", "--max-combo", "1", "--strict"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "short" in err[0] and "Traceback" not in err[0]


def test_cli_max_combo_default_is_the_documented_one(tmp_path, monkeypatch):
    """The commands page (docs/reference/commands.md) and --help document ``--max-combo 3``; the CLI must pass 3 when the option is left out.
    Bug caught: a different default in the parser."""
    documented = int(re.search(r"\[--max-combo (\d)\]", COMMANDS_PAGE.read_text(encoding="utf-8")).group(1))
    assert documented == 3
    seen = {}

    import importlib

    dg = importlib.import_module("chainid.gap.diagnose")  # the module (the package exports a function of that name)

    def fake(records, holdout, model=None, **kw):
        seen.update(kw)
        raise ValueError("stop here")

    monkeypatch.setattr(dg, "diagnose", fake)
    data = _data(tmp_path, with_short=False)
    assert main(["diagnose", "--resamples", "0", str(data), "--holdout", "3"]) == 2
    assert seen["max_combo"] == documented


@pytest.mark.parametrize("tol,ok", [("0.05", True), ("0.999", True), ("0", False), ("1", False)])
def test_cli_diagnose_steady_tol_range(tmp_path, monkeypatch, capsys, tol, ok):
    """--steady-tol in (0, 1): 0.05 passes the check (the stand-in diagnosis then stops), 0 and 1 are refused.
    Bug caught: the lower bound's comparison garbled."""
    import importlib

    dg = importlib.import_module("chainid.gap.diagnose")

    def fake(*a, **k):
        raise ValueError("stand-in stops here")

    monkeypatch.setattr(dg, "diagnose", fake)
    data = _data(tmp_path, with_short=False)
    assert main(["diagnose", "--resamples", "0", str(data), "--holdout", "3", "--steady-tol", tol]) == 2
    err = capsys.readouterr().err
    assert ("stand-in stops here" in err) is ok and ("--steady-tol" in err) is (not ok)


SPRING = LinearModel(k=200.0, x_ref=0.0, mass=0.0)


def test_save_models_writes_the_last_step_and_every_step(tmp_path):
    """``--save-model M.toml`` is the chosen chain's model (the last step); ``--save-steps`` writes step i to
    ``M.stepi.toml``; every file carries the command line as provenance."""
    step0 = AugmentedModel(base=SPRING)
    step1 = AugmentedModel(base=SPRING, effects=[("friction", {"F_c": 150.0, "mu": 0.0})])
    step2 = AugmentedModel(base=SPRING, effects=[("friction", {"F_c": 150.0, "mu": 0.0}),
                                                 ("backlash", {"b": 0.02})])
    res = {"_models": [step0, step1, step2]}
    m = tmp_path / "m.toml"
    paths = save_models(res, str(m), True, "d.csv", ["diagnose", "d.csv", "--holdout", "3"], force=False)
    assert paths == [m, *step_paths(m, 3)]
    assert [p.name for p in paths[1:]] == ["m.step0.toml", "m.step1.toml", "m.step2.toml"]
    assert [n for n, _ in load_model(m).effects] == ["friction", "backlash"]
    assert [[n for n, _ in load_model(p).effects] for p in paths[1:]] == [[], ["friction"], ["friction", "backlash"]]
    assert "chainid diagnose d.csv --holdout 3" in m.read_text()
    m2 = tmp_path / "only.json"
    assert save_models(res, str(m2), False, "d.csv", ["x"], force=False) == [m2]
    assert [e["name"] for e in json.loads(m2.read_text())["effects"]] == ["friction", "backlash"]
    assert not (tmp_path / "only.step0.json").exists()


@pytest.mark.parametrize("max_combo", [1, 2, 3])
def test_diagnose_checks_every_step_file_before_it_runs(tmp_path, capsys, max_combo):
    """A chain of ``--max-combo`` K effects has K + 1 steps (baseline + K): the last step file M.stepK.toml is
    checked before anything else (here the data does not even exist, so any later check names the data)."""
    m = tmp_path / "m.toml"
    last = step_paths(m, max_combo + 1)[-1]
    assert last.name == f"m.step{max_combo}.toml"
    last.write_text("mine")
    rc = main(["diagnose", "--resamples", "0", str(tmp_path / "missing.csv"), "--holdout", "1", "--max-combo", str(max_combo),
               "--save-model", str(m), "--save-steps"])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and last.name in err[0] and "missing.csv" not in err[0], err
    assert last.read_text() == "mine"
    # one step more is not checked: the data error comes first
    last.unlink()
    step_paths(m, max_combo + 2)[-1].write_text("mine")
    rc = main(["diagnose", "--resamples", "0", str(tmp_path / "missing.csv"), "--holdout", "1", "--max-combo", str(max_combo),
               "--save-model", str(m), "--save-steps"])
    assert rc == 2 and "missing.csv" in capsys.readouterr().err


def test_saved_model_records_the_command_line_and_the_data_hash(tmp_path):
    """The model file's provenance is the command as typed (``main(argv)``'s argv, not the process's) and the
    SHA-256 of the data file (hashlib on the bytes)."""
    import hashlib

    data, m = tmp_path / "d.csv", tmp_path / "m.toml"
    assert main(["simulate", str(data), "--cycles", "5", "--samples-per-cycle", "48", "--noise-F", "5"]) == 0
    argv = ["diagnose", "--resamples", "0", str(data), "--holdout", "3,7", "--max-combo", "1", "--save-model", str(m)]
    assert main(argv) == 0
    prov = load_model(m).info["provenance"]
    assert prov["command"] == "chainid " + " ".join(argv)
    assert prov["data_sha256"] == hashlib.sha256(data.read_bytes()).hexdigest()
    assert prov["data_file"] == str(data)


class _Reached(Exception):
    """Raised by a stand-in once the command has handed over its arguments."""


def test_diagnose_model_linear_hands_no_chain_model(chain_records, monkeypatch):
    """``diagnose --model linear`` diagnoses against a linear spring fitted to the data: the library is given no
    chain model (None); the default hands it the chain's.  Bug caught: ``== "linear"`` → ``> "linear"`` (the
    chain model used for --model linear)."""
    import importlib

    from chainid.model.base import ChainModel

    seen = []

    def stand_in(recs, holdout, model, **kw):  # noqa: ANN001
        seen.append(model)
        raise _Reached

    monkeypatch.setattr(importlib.import_module("chainid.gap.diagnose"), "diagnose", stand_in)
    for extra in (["--model", "linear"], []):
        with pytest.raises(_Reached):
            main(["diagnose", "--resamples", "0", str(chain_records), "--holdout", "3,7", "--quiet", *extra])
    assert seen[0] is None and isinstance(seen[1], ChainModel)


def test_step_files_are_outputs_only_with_save_steps(tmp_path):
    """``check_io``: the step files ``M.step0.toml`` … are outputs of the run only with ``--save-steps``; an input
    named like one is refused then (naming ``--save-steps``), and accepted without it.  Bug caught (seed 25):
    ``save_steps and save_model`` → ``or`` (the step files counted as outputs of every ``--save-model`` run)."""
    from argparse import Namespace

    from chainid.cli.common import check_io

    data = tmp_path / "m.step0.toml"
    data.write_text("x")
    check_io(Namespace(data=str(data), save_model=str(tmp_path / "m.toml"), save_steps=False))
    with pytest.raises(ValueError, match="--save-steps"):
        check_io(Namespace(data=str(data), save_model=str(tmp_path / "m.toml"), save_steps=True))
