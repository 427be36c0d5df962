"""Tests left out with their reason: identify_records, `identify` JSON/stderr, --strict."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from chainid.model.laws import ViscousLaw
from chainid.damping.identify import identify_records
from chainid.records.files import Record, write_records
from chainid.records.simulate import TestSpec, simulate


class Lin:
    """Stand-in stiffness model F_k = k (x - x_ref) [N], k [N/mm]."""

    name = "stand-in linear"

    def __init__(self, k=20000.0, x_ref=1.0, mass_kg=0.0):
        self.k, self.x_ref, self.mass_kg = k, x_ref, mass_kg

    def force(self, x):
        return self.k * (np.asarray(x, float) - self.x_ref)

    def stiffness(self, x):
        return np.full(np.shape(x), self.k, dtype=float)


C_TRUE = 300.0  # N.s/mm


def _records():
    """8 good tests (viscous c = 300 N.s/mm) and one whose displacement is pure noise (no oscillation)."""
    plan = [TestSpec(f"T{i}", float(w), 2.2, float(a))
            for i, (w, a) in enumerate([(1.0, 0.2), (2.0, 0.2), (3.0, 0.2), (1.0, 0.3), (2.0, 0.3),
                                        (3.0, 0.3), (1.5, 0.25), (2.5, 0.25)])]
    model = Lin()
    recs = simulate(plan, model, ViscousLaw([C_TRUE]), seed=3, n_cycles=6, samples_per_cycle=100, ramp_rate=None)
    rng = np.random.default_rng(9)
    t = np.linspace(0.0, 30.0, 3000)
    x = 2.2 + rng.normal(0, 0.01, t.size)
    bad = Record("NOISE", t, x, model.force(x))
    return recs[:4] + [bad] + recs[4:], model


def test_identify_records_excludes_with_reason():
    recs, model = _records()
    res = identify_records(recs, model)
    assert [r.test for r in res] == [f"T{i}" for i in range(8)]
    assert len(res.excluded) == 1
    ex = res.excluded[0]
    assert ex["test"] == "NOISE"
    assert "amplitude below the noise" in ex["reason"] or "no harmonic oscillation" in ex["reason"]
    for r in res:  # the kept tests are unaffected: c_e within 1 % of the truth (noise-free simulation)
        assert r.c_e == pytest.approx(C_TRUE, rel=0.01)
        assert "cycle(s) kept" in r.steady and r.steady_tol == pytest.approx(0.03)
    with pytest.raises(ValueError, match=r"test 'NOISE'"):
        identify_records(recs, model, strict=True)


def test_identify_records_data_error_still_raises():
    recs, model = _records()
    recs[1].F[10] = math.nan
    with pytest.raises(ValueError, match=r"test 'T1': column 'F' has a NaN"):
        identify_records(recs, model)


def _cli(argv):
    from chainid.cli import main

    return main(argv)


def test_cli_identify_excluded_json_stderr_and_strict(tmp_path, capsys):
    recs, _ = _records()
    data = tmp_path / "d.csv"
    write_records(data, recs)
    out = tmp_path / "o.json"
    rc = _cli(["identify", str(data), "--model", "linear", "--k", "20000", "--x-ref", "1", "--mass", "0",
               "--law", "viscous", "--json", str(out), "--quiet"])
    err = capsys.readouterr().err
    assert rc == 0
    doc = json.loads(out.read_text())
    assert [e["test"] for e in doc["excluded"]] == ["NOISE"]
    assert doc["excluded"][0]["reason"]
    assert len(doc["tests"]) == 8
    assert doc["law"]["params"][0] == pytest.approx(C_TRUE, rel=0.01)
    lines = [ln for ln in err.splitlines() if ln.startswith("excluded test")]
    assert len(lines) == 1 and lines[0].startswith("excluded test NOISE: ")
    rc = _cli(["identify", str(data), "--model", "linear", "--k", "20000", "--x-ref", "1", "--mass", "0",
               "--strict", "--quiet"])
    err = capsys.readouterr().err
    assert rc == 2
    assert "--strict: 1 test(s) could not be identified: NOISE" in err


def test_cli_identify_too_few_tests_left(tmp_path, capsys):
    recs, _ = _records()
    data = tmp_path / "d.csv"
    write_records(data, recs[:5])  # 4 good + NOISE -> 4 < 6 tests for a law
    rc = _cli(["identify", str(data), "--model", "linear", "--k", "20000", "--x-ref", "1", "--quiet"])
    err = capsys.readouterr().err
    assert rc == 2
    assert "only 4 test(s) identified (1 excluded)" in err


@pytest.mark.parametrize("tol, ok", [("5%", 0.05), ("0.05", 0.05), ("auto", None)])
def test_cli_steady_tol_parsing(tol, ok):
    from chainid.cli.identify import _steady_tol

    assert _steady_tol(tol) == ok


@pytest.mark.parametrize("tol", ["0", "1.5", "150%", "abc", "nan"])
def test_cli_steady_tol_rejects(tol):
    from chainid.cli.identify import _steady_tol

    with pytest.raises(ValueError, match="--steady-tol"):
        _steady_tol(tol)
