"""``chainid audit --data``: the Eq. 28 audit on records simulated with a known damping law (issue 19).

References are the law's own numbers and closed forms of it (stationary points, minimum over the tested box,
the conversion of α to the paper's column unit ω·10/π), never the audit's output."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from chainid.cli import main
from chainid.model.laws import PolynomialLaw
from chainid.records.files import write_records
from chainid.records.simulate import paper_plan, simulate
from chainid.model.base import model_for

ALPHA = (100.0, -300.0, 2000.0, -500.0, 3000.0)  # c_e = 100 ω² - 300 ω + 2000 A² - 500 A + 3000 [N·s/mm]


@pytest.fixture(scope="module")
def records():
    return simulate(paper_plan(), model_for(None), PolynomialLaw(list(ALPHA)), ramp_rate=None, n_cycles=4,
                    samples_per_cycle=200)


def _audit(argv, tmp_path, capsys):
    out = tmp_path / "a.json"
    rc = main(["audit", *argv, "--json", str(out), "--quiet"])
    text, err = capsys.readouterr()
    return rc, (json.loads(out.read_text()) if out.exists() else None), text, err


def test_audit_data_recovers_the_law(records, tmp_path, capsys):
    p = write_records(tmp_path / "sim.csv", records)
    rc, rep, text, _ = _audit(["--data", str(p)], tmp_path, capsys)
    assert rc == 0 and rep["source"] == "data" and len(rep["tests"]) == 9 and rep["excluded"] == []
    # noise-free records: α back to 1e-6 (the identification's own error is ~1e-9 relative in c_e)
    np.testing.assert_allclose(rep["eq28_alpha"], ALPHA, rtol=1e-6)
    np.testing.assert_allclose(rep["eq28"]["alpha_normal_equations"], ALPHA, rtol=1e-6)
    s = math.pi / 10  # the paper's column unit: ω_col = ω / s, so α1 -> α1 s², α2 -> α2 s
    np.testing.assert_allclose(rep["eq28_column_unit"]["alpha"], [ALPHA[0] * s * s, ALPHA[1] * s, *ALPHA[2:]],
                               rtol=1e-6)
    f = {x["id"]: x["numbers"] for x in rep["findings"]}
    assert f["a"]["max_rel_deviation"] < 1e-9
    assert f["c"]["tests_with_compressive_minimum"] == []
    assert f["d"]["stationary_omega_rad_s"] == pytest.approx(300 / (2 * 100), rel=1e-6)  # -α2/(2α1) = 1.5
    assert f["d"]["stationary_A_mm"] == pytest.approx(500 / (2 * 2000), rel=1e-6)  # 0.125, below the tested A
    assert f["d"]["stationary_points_inside_range"] == ["omega"]
    w = [t.omega for t in paper_plan()]
    A = [t.A for t in paper_plan()]
    # minimum of the law over the tested box: ω = 1.5 (inside), A at its lower end (c rises with A beyond 0.125)
    cmin = 100 * 1.5 ** 2 - 300 * 1.5 + 2000 * min(A) ** 2 - 500 * min(A) + 3000
    assert min(w) < 1.5 < max(w)
    # on the audit's 41 x 41 grid the nearest ω is within 0.036 of 1.5: c is higher by <= 100·0.036² = 0.13 N·s/mm
    assert cmin - 1e-3 <= f["d"]["min_c_e_fit_in_range"] <= cmin + 0.13
    assert f["e"]["tests_generating_energy"] == []
    assert f["f"]["best_law"] == "polynomial"
    assert "Eq. 21 fitted to c_e of 9 identified test(s)" in text


def test_audit_data_through_the_reading_options(records, tmp_path, capsys):
    """The same tests as a rig writes them: one file per test, time in ms, displacement in inches, force in kN,
    the rig's column names; the audit through --columns/--units/--id-pattern gives the same law."""
    d = tmp_path / "rig"
    d.mkdir()
    for r in records:
        rows = "\n".join(f"{t * 1e3!r},{x / 25.4!r},{F / 1e3!r}" for t, x, F in zip(r.t.tolist(), r.x.tolist(),
                                                                              r.F.tolist()))
        (d / f"run_{r.test}.csv").write_text("Time,Disp,Load\n" + rows + "\n")
    rc, rep, _, err = _audit(["--data", str(d), "--columns", "t=Time,x=Disp,F=Load", "--units", "t=ms,x=in,F=kN",
                              "--id-pattern", r"run_(\d+)"], tmp_path, capsys)
    assert rc == 0, err
    assert sorted(t["test"] for t in rep["tests"]) == [str(i) for i in range(1, 10)]
    np.testing.assert_allclose(rep["eq28_alpha"], ALPHA, rtol=1e-6)
    # a force unit given for x is refused, one line, rc 2
    (tmp_path / "a.json").unlink()
    rc, rep, _, err = _audit(["--data", str(d), "--columns", "t=Time,x=Disp,F=Load", "--units", "x=kN"],
                             tmp_path, capsys)
    assert rc == 2 and rep is None and len(err.strip().splitlines()) == 1 and "kN" in err


def test_audit_data_needs_six_tests(records, tmp_path, capsys):
    p = write_records(tmp_path / "few.csv", records[:4])
    rc, rep, _, err = _audit(["--data", str(p)], tmp_path, capsys)
    assert rc == 2 and rep is None
    assert "at least 6 tests" in err and len(err.strip().splitlines()) == 1


def test_audit_without_data_is_table1(tmp_path, capsys):
    rc, rep, _, _ = _audit([], tmp_path, capsys)
    assert rc == 0 and "source" not in rep
    assert [round(a, 2) for a in rep["eq28_alpha"]] == pytest.approx([28.02, -651.57, -8386.5, 7394.84, 4378.89],
                                                                     abs=0.01)
