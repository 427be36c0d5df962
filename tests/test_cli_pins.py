"""CLI behaviours pinned through the command line itself (issue 20 §5): ``diagnose`` excluding an unusable test
(stderr line, JSON, ``--strict``), the documented ``--max-combo`` default.  Each test fails under the bug its
docstring names."""
from __future__ import annotations

import json
import re

import numpy as np
import pytest

from chainid.cli import main
from chainid.gap.benchmark.grid import grid3x3_plan
from chainid.model.base import ChainModel
from chainid.model.laws import PolynomialLaw
from chainid.records.files import write_records
from chainid.records.simulate import TestSpec, simulate, simulate_test
from repo_paths import REPO

MODEL = ChainModel()
LAW = PolynomialLaw([0.5, 1.0, 100.0, 20.0, 50.0])
README = REPO / "README.md"


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
    assert main(["diagnose", str(data), "--holdout", "3,7,11", "--max-combo", "1", "--json", str(out)]) == 0
    err = capsys.readouterr().err
    lines = [ln for ln in err.splitlines() if "excluded" in ln]
    assert len(lines) == 1 and "short" in lines[0]
    doc = json.loads(out.read_text())
    assert [e["test"] for e in doc["excluded"]] == ["short"] and doc["excluded"][0]["reason"]
    assert "short" not in [t["test"] for t in doc.get("tests", [])]
    assert main(["diagnose", str(data), "--holdout", "3,7,11", "--max-combo", "1", "--strict"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "short" in err[0] and "Traceback" not in err[0]


def test_cli_max_combo_default_is_the_documented_one(tmp_path, monkeypatch):
    """README and --help document ``--max-combo 3``; the CLI must pass 3 when the option is left out.
    Bug caught: a different default in the parser."""
    documented = int(re.search(r"\[--max-combo (\d)\]", README.read_text(encoding="utf-8")).group(1))
    assert documented == 3
    seen = {}

    import importlib

    dg = importlib.import_module("chainid.gap.diagnose")  # the module (the package exports a function of that name)

    def fake(records, holdout, model=None, **kw):
        seen.update(kw)
        raise ValueError("stop here")

    monkeypatch.setattr(dg, "diagnose", fake)
    data = _data(tmp_path, with_short=False)
    assert main(["diagnose", str(data), "--holdout", "3"]) == 2
    assert seen["max_combo"] == documented


def test_cli_benchmark_gap_exit_code(monkeypatch):
    """A finished benchmark exits 0 (the grid itself is replaced by a stand-in here).  Bug caught: rc 1."""
    import importlib

    bm = importlib.import_module("chainid.gap.benchmark.grid")
    monkeypatch.setattr(bm, "run_benchmark", lambda **kw: None)
    assert main(["benchmark-gap", "--small", "--no-progress"]) == 0


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
    assert main(["diagnose", str(data), "--holdout", "3", "--steady-tol", tol]) == 2
    err = capsys.readouterr().err
    assert ("stand-in stops here" in err) is ok and ("--steady-tol" in err) is (not ok)


def test_cli_chains_compare_labels_only_din_rows(capsys):
    """--compare: the DIN 22252 rows say their catalogue EA is the studless formula used as a reference; the
    mooring rows do not.  Bug caught: the label on the wrong rows."""
    assert main(["chains", "--compare"]) == 0
    out = capsys.readouterr().out
    comp = out[out.index("EA model N"):]
    din = [ln for ln in comp.splitlines() if ln.startswith("din22252:")]
    moor = [ln for ln in comp.splitlines() if ln.startswith(("studless:", "studlink:"))]
    assert din and moor
    assert all("(EA cat.: studless formula as reference)" in ln for ln in din)
    assert not any("studless formula as reference" in ln for ln in moor)


def test_cli_simulate_from_a_model_file(tmp_path, capsys):
    """simulate --model M.toml (a linear base, no effects) writes the paper's plan within the default memory limit
    (1 GiB) and names 'no effects'.  Bugs caught: the model-file option not registered, GiB mis-scaled (1024-3
    bytes), the 'no effects' fallback lost."""
    from chainid.model.augmented import AugmentedModel
    from chainid.model.modelfile import save_model
    from chainid.model.timedamping import Damping

    mf = tmp_path / "m.toml"
    save_model(AugmentedModel(LinearModel_(), [], Damping("viscous", {"c": 1.0}), 0.0, 0.0), mf)
    out = tmp_path / "r.csv"
    assert main(["simulate", str(out), "--model", str(mf), "--cycles", "3", "--samples-per-cycle", "32"]) == 0
    text = capsys.readouterr().out
    assert "no effects" in text and out.is_file()


def LinearModel_():
    from chainid.model.base import LinearModel

    return LinearModel(1e4, 0.0)


def test_predict_bad_model_file_is_one_line_and_exit_2(tmp_path, capsys):
    """``chainid predict`` on a model file that is not TOML: exit code 2 (bad input, the CLI contract) and one line
    on stderr naming the file; nothing on stdout."""
    from chainid.cli import main

    m, d = tmp_path / "m.toml", tmp_path / "d.csv"
    m.write_text("not = [toml\n")
    d.write_text("test,t,x,F\nT,0,1,1\nT,1,2,2\n")
    assert main(["predict", str(m), str(d)]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1
    assert err.startswith(f"chainid predict: error: model file {str(m)!r} is not valid TOML")


def test_simulate_default_laws_are_the_papers_eq28_and_eq27(tmp_path, capsys):
    """``chainid simulate`` without --params: the viscous law's c = 2834.4 N·s/mm (Eq. 27, test 3; the option's
    help) and the polynomial law's α = Eq. 28 as printed in the paper, (28.02, −651.57, −8386.50, 7394.84, 4378.89),
    whose c_e at each test of the paper plan the table states (Eq. 21 by hand with ω the plan's rad/s)."""
    from chainid.cli import main
    from chainid.records.simulate import paper_plan

    eq28 = (28.02, -651.57, -8386.50, 7394.84, 4378.89)
    assert main(["simulate", str(tmp_path / "v.csv"), "--cycles", "3"]) == 0
    assert "(law viscous [2834.4]," in capsys.readouterr().out
    assert main(["simulate", str(tmp_path / "p.csv"), "--law", "polynomial", "--cycles", "3"]) == 0
    out = capsys.readouterr().out
    assert f"(law polynomial {list(eq28)}," in out
    rows = [ln.split() for ln in out.splitlines()[2:11]]
    for s, row in zip(paper_plan(), rows):
        c = eq28[0] * s.omega ** 2 + eq28[1] * s.omega + eq28[2] * s.A ** 2 + eq28[3] * s.A + eq28[4]
        assert row[0] == s.test and float(row[4]) == pytest.approx(c, rel=1e-4)  # printed to 5 digits


def test_convert_refuses_an_unknown_output_suffix_before_reading(tmp_path, capsys):
    """``chainid convert --to``: the suffix names the format (.csv, .parquet or .pq); another suffix, or none,
    is one line naming it and the valid ones, exit 2, before the inputs are read (a missing input is not the
    error reported) and nothing written."""
    from chainid.records.writer import OUTPUT_FORMATS

    for to, shown in (("o.txt", "'.txt'"), ("o", "'(none)'"), ("o.CSV.gz", "'.gz'")):
        assert main(["convert", str(tmp_path / "missing.csv"), "--to", str(tmp_path / to)]) == 2
        err = capsys.readouterr().err
        assert err == (f"chainid convert: error: --to {str(tmp_path / to)!r}: unknown output suffix {shown}; "
                       f"valid: {', '.join(OUTPUT_FORMATS)}\n")
        assert not (tmp_path / to).exists()
    assert sorted(OUTPUT_FORMATS) == [".csv", ".parquet", ".pq"]


def test_a_file_system_fault_is_one_line_naming_the_file(monkeypatch, capsys):
    """An OSError escaping a command (a file system fault) is one line on stderr, exit 2, no traceback: with the
    file it concerns when the error names one, else the system's message alone."""
    import chainid.cli.convert as conv

    for exc, line in ((OSError(13, "Permission denied", "/data/out.csv"),
                       "chainid convert: error: '/data/out.csv' Permission denied\n"),
                      (OSError(28, "No space left on device"), "chainid convert: error: No space left on device\n")):
        def boom(args, exc=exc):
            raise exc
        monkeypatch.setattr(conv, "cmd_convert", boom)
        assert main(["convert", "in.csv", "--to", "out.csv"]) == 2
        assert capsys.readouterr().err == line


def test_generate_lists_every_file_with_its_status_and_a_stale_check_exits_1(tmp_path, capsys, monkeypatch):
    """``generate`` prints one line per generated file, its status right-aligned in 9 columns then the path; with
    ``--check`` a file that is not unchanged makes generated/ stale: exit 1 and one stderr line naming it (README:
    --check exits 1 when stale).  The emitter is stubbed (the CLI is under test)."""
    from chainid.derive import emit

    out = tmp_path / "gen"
    out.mkdir()
    monkeypatch.setattr(emit, "generate", lambda o, check=False: {"a.py": "unchanged", "b.py": "written"})
    assert main(["generate", "--check", "--out", str(out)]) == 1
    cap = capsys.readouterr()
    assert cap.out.splitlines() == [f"unchanged  {out / 'a.py'}", f"  written  {out / 'b.py'}"]
    assert cap.err == "generated/ is stale: b.py; run `chainid generate` and commit\n"
