"""More pins of the damping package's weak spots (issue 20 §5, own mutation seeds of mutH): the identification's
finiteness rule, the audit's text table and its remaining numbers, the ``audit --data`` findings' texts.
References are hand computations (numpy's lstsq on the shipped Table 1, Eq. 21 on hand-made tests) and the
documented contract.  Units: mm, N, s, kg; c_e N·s/mm."""
from __future__ import annotations

import math

import numpy as np
import pytest

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


def test_identify_records_needs_both_c_e_and_f_ac_finite(monkeypatch):
    """A test is kept only when c_e AND F_ac are finite (a finite F_ac over an ω·A that underflows gives c_e = inf;
    the rule is stated for both).  Bug caught: the rule weakened to "either is finite"."""
    import chainid.damping.identify as ident
    from chainid.records.simulate import TestSpec, simulate
    from chainid.model.laws import ViscousLaw

    recs = simulate([TestSpec("T0", 2.0, 2.2, 0.2), TestSpec("T1", 3.0, 2.2, 0.2)], Lin(), ViscousLaw([300.0]),
                    n_cycles=4, samples_per_cycle=100, ramp_rate=None)
    real = ident.identify_test
    for bad in (dict(c_e=math.inf, F_ac=5.0), dict(c_e=5.0, F_ac=math.nan)):
        def fake(rec, model, **kw):
            r = real(rec, model, **kw)
            if rec.test == "T1":
                r.c_e, r.F_ac = bad["c_e"], bad["F_ac"]
            return r
        monkeypatch.setattr(ident, "identify_test", fake)
        res = ident.identify_records(recs, Lin())
        assert [r.test for r in res] == ["T0"]
        assert res.excluded == [{"test": "T1", "reason": f"damping estimate is not finite (c_e = {bad['c_e']!r} N.s/mm)"}]


def test_identify_test_and_linear_spring_refuse_records_without_a_steady_cycle():
    """No steady whole cycle: identify_test names the test; the linear-spring fit says why it cannot start.
    A constant force has R² = 1 by definition (nothing to explain), not a division by zero."""
    from types import SimpleNamespace

    from chainid.damping.identify import fit_harmonic, identify_test, linear_model_from_records
    from chainid.records.record import Record

    t = np.linspace(0.0, 1.0, 50)
    rec = Record("Z9", t, 2.0 + 0.0 * t, 1e4 * (2.0 + 0.0 * t))
    with pytest.raises(ValueError, match=r"test 'Z9': no steady whole cycle to identify from"):
        identify_test(rec, Lin(), estimate=SimpleNamespace(window=None))
    with pytest.raises(ValueError, match=r"test 'Z9': no steady whole cycle"):
        identify_test(rec, Lin(), estimate=SimpleNamespace(window=SimpleNamespace(n_cycles=0)))
    with pytest.raises(ValueError, match=r"no test has steady cycles: cannot fit the linear spring \(--model linear "
                                         r"without --k\)"):
        linear_model_from_records([rec])
    h = fit_harmonic(np.linspace(0.0, 6.0, 40), np.full(40, 7.5))
    assert h.r2 == 1.0 and h.F0 == pytest.approx(7.5, rel=1e-12) and h.FA == pytest.approx(0.0, abs=1e-9)


def test_format_audit_table_is_eq21_fitted_by_hand_on_table1():
    """format_audit's table: rows alpha1..alpha5 with the lstsq fit, the normal-equations fit (G α = C), the paper's
    Eq. 28 and the standard error sqrt(s²·diag((XᵀX)⁻¹)), s² = RSS/(n − 5); then cond(X), cond(G), RMSE, LOO RMSE
    (hat-matrix leave-one-out) and the same fit with ω = (π/10)·column; all computed here with numpy from the
    shipped Table 1 (itself pinned against the paper by test_audit.py).  "NO" when the 4-digit check fails."""
    from chainid.damping.audit import EQ28_PAPER, audit, format_audit, load_table1

    tb = load_table1()
    w, A, c = tb["omega_col"].astype(float), tb["A"].astype(float), tb["c_e"].astype(float)

    def design(ww):
        return np.column_stack([ww ** 2, ww, A ** 2, A, np.ones_like(ww)])
    X = design(w)
    al = np.linalg.lstsq(X, c, rcond=None)[0]
    G = X.T @ X
    an = np.linalg.solve(G, X.T @ c)
    r = c - X @ al
    se = np.sqrt(np.diag(r @ r / (len(c) - 5) * np.linalg.inv(G)))
    h = np.einsum("ij,jk,ik->i", X, np.linalg.inv(G), X)
    loo = math.sqrt(np.mean((r / (1 - h)) ** 2))
    alr = np.linalg.lstsq(design(w * S), c, rcond=None)[0]

    rep = audit(Lin())
    text = format_audit(rep).splitlines()
    assert text[0] == "Eq. 28 reproduced from Table 1 (omega = table column, Eq. 22-24):"
    assert text[1].split() == ["computed", "normal", "eq.", "paper", "std", "err"]
    rows = [ln.split() for ln in text[2:7]]
    assert [x[0] for x in rows] == ["alpha1", "alpha2", "alpha3", "alpha4", "alpha5"]
    got = np.array([[float(v) for v in x[1:]] for x in rows])
    np.testing.assert_allclose(got[:, 0], al, rtol=2e-6)
    np.testing.assert_allclose(got[:, 1], an, rtol=1e-4)  # ill-conditioned G: 6 digits of a near-equal solution
    np.testing.assert_allclose(got[:, 2], EQ28_PAPER, rtol=1e-9)
    np.testing.assert_allclose(got[:, 3], se, rtol=5e-4)  # printed to 4 digits: at most 5e-4 off
    assert text[7] == "  matches the paper to 4 significant figures: yes"
    m = [float(v.rstrip(",")) for v in text[8].replace("=", " ").split() if v.rstrip(",").replace(".", "", 1)
         .replace("e+", "", 1).replace("e-", "", 1).isdigit()]
    np.testing.assert_allclose(m, [np.linalg.cond(X), np.linalg.cond(G), math.sqrt(np.mean(r ** 2)), loo], rtol=1e-3)
    assert text[8].startswith("  cond(X) = ") and "N s/mm, LOO RMSE = " in text[8]
    assert text[9].startswith("  same fit with omega in rad/s (pi/10 x column): ")
    np.testing.assert_allclose([float(v) for v in text[9].split(": ")[1].split(", ")], alr, rtol=1e-4)
    rep["eq28_matches_4sf"] = False
    assert "  matches the paper to 4 significant figures: NO" in format_audit(rep)


def test_audit_numbers_of_findings_a_and_b_by_hand():
    """Finding (a): the mean factor of tests 2–9 over π/10; finding (b): test 1's tabulated F_ac = 8000 N and
    c_e = 5095.5 N·s/mm, the c_e that F_ac implies at ω = 0.1π rad/s, A = 0.25 mm, and its factor over the table's;
    eq28() states the ω scale it used.  sig_round: 4 significant figures, 0 and non-finite values unchanged."""
    from chainid.damping.audit import audit, eq28, load_table1, sig_round

    tb = load_table1()
    f = {x["id"]: x["numbers"] for x in audit(Lin())["findings"]}
    fac = (tb["F_ac"] / (tb["c_e"] * tb["A"] * tb["omega_col"]))[1:]
    assert f["a"]["factor_mean_over_pi_10"] == pytest.approx(fac.mean() / S, rel=1e-12)
    ce1 = 8000.0 / (0.1 * math.pi * 0.25)
    assert (f["b"]["F_ac_table"], f["b"]["c_e_table"]) == (8000.0, 5095.5)
    assert f["b"]["omega_rad_s"] == pytest.approx(0.1 * math.pi, rel=1e-12)
    assert f["b"]["c_e_implied_by_F_ac"] == pytest.approx(ce1, rel=1e-12)
    assert f["b"]["factor"] == pytest.approx(ce1 / 5095.5, rel=1e-12)
    assert eq28(S)["omega_scale"] == S and eq28()["omega_scale"] == 1.0
    assert sig_round(12345.678) == 12350.0 and sig_round(-0.00123456) == -0.001235 and sig_round(0.5, 2) == 0.5
    assert sig_round(0) == 0 and sig_round(math.inf) == math.inf and math.isnan(sig_round(math.nan))


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


def test_test_result_json_writes_non_finite_numbers_as_null():
    """TestResult.to_dict: the contract's strict JSON: every non-finite float (the NaN defaults of a hand-made
    result: W_ratio, r2_c, F_as, Fc0, steady_tol; an infinite c_e) is None; t_origin is not a key; θ is unchanged
    when the record starts at t = 0."""
    from chainid.damping.identify import TestResult

    r = TestResult("T", 10.0, 2.0, 0.3, 2e4, 3e3, 0.1, 0.99, 300.0, math.inf, 50.0, theta=0.7)
    d = r.to_dict()
    assert [d[k] for k in ("W_ratio", "r2_c", "F_as", "Fc0", "steady_tol", "c_e")] == [None] * 6
    assert "t_origin" not in d and d["theta"] == 0.7 and d["W"] == 50.0 and d["F_ac"] == 300.0


def test_a_loop_without_damping_has_no_energy_ratio():
    """A record whose force is exactly the spring's (F = k·x, no mass): F_c ≡ 0, so c_e = F_ac = 0 and the ratio
    W/(π c_e ω A²) has no value: NaN (null in the JSON), not a division by zero."""
    from chainid.damping.identify import identify_test
    from chainid.records.record import Record

    t = np.linspace(0.0, 8.0, 1601)
    x = 2.2 + 0.25 * np.sin(2 * math.pi * 0.5 * t)
    rec = Record("E", t, x, 10000.0 * x)
    r = identify_test(rec, Lin(), mass_kg=0.0)
    assert r.c_e == 0.0 and r.F_ac == 0.0 and math.isnan(r.W_ratio) and r.to_dict()["W_ratio"] is None


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
