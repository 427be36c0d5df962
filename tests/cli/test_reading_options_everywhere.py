"""The reading options on the commands that read records: ``--tests`` on identify, diagnose and predict (applied
after reading; an unmatched id is one error listing the valid ids), and the not-a-chain suggestion, which replaces
the chain's unit-slip and load warnings when no ``--chain`` was given (and goes into the JSON ``warnings``)."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from chainid.chain.spec import default_chain
from chainid.records.plausible import plausibility_warnings
from chainid.records.record import Record
from chainid.records.writer import write_canonical

SUGGEST = "these records do not look like a chain's"


def _seal_records():
    """Six rod-force records of a pneumatic seal: 40..67 N over a 42 mm stroke (positive: no compression)."""
    t = np.arange(3000) * 0.01
    out = []
    for k in range(6):
        f = 0.5 + 0.1 * k
        x = 17 + 21 * np.sin(2 * math.pi * f * t)
        out.append(Record(f"S{k}", t, x, 48 + 8 * np.tanh(20 * np.cos(2 * math.pi * f * t)) + 0.3 * x))
    return out


def _main(argv, capsys):
    from chainid.cli import main

    rc = main(argv)
    out, err = capsys.readouterr()
    return rc, out, err


def test_identify_suggests_linear_instead_of_the_chain_warnings(tmp_path, capsys):
    recs = _seal_records()
    chain_msgs = plausibility_warnings(recs, default_chain())
    assert any("span(F)/span(x)" in m for m in chain_msgs)  # what the chain checks would have said
    data = write_canonical(tmp_path / "seal.csv", recs)
    rc, out, err = _main(["identify", str(data), "--quiet", "--json", str(tmp_path / "id.json")], capsys)
    assert rc == 0, err
    assert err.count(SUGGEST) == 1 and "--model linear" in err
    assert "span(F)/span(x)" not in err and "--units" not in err and "exceeds" not in err
    doc = json.loads((tmp_path / "id.json").read_text())
    assert len(doc["warnings"]) == 1 and doc["warnings"][0].startswith(SUGGEST)
    rc, out, err = _main(["identify", str(data), "--quiet", "--chain", "din22252:14x50"], capsys)
    assert SUGGEST not in err and "span(F)/span(x)" in err  # a chain given: its checks run


def test_tests_selects_on_identify_diagnose_and_reports_unmatched_ids(tmp_path, capsys):
    data = write_canonical(tmp_path / "seal.csv", _seal_records())
    rc, out, err = _main(["identify", str(data), "--quiet", "--model", "linear", "--tests", "S9,S1"], capsys)
    assert rc == 2 and err.strip().endswith("--tests: 'S9' match(es) no test; valid ids: S0, S1, S2, S3, S4, S5")
    js = tmp_path / "dg.json"
    # (one effect at most: the selection of tests is what is pinned here, not the diagnosis)
    rc, out, err = _main(["diagnose", "--resamples", "0", "--max-combo", "1", str(data), "--model", "linear",
                          "--holdout", "S5", "--tests", "S[1-5]", "--json", str(js), "--quiet"], capsys)
    assert rc == 0, err
    doc = json.loads(js.read_text())
    assert [t["test"] for t in doc["tests"]] == ["S1", "S2", "S3", "S4", "S5"] and doc["holdout"] == ["S5"]


@pytest.mark.parametrize("cmd", ["identify", "diagnose", "predict", "convert", "audit"])
def test_every_reading_command_takes_the_new_options(cmd, capsys):
    from chainid.cli.parser import build_parser

    with pytest.raises(SystemExit):
        build_parser().parse_args([cmd, "--help"])
    text = capsys.readouterr().out
    for opt in ("--tests", "--derive", "--keep", "--reduce", "--covariate ", "--covariates", "--zero",
                "--header-marker", "--names", "--bad-lines", "--split-events", "--split-gap", "--segment-ids",
                "--segment-id"):
        assert opt in text, (cmd, opt)
