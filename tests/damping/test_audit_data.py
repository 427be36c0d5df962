"""``chainid audit --data`` (chainid.damping.audit_data): the Eq. 28 audit on records simulated with a known damping
law, and on hand-made test results.

References are the law's own numbers and closed forms of it (stationary points, minimum over the tested box,
the conversion of α to the paper's column unit ω·10/π), never the audit's output."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from chainid.cli import main
from chainid.model.base import model_for
from chainid.model.laws import PolynomialLaw
from chainid.records.files import write_records
from chainid.records.simulate import paper_plan, simulate

from stand_ins import LinearSpring


S = math.pi / 10  # ω [rad/s] = (π/10) × Table 1's column


def Lin():
    return LinearSpring(10000.0)


def _tests(alpha, grid=((1.0, 0.2), (2.0, 0.2), (3.0, 0.2), (1.0, 0.3), (2.0, 0.3), (3.0, 0.3), (1.0, 0.4),
                        (2.0, 0.4), (3.0, 0.4))):
    """Nine hand-made identified tests whose c_e follow Eq. 21 with ``alpha`` exactly (F_ac = c_e ω A,
    W = π c_e ω A², F0 = 20 kN, F_A = 8000·A N)."""
    from chainid.damping.identify import TestResult

    out = []
    for n, (w, A) in enumerate(grid):
        c = alpha[0] * w * w + alpha[1] * w + alpha[2] * A * A + alpha[3] * A + alpha[4]
        out.append(TestResult(test=str(n + 1), omega=w, x0=2.2, A=A, F0=20000.0, FA=8000.0 * A, phi=0.1, r2=1.0,
                              F_ac=c * w * A, c_e=c, W=math.pi * c * w * A * A))
    return out


def test_audit_data_findings_a_c_e_texts_by_hand():
    """audit --data's findings on hand-made tests: (a) F_ac/(c_e ω A) per test and its largest deviation from 1
    (one test's F_ac made 10 % high: 1.1, deviation 0.1); (c) F_A/A = 8000 N/mm against k_e = 1e4: 0.8 x, and
    F0 − F_A = 20000 − 8000·0.4 = 16800 N > 0, or test 7 compressed (F0 = 1000 < F_A = 3200); (e) F_ac <= 0 or
    W <= 0 flags a test (0 itself counts: nothing dissipated)."""
    from chainid.damping.audit_data import audit_results

    alpha = (100.0, -300.0, 2000.0, -500.0, 3000.0)
    rep = audit_results(_tests(alpha), Lin())
    f = {x["id"]: x for x in rep["findings"]}
    np.testing.assert_allclose(f["a"]["numbers"]["F_ac_over_ce_omega_A"], np.ones(9), rtol=1e-12)
    assert f["c"]["numbers"]["ratio_dynamic_over_k_e"] == pytest.approx([0.8] * 9, rel=1e-12)
    assert f["c"]["summary"] == ("F_A/A is 0.8-0.8 x the model's k_e(x0) (stand-in linear). "
                                 "F0 - F_A >= 1.68e+04 N > 0: no test compresses.")
    assert f["e"]["summary"] == "F_ac > 0 and W > 0 in every test: the loops dissipate."
    tests = _tests(alpha)
    tests[2].F_ac *= 1.1
    tests[6].F0, tests[6].FA = 1000.0, 3200.0
    tests[4].F_ac = 0.0
    tests[8].W = 0.0
    rep = audit_results(tests, None)
    f = {x["id"]: x for x in rep["findings"]}
    assert f["a"]["numbers"]["F_ac_over_ce_omega_A"][2] == pytest.approx(1.1, rel=1e-12)
    assert f["a"]["numbers"]["max_rel_deviation"] == pytest.approx(1.0, rel=1e-12)  # test 5: F_ac = 0
    assert f["a"]["summary"].startswith("F_ac/(c_e omega A) is 1 within 1 for every test: omega is in rad/s")
    assert f["c"]["summary"] == "F0 - F_A < 0 (compression) in test(s) 7."
    assert "k_e_at_x0_N_per_mm" not in f["c"]["numbers"]
    assert f["c"]["numbers"]["F_min_N"][6] == -2200.0
    assert f["e"]["numbers"]["tests_generating_energy"] == ["5", "9"]
    assert f["e"]["summary"] == "F_ac <= 0 or W <= 0 (energy generated) in test(s) 5, 9."


def test_audit_data_stationary_points_inside_the_box_and_the_text_table():
    """(d): Eq. 21 with α = (100, −300, 2000, −1200, 3000) is stationary at ω = 300/200 = 1.5 rad/s and
    A = 1200/4000 = 0.3 mm, both inside the tested 1–3 rad/s × 0.2–0.4 mm (strictly); its minimum there is
    3000 − 225 − 180 = 2595 N·s/mm (both on the 41-point grid).  The text: a header, rows alpha1..5 with lstsq,
    normal equations, std err, the column-unit fit (α1·s², α2·s, α3..5 with s = π/10) and the paper's Eq. 28; the
    excluded tests with their reasons."""
    from chainid.damping.audit import EQ28_PAPER
    from chainid.damping.audit_data import audit_results, format_audit_data

    alpha = (100.0, -300.0, 2000.0, -1200.0, 3000.0)
    rep = audit_results(_tests(alpha), Lin())
    d = {x["id"]: x for x in rep["findings"]}["d"]
    assert d["numbers"]["stationary_points_inside_range"] == ["omega", "A"]
    assert d["numbers"]["stationary_A_mm"] == pytest.approx(0.3, rel=1e-9)
    assert d["numbers"]["min_c_e_fit_in_range"] == pytest.approx(2595.0, rel=1e-9)
    assert d["summary"] == ("Tests cover omega 1-3 rad/s and A 0.2-0.4 mm; Eq. 21 is stationary at omega = 1.5 rad/s "
                            "and A = 0.3 mm (inside the tested range: omega, A); its minimum over the tested range is "
                            "2595 N s/mm. Outside the range it extrapolates.")
    rep2 = audit_results(_tests((100.0, -900.0, 2000.0, -1800.0, 3000.0)), Lin())  # ω* = 4.5, A* = 0.45: outside
    assert {x["id"]: x for x in rep2["findings"]}["d"]["numbers"]["stationary_points_inside_range"] == []
    rep["excluded"] = [{"test": "T10", "reason": "0 steady cycles"}, {"test": "T11", "reason": "x is constant"}]
    text = format_audit_data(rep).splitlines()
    assert text[0] == "Eq. 21 fitted to c_e of 9 identified test(s) (Eq. 22-24; omega rad/s):"
    assert text[1].split() == ["lstsq", "normal", "eq.", "std", "err", "omega=20f", "paper"]
    rows = np.array([[float(v) for v in ln.split()[1:]] for ln in text[2:7]])
    np.testing.assert_allclose(rows[:, 0], alpha, rtol=1e-5)
    np.testing.assert_allclose(rows[:, 1], alpha, rtol=1e-4)
    assert np.all(np.abs(rows[:, 2]) < 1e-6)  # exact data: no scatter
    np.testing.assert_allclose(rows[:, 3], [alpha[0] * S * S, alpha[1] * S, *alpha[2:]], rtol=1e-5)
    np.testing.assert_allclose(rows[:, 4], EQ28_PAPER, rtol=1e-9)
    assert text[7].startswith("  cond(X) = ")
    assert text[-1] == "2 test(s) excluded: T10 (0 steady cycles); T11 (x is constant)"


# ---------------------------------------------------------------- survivors of the blind seed-23 run
def test_audit_data_positive_minimum_below_one_is_not_unphysical():
    """(d) on Eq. 21 with α = (100, −300, 2000, −1200, 405.5): stationary at ω = 1.5 rad/s, A = 0.3 mm, where
    c = 225 − 450 + 180 − 360 + 405.5 = 0.5 N·s/mm (by hand, on the 41-point grid): positive, so the text
    names the minimum and calls nothing unphysical; α5 = 404.5 gives −0.5: '<= 0: unphysical'.  Bug caught:
    the rule ``cmin <= 0`` → ``cmin <= 1``."""
    from chainid.damping.audit_data import audit_results

    for a5, cmin, bad in ((405.5, 0.5, False), (404.5, -0.5, True)):
        rep = audit_results(_tests((100.0, -300.0, 2000.0, -1200.0, a5)), Lin())
        d = {x["id"]: x for x in rep["findings"]}["d"]
        assert f"its minimum over the tested range is {cmin:.4g} N s/mm" in d["summary"]
        assert ("<= 0: unphysical" in d["summary"]) is bad


def test_audit_data_polynomial_loo_rmse_is_eq21s_own_when_another_law_ranks_first():
    """(f) on tests whose c_e = 4·F_f/(π ω A) exactly (F_f = 50 N): the Coulomb law ranks first (its
    leave-one-out error is 0) and the finding still quotes Eq. 21's own leave-one-out RMSE: numpy's lstsq on
    [ω², ω, A², A, 1] refitted nine times with one test left out, by hand.  Bug caught: the row picked by
    ``law <= "polynomial"`` (the first law sorting before it: coulomb) instead of ``== "polynomial"``."""
    from chainid.damping.audit_data import audit_results

    tests = _tests((0.0, 0.0, 0.0, 0.0, 0.0))
    for r in tests:
        r.c_e = 4 * 50.0 / (math.pi * r.omega * r.A)
        r.F_ac, r.W = r.c_e * r.omega * r.A, math.pi * r.c_e * r.omega * r.A * r.A
    f = {x["id"]: x for x in audit_results(tests, Lin())["findings"]}["f"]
    assert f["numbers"]["best_law"] == "coulomb"
    w = np.array([r.omega for r in tests])
    A = np.array([r.A for r in tests])
    c = np.array([r.c_e for r in tests])
    X = np.column_stack([w**2, w, A**2, A, np.ones(9)])
    res = []
    for i in range(9):
        keep = np.arange(9) != i
        beta = np.linalg.lstsq(X[keep], c[keep], rcond=None)[0]
        res.append(c[i] - X[i] @ beta)
    want = math.sqrt(np.mean(np.square(res)))
    assert want > 0.1  # Eq. 21 cannot follow 1/(ωA) exactly
    assert f["numbers"]["polynomial_loo_rmse"] == pytest.approx(want, rel=1e-9)


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


@pytest.mark.slow
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


def _exact_law_tests(alpha):
    """Nine hand-made identified tests (ω 1–3 rad/s × A 0.2–0.4 mm) whose c_e follow Eq. 21 with ``alpha`` exactly
    (F_ac = c_e ω A, W = π c_e ω A²)."""
    from chainid.damping.identify import TestResult

    tests = []
    for n, (w, A) in enumerate([(1.0, 0.2), (2.0, 0.2), (3.0, 0.2), (1.0, 0.3), (2.0, 0.3), (3.0, 0.3),
                                (1.0, 0.4), (2.0, 0.4), (3.0, 0.4)]):
        c = alpha[0] * w * w + alpha[1] * w + alpha[2] * A * A + alpha[3] * A + alpha[4]
        tests.append(TestResult(test=str(n + 1), omega=w, x0=2.2, A=A, F0=20000.0, FA=8000.0 * A, phi=0.1, r2=1.0,
                                F_ac=c * w * A, c_e=c, W=math.pi * c * w * A * A))
    return tests


def test_audit_data_text_numbers_alpha1_to_alpha5():
    """``format_audit_data``: one row per Eq. 21 coefficient, named alpha1 … alpha5 in order, each with the fitted
    value; fed with nine hand-made tests whose c_e follow c_e = 100 ω² − 300 ω + 2000 A² − 500 A + 3000 exactly,
    so each row's lstsq value is the law's α to 6 digits.
    Bug caught: the row label's index (i + 1)."""
    from chainid.damping.audit_data import audit_results, format_audit_data

    alpha = (100.0, -300.0, 2000.0, -500.0, 3000.0)
    rep = audit_results(_exact_law_tests(alpha), Lin())
    rep["excluded"] = []
    rows = [ln.split() for ln in format_audit_data(rep).splitlines() if ln.strip().startswith("alpha")]
    assert [r[0] for r in rows] == ["alpha1", "alpha2", "alpha3", "alpha4", "alpha5"]
    np.testing.assert_allclose([float(r[1]) for r in rows], alpha, rtol=1e-5)


def test_audit_data_finding_f_is_eq21_and_d_flags_a_negative_damping():
    """On tests that follow an Eq. 21 law exactly, finding (f) reports the polynomial law's own leave-one-out error,
    which is ~0 (every other law misses the law's curvature by far more: > 1 N·s/mm here), and its summary quotes
    it; finding (d) flags a fitted c_e <= 0 over the tested box as unphysical (c = 100 ω² − 400 ω + 350 is −50 at
    ω = 2 inside the box) and is silent for a positive one (the law of the previous test: 2755 at ω = 1.5, A = 0.2 by hand).
    Bugs caught: (f) quoting another law's error, the unphysical note inverted or dropped."""
    from chainid.damping.audit_data import audit_results

    rep = audit_results(_exact_law_tests((100.0, -300.0, 2000.0, -500.0, 3000.0)), Lin())
    f = {x["id"]: x for x in rep["findings"]}
    loo = f["f"]["numbers"]["polynomial_loo_rmse"]
    assert f["f"]["numbers"]["best_law"] == "polynomial" and loo < 1e-6
    others = [r["loo_rmse"] for r in rep["ranking"] if r["law"] != "polynomial"]
    assert others and min(others) > 1.0
    assert f"Eq. 21 (polynomial) {loo:.4g} N s/mm against {loo:.4g}." in f["f"]["summary"]
    assert "unphysical" not in f["d"]["summary"] 
    assert f["d"]["numbers"]["min_c_e_fit_in_range"] == pytest.approx(2755.0, abs=1e-6)
    rep = audit_results(_exact_law_tests((100.0, -400.0, 0.0, 0.0, 350.0)), Lin())
    d = {x["id"]: x for x in rep["findings"]}["d"]
    assert d["numbers"]["min_c_e_fit_in_range"] == pytest.approx(-50.0, abs=1e-6)
    assert "minimum over the tested range is -50 N s/mm <= 0: unphysical." in d["summary"]


def test_audit_records_takes_the_records_and_model_by_keyword_and_its_options_only_by_keyword(records):
    """``audit_records(records, model, *, mass_kg=…, …)``: the first two may be named, the options must be (a
    positional third argument would silently become the mass of a later signature).  Seed-29 survivor: the ``*``
    turned into ``/`` (positional-only records and model, a positional mass) passed every call in the suite."""
    from chainid.damping.audit_data import audit_records

    rep = audit_records(records=records, model=model_for(None))
    np.testing.assert_allclose(rep["eq28_alpha"], ALPHA, rtol=1e-6)
    with pytest.raises(TypeError):
        audit_records(records, model_for(None), 2.0)
