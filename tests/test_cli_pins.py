"""CLI behaviours pinned through the command line itself (issue 20 §5): ``diagnose`` excluding an unusable test
(stderr line, JSON, ``--strict``), the documented ``--max-combo`` default.  Each test fails under the bug its
docstring names."""
from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

from chainid.cli import main
from chainid.gap.benchmark import grid3x3_plan
from chainid.model.base import ChainModel
from chainid.model.laws import PolynomialLaw
from chainid.records.files import write_records
from chainid.records.simulate import TestSpec, simulate, simulate_test

MODEL = ChainModel()
LAW = PolynomialLaw([0.5, 1.0, 100.0, 20.0, 50.0])
README = Path(__file__).resolve().parents[1] / "README.md"


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
