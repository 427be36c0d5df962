"""``chainid audit --data`` with a fitted linear spring names each excluded test."""
from __future__ import annotations

import json

import numpy as np

from chainid.cli import main
from chainid.model.base import LinearModel
from chainid.records.files import write_records
from chainid.records.simulate import TestSpec, simulate


SPRING = LinearModel(k=200.0, x_ref=0.0, mass=0.0)


def test_audit_data_with_a_fitted_linear_spring_names_each_excluded_test(tmp_path, capsys):
    """``audit --data R --model linear`` without ``--k`` fits the spring on the records (as ``identify`` does) and
    audits Eq. 21 on the c_e identified through it: nine tests of a spring 200 N/mm and the law c_e = 2 ω² − 3 ω +
    50 A² − 10 A + 20 [N·s/mm] give the law's α back (rtol 1e-3); a tenth test with no oscillation is left out, one
    ``excluded test ID: reason`` line on stderr and in the JSON's ``excluded``.
    Bugs caught: the linear spring not fitted, the exclusion lines dropped, the data path not in the report."""
    from chainid.model.laws import PolynomialLaw
    from chainid.records.files import Record

    alpha = [2.0, -3.0, 50.0, -10.0, 20.0]
    plan = [TestSpec(f"T{i}", w, 2.0, A) for i, (w, A) in enumerate(
        [(w, A) for w in (1.0, 2.0, 4.0) for A in (0.1, 0.2, 0.3)])]
    recs = simulate(plan, SPRING, PolynomialLaw(alpha), n_cycles=4, samples_per_cycle=100, ramp_rate=None)
    t = np.linspace(0.0, 20.0, 2000)
    x = 2.0 + np.random.default_rng(4).normal(0.0, 1e-3, t.size)
    recs.append(Record("FLAT", t, x, 200.0 * x))
    data = write_records(tmp_path / "d.csv", recs)
    out = tmp_path / "a.json"
    assert main(["audit", "--data", str(data), "--model", "linear", "--mass", "0", "--json", str(out), "--quiet"]) == 0
    err = [ln for ln in capsys.readouterr().err.splitlines() if ln.startswith("excluded test")]
    assert len(err) == 1 and err[0].startswith("excluded test FLAT: ")
    doc = json.loads(out.read_text())
    assert [e["test"] for e in doc["excluded"]] == ["FLAT"] and len(doc["tests"]) == 9
    assert doc["data"] == str(data)
    np.testing.assert_allclose(doc["eq28_alpha"], alpha, rtol=1e-3)
