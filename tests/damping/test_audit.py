"""Audit of the paper's Table 1 / Eq. 25–28 (chainid.damping.audit): each finding's numbers by hand, the fitted
table, and the identify/simulate/audit CLI."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from chainid.cli.identify import main as cli
from chainid.damping.audit import EQ28_PAPER, VALIDATION, audit, eq28, format_audit, load_table1

import paper_forms
from stand_ins import LinearSpring


def Lin():
    """The closed-form spring of these tests: F = 10000·x."""
    return LinearSpring(10000.0)


def _models_available():
    try:
        from chainid.model import base as models  # noqa: F401
    except ImportError:
        return False
    return hasattr(models, "model_for") and hasattr(models, "LinearModel")


needs_models = pytest.mark.skipif(not _models_available(), reason="chainid.model.base (lead's module) not available yet")


def four_sf(v):
    return float(f"{v:.4g}")


def test_table1_shipped():
    tb = load_table1()
    assert tb["test"].tolist() == list(range(1, 10))
    assert tb["omega_col"].tolist() == [1, 4, 6, 8, 10, 6, 6, 6, 6]
    assert tb["c_e"][2] == 2834.4 and tb["F_ac"][2] == 1335


def test_eq28_reproduced_to_4_significant_figures():
    e = eq28()
    assert [four_sf(a) for a in e["alpha"]] == [four_sf(p) for p in EQ28_PAPER]
    # paper's normal equations (Eq. 23) and lstsq agree; the system is ill-conditioned
    np.testing.assert_allclose(e["alpha_normal_equations"], e["alpha"], rtol=1e-6)
    assert e["cond_G"] > 1e8
    rep = audit(Lin())
    assert rep["eq28_matches_4sf"] is True
    assert [four_sf(a) for a in rep["eq28_alpha"]] == [28.02, -651.6, -8386.0, 7395.0, 4379.0]


# Table 1 as printed (test, omega column, x0 mm, A mm, F_ac N, c_e N s/mm), typed from the paper
TABLE1 = [(1, 1, 2.2, 0.25, 8000, 5095.5), (2, 4, 2.2, 0.25, 1100, 3503.2), (3, 6, 2.2, 0.25, 1335, 2834.4),
          (4, 8, 2.2, 0.25, 1465, 2332.8), (5, 10, 2.2, 0.25, 1542, 1964.3), (6, 6, 2.15, 0.2, 985, 2614.1),
          (7, 6, 2.25, 0.3, 1643, 2906.9), (8, 6, 2.3, 0.35, 2017, 3058.8), (9, 6, 2.35, 0.4, 2329, 3090.5)]


def test_eq28_standard_errors_textbook():
    """Eq. 21 fitted to Table 1 (omega = printed column, as the paper did): parameters from the normal equations
    and standard errors s^2 (X'X)^-1 with s^2 = RSS/(M - 5), computed here in plain numpy."""
    w = np.array([r[1] for r in TABLE1], float)
    A = np.array([r[3] for r in TABLE1], float)
    c = np.array([r[5] for r in TABLE1], float)
    X = np.column_stack([w**2, w, A**2, A, np.ones(9)])
    G = X.T @ X
    beta = np.linalg.solve(G, X.T @ c)
    s2 = float(np.sum((c - X @ beta) ** 2)) / (9 - 5)
    se = np.sqrt(s2 * np.diag(np.linalg.inv(G)))
    e = eq28()
    np.testing.assert_allclose(e["alpha"], beta, rtol=1e-6)
    np.testing.assert_allclose(e["stderr"], se, rtol=1e-6)
    assert [four_sf(v) for v in beta] == [four_sf(v) for v in EQ28_PAPER]


def test_table1_matches_the_paper():
    tb = load_table1()
    for col, i in (("test", 0), ("omega_col", 1), ("x0", 2), ("A", 3), ("F_ac", 4), ("c_e", 5)):
        assert tb[col].tolist() == [r[i] for r in TABLE1], col


def test_finding_a_omega_unit():
    f = {x["id"]: x for x in audit(Lin())["findings"]}["a"]["numbers"]
    # omega implied by Eq. 27, F_ac/(c_e A), from Table 1's printed numbers, worked out by hand (5 s.f.):
    # test 1: 8000/(5095.5*0.25) = 6.2801;  2: 1100/(3503.2*0.25) = 1.2560;  3: 1335/(2834.4*0.25) = 1.8840;
    # 4: 1465/(2332.8*0.25) = 2.5120;  5: 1542/(1964.3*0.25) = 3.1400;  6: 985/(2614.1*0.2) = 1.8840;
    # 7: 1643/(2906.9*0.3) = 1.8840;  8: 2017/(3058.8*0.35) = 1.8840;  9: 2329/(3090.5*0.4) = 1.8840
    hand = [6.2801, 1.2560, 1.8840, 2.5120, 3.1400, 1.8840, 1.8840, 1.8840, 1.8840]
    assert f["implied_omega_rad_s"] == pytest.approx(hand, abs=6e-4)
    # column 1, 4, 6, 8, 10, 6, 6, 6, 6: the ratio is 0.314 = pi/10 for tests 2-9 (1.2560/4 ... 1.8840/6), 6.28 for test 1
    assert f["factor_tests_2_9_mean"] == pytest.approx(0.31400, abs=2e-4)
    assert f["factor_tests_2_9_mean"] == pytest.approx(math.pi / 10, rel=1e-3)
    assert f["factor_tests_2_9_rel_spread"] < 1e-3
    assert f["implied_factor_omega_over_column"][0] == pytest.approx(6.2801, abs=6e-4)


def test_finding_b_test1_factor_20():
    f = {x["id"]: x for x in audit(Lin())["findings"]}["b"]["numbers"]
    assert f["factor"] == pytest.approx(8000 / (0.1 * math.pi * 0.25) / 5095.5, rel=1e-12)
    assert 19.9 < f["factor"] < 20.1
    assert f["F_ac_implied_by_c_e"] == pytest.approx(5095.5 * 0.1 * math.pi * 0.25)


def test_finding_c_eq26():
    f = {x["id"]: x for x in audit(Lin())["findings"]}["c"]["numbers"]
    assert f["dynamic_stiffness_FA_over_A_N_per_mm"] == pytest.approx(19522.1 / 0.25)
    assert f["F0_minus_FA"] == pytest.approx(11117.21 - 19522.1)
    assert f["F0_minus_FA"] < 0
    assert f["k_e_at_x0_N_per_mm"] == 10000.0
    assert f["ratio_dynamic_over_k_e"] == pytest.approx(19522.1 / 0.25 / 10000.0)


@needs_models
def test_finding_c_with_chain_model():
    f = {x["id"]: x for x in audit()["findings"]}["c"]["numbers"]
    assert f["model"] is not None
    # F_A/A = 19522.1/0.25 = 78088.4 N/mm against k_e(2.2 mm) = 7622.83 N/mm (Eq. 15/16 typed in paper_forms):
    # 10.24 times the model's stiffness
    assert f["k_e_at_x0_N_per_mm"] == pytest.approx(paper_forms.k_e(2.2), rel=1e-9)
    assert f["ratio_dynamic_over_k_e"] == pytest.approx(78088.4 / paper_forms.k_e(2.2), rel=1e-9)
    assert f["ratio_dynamic_over_k_e"] == pytest.approx(10.24, abs=0.01)


def test_finding_d_validation_case():
    f = {x["id"]: x for x in audit(Lin())["findings"]}["d"]["numbers"]
    a = EQ28_PAPER  # hand evaluation of Eq. 21 with the printed coefficients

    def c(w, A):
        return a[0] * w * w + a[1] * w + a[2] * A * A + a[3] * A + a[4]

    assert f["c_e_omega_7"] == pytest.approx(c(7.0, 0.32), rel=1e-3)
    assert f["c_e_omega_14pi"] == pytest.approx(c(14 * math.pi, 0.32), rel=1e-3)
    assert f["c_e_consistent_units"] == pytest.approx(c(140.0, 0.32), rel=1e-3)
    assert f["ratio_14pi_over_7"] > 10


def test_finding_e_phase():
    f = {x["id"]: x for x in audit(Lin())["findings"]}["e"]["numbers"]
    assert f["FA_sin_phi_N"] == pytest.approx(19522.1 * math.sin(-0.835))
    assert f["FA_sin_phi_N"] < 0 < f["F_ac_eq27"]


def test_format_audit_mentions_everything():
    text = format_audit(audit(Lin()))
    for s in ("Eq. 28", "(a)", "(b)", "(c)", "(d)", "(e)", "28.02"):
        assert s in text


# --------------------------------------------------------------------------- CLI
@needs_models
def test_cli_audit_json(tmp_path, capsys):
    p = tmp_path / "a.json"
    assert cli(["audit", "--json", str(p)]) == 0
    d = json.loads(p.read_text())
    assert [four_sf(v) for v in d["eq28_alpha"]] == [four_sf(v) for v in EQ28_PAPER]
    assert {f["id"] for f in d["findings"]} == {"a", "b", "c", "d", "e"}
    before = p.read_text()
    assert cli(["audit", "--json", str(p)]) == 2
    assert "already exists" in capsys.readouterr().err
    assert p.read_text() == before
    assert cli(["audit", "--json", str(p), "--force"]) == 0


@pytest.mark.slow
@needs_models
def test_cli_simulate_then_identify(tmp_path, capsys):
    data = tmp_path / "sim.csv"
    assert cli(["simulate", str(data), "--law", "viscous", "--params", "2834.4", "--noise-x", "0.0005",
                "--noise-F", "20", "--seed", "3", "--cycles", "4", "--samples-per-cycle", "100"]) == 0
    out = tmp_path / "id.json"
    plots = tmp_path / "plots"
    assert cli(["identify", str(data), "--json", str(out), "--plots", str(plots), "--quiet"]) == 0
    d = json.loads(out.read_text())
    # the machine contract: exact key sets (a renamed key breaks every consumer)
    # the contract keys, plus the tests left out with their reason and the load-limit warnings
    assert set(d) == {"tests", "model", "law", "ranking", "excluded", "warnings"}
    assert d["excluded"] == []
    assert set(d["model"]) == {"name", "mass_kg"}
    assert set(d["law"]) == {"name", "formula", "param_names", "params", "params_normal_equations", "stderr",
                             "rmse", "loo_rmse", "residuals", "cond_X", "cond_G", "dof", "n_tests"}
    assert {r["law"] for r in d["ranking"]} == {"polynomial", "viscous", "viscous+hysteretic", "viscous+coulomb",
                                                "hysteretic", "coulomb"}
    for r in d["ranking"]:
        assert set(r) == {"law", "formula", "params", "param_names", "stderr", "rmse", "loo_rmse", "n_params"}
    assert [r["loo_rmse"] for r in d["ranking"]] == sorted(r["loo_rmse"] for r in d["ranking"])
    visc = {r["law"]: r for r in d["ranking"]}["viscous"]
    assert visc["params"] == pytest.approx([2834.4], rel=0.01)  # the simulated viscous law
    assert d["model"]["mass_kg"] == pytest.approx(3.2)  # 4.0 kg/m x 16 links x 50 mm
    assert len(d["tests"]) == 9
    for t in d["tests"]:
        assert set(t) == {"test", "omega", "x0", "A", "theta", "F0", "FA", "phi", "r2", "F_ac", "F_as", "Fc0", "c_e",
                          "W", "W_ratio", "r2_c", "mass_kg", "n_cycles", "cycles_kept", "t_start", "t_end",
                          "noise_x", "source", "steady", "steady_tol"}
        assert t["c_e"] == pytest.approx(2834.4, rel=0.01)
    assert d["law"]["name"] == "polynomial" and len(d["law"]["params"]) == 5
    assert (plots / "loop_3.png").is_file() and (plots / "damping_surface.png").is_file()
    assert cli(["identify", str(data), "--json", str(out), "--quiet"]) == 2  # no overwrite
    assert cli(["simulate", str(data)]) == 2  # no overwrite


@needs_models
def test_cli_identify_fewer_than_six_tests(tmp_path, capsys):
    plan = tmp_path / "plan.csv"
    plan.write_text("test,omega,x0,A\na,1.0,2.2,0.25\nb,2.0,2.2,0.25\n")
    data = tmp_path / "two.csv"
    assert cli(["simulate", str(data), "--plan", str(plan), "--cycles", "3"]) == 0
    rc = cli(["identify", str(data), "--quiet"])
    assert rc == 2
    assert "at least 6" in capsys.readouterr().err


@needs_models
def test_cli_identify_linear_model_allows_compression(tmp_path):
    data = tmp_path / "damper.csv"
    # a linear part about zero force: F changes sign
    assert cli(["simulate", str(data), "--model", "linear", "--k", "500", "--x-ref", "2.2", "--mass", "0",
                "--law", "viscous", "--params", "100", "--ramp-rate", "0", "--cycles", "4"]) == 0
    assert cli(["identify", str(data), "--quiet"]) == 2  # chain model: compressive force refused
    out = tmp_path / "d.json"
    assert cli(["identify", str(data), "--model", "linear", "--json", str(out), "--quiet"]) == 0
    d = json.loads(out.read_text())
    for t in d["tests"]:
        assert t["c_e"] == pytest.approx(100.0, rel=1e-3)


@needs_models
def test_cli_side_file_roundtrip(tmp_path):
    data = tmp_path / "s.csv"
    assert cli(["simulate", str(data), "--cycles", "4", "--samples-per-cycle", "80"]) == 0
    side = tmp_path / "side.csv"
    assert cli(["identify", str(data), "--write-side", str(side), "--quiet"]) == 0
    text = side.read_text().splitlines()
    assert text[0] == "test,omega,x0,A" and len(text) == 10
    out = tmp_path / "o.json"
    assert cli(["identify", str(data), "--side", str(side), "--json", str(out), "--quiet"]) == 0
    d = json.loads(out.read_text())
    assert all(t["source"] == "side file" for t in d["tests"])
    assert d["tests"][2]["omega"] == pytest.approx(0.6 * math.pi, rel=1e-4)
    bad = tmp_path / "bad_side.csv"
    bad.write_text("test,omega,x0,A\nnope,1,2,0.2\n")
    assert cli(["identify", str(data), "--side", str(bad), "--quiet"]) == 2


def test_finding_d_forward_prediction_closed_form():
    """x = x0 + A sin ψ with ψ = ωt over one period: F = k x + m ẍ·1e-3 + c ẋ = k x0 + B sin ψ + C cos ψ with
    B = A(k − m ω²·1e-3), C = c ω A, so F_max,min = k x0 ± sqrt(B² + C²) (721 samples over the period: the sampled
    extreme misses by at most amp·(1 − cos(π/720)) < 1e-5·amp).
    Bugs caught: ẋ = ωA cos ψ garbled (ω/A), the prediction skipped when a model is given."""
    f = {x["id"]: x for x in audit(Lin())["findings"]}["d"]["numbers"]
    w = 2 * math.pi * VALIDATION["f_Hz"]
    A, x0, k, m = VALIDATION["A"], VALIDATION["x0"], 1e4, 3.2
    for key in ("omega_7", "omega_14pi"):
        c = f[f"c_e_{key}"]
        B, C = A * (k - m * w * w * 1e-3), c * w * A
        amp = math.hypot(B, C)
        assert f[f"F_max_N_{key}"] == pytest.approx(k * x0 + amp, abs=1e-5 * amp)
        assert f[f"F_min_N_{key}"] == pytest.approx(k * x0 - amp, abs=1e-5 * amp)
    assert f["F_k_range_N"] == pytest.approx([k * (x0 - A), k * (x0 + A)], rel=1e-9)


def test_finding_c_half_swing_of_a_linear_spring():
    """k = 1e4 N/mm: half the swing of F_k over x0 ± A is k·A, its value at x0 is k·x0 (EQ27's x0, A).
    Bug caught: 0.5·(F₊ − F₋) garbled."""
    from chainid.damping.audit import EQ27

    f = {x["id"]: x for x in audit(Lin())["findings"]}["c"]["numbers"]
    assert f["F_k_swing_half_N"] == pytest.approx(1e4 * EQ27["A"], rel=1e-12)
    assert f["F_k_at_x0_N"] == pytest.approx(1e4 * EQ27["x0"], rel=1e-12)
    assert f["k_e_range_x0_pm_A_N_per_mm"] == [1e4, 1e4]


# ---------------------------------------------------------------- seed-21 survivors (issue 20 §5)
class HeavySpring(LinearSpring):
    """F = 10000·x with a 500 kg moving mass: m·ω²·1e-3 = 967 N/mm at 7 Hz, a tenth of k (the inertia shows)."""

    mass_kg = 500.0


def test_finding_d_inertia_term_of_a_heavy_mass():
    """The closed form of test_finding_d_forward_prediction_closed_form with m = 500 kg, where the inertia term
    −m·ω²·A·sin ψ·1e-3 moves the extremes by hundreds of N.  Bug caught: ẍ = −ω²·A sin ψ garbled (−ω + 2·A sin ψ),
    invisible next to c·ω·A with the chain's 3.2 kg."""
    f = {x["id"]: x for x in audit(HeavySpring())["findings"]}["d"]["numbers"]
    w = 2 * math.pi * VALIDATION["f_Hz"]
    A, x0, k, m = VALIDATION["A"], VALIDATION["x0"], 1e4, 500.0
    for key in ("omega_7", "omega_14pi"):
        B, C = A * (k - m * w * w * 1e-3), f[f"c_e_{key}"] * w * A
        amp = math.hypot(B, C)
        assert f[f"F_max_N_{key}"] == pytest.approx(k * x0 + amp, abs=1e-5 * amp)
        assert f[f"F_min_N_{key}"] == pytest.approx(k * x0 - amp, abs=1e-5 * amp)


def test_finding_a_paper_omega_over_the_column_is_pi_over_10():
    """Eq. 25's ω of test 3 is 1.884 rad/s where Table 1's column says 6: 1.884/6 = 0.314 = π/10 to 0.051 %
    (by hand), the unit factor finding (a) is about.  Bug caught: 1.884 // 6 = 0."""
    f = {x["id"]: x for x in audit(Lin())["findings"]}["a"]["numbers"]
    assert f["eq25_omega_test3_rad_s"] == 1.884
    assert f["eq25_over_column_test3"] == pytest.approx(0.314, rel=1e-12)
    assert f["eq25_over_column_test3"] == pytest.approx(math.pi / 10, rel=6e-4)
    assert f["column_equals_f_Hz_times"] == pytest.approx(20.0, rel=1e-12)  # 2π/(π/10)


def test_findings_summaries_state_the_hand_numbers():
    """The audit's findings as the reader gets them: each summary's numbers from the paper's Table 1 and Eq. 26/27
    by hand (test 1: ω = 0.1π·1 rad/s, A = 0.25 mm; Eq. 26: F_A = 19522.1 N, φ = −0.835, F0 = 11117.21 N) on the
    spring k = 1e4 N/mm."""
    from chainid.damping.audit import format_audit, load_table1

    rep = audit(Lin())
    s = {x["id"]: x["summary"] for x in rep["findings"]}
    tb = load_table1()
    fac = tb["F_ac"] / (tb["c_e"] * tb["A"] * tb["omega_col"])  # ω / column implied by c_e = F_ac/(ωA)
    f29 = fac[1:]
    assert s["a"].startswith(f"For tests 2-9, F_ac/(c_e A) = {f29.mean():.5f} x column (spread "
                             f"{100 * np.ptp(f29) / f29.mean():.3f} %), i.e. pi/10 = 0.31416 to "
                             f"{100 * abs(f29.mean() / (math.pi / 10) - 1):.3f} % (the paper rounds it to 0.3140")
    assert f"F_ac/(omega A) is {f29.mean():.3f} x the tabulated c_e" in s["a"]
    w1 = 0.1 * math.pi
    ce1 = 8000.0 / (w1 * 0.25)
    assert s["b"] == (f"At omega = 0.3142 rad/s, F_ac = 8000 N gives c_e = {ce1:.1f} N s/mm, {ce1 / 5095.5:.2f} x the "
                      f"tabulated 5095.5; c_e = 5095.5 needs F_ac = {5095.5 * w1 * 0.25:.1f} N.")
    assert s["c"] == ("F_A/A = 19522.1/0.25 = 78088 N/mm. The model's k_e(2.2 mm) = 10000 N/mm, so F_A/A is 7.81 x k_e; "
                      "the model's F_k(2.2 mm) = 22000 N against F0 = 11117 N. F0 - F_A = -8404.9 N < 0: the fitted "
                      "force would compress the chain.")
    v = 19522.1 * math.sin(-0.835)
    assert s["e"].startswith(f"With x = x0 + A sin(omega t), the part of F in phase with the velocity is F_A sin(phi) = "
                             f"{v:.0f} N")
    assert f"W = pi A F_A sin(phi) = {math.pi * 0.25 * v:.0f} N mm < 0" in s["e"]
    d = {x["id"]: x for x in rep["findings"]}["d"]["numbers"]
    assert ("the elastic part alone spans [19300, 25700] N." in s["d"]  # k·(2.25 ∓ 0.32)
            and f"with omega = 14 pi = {14 * math.pi:.2f} rad/s" in s["d"]
            and f"({d['c_e_omega_14pi'] / d['c_e_omega_7']:.1f} x)" in s["d"]
            and "(20 f = 140)" in s["d"] and "0.314-3.142 rad/s" in s["d"])
    text = format_audit(rep)
    for f in rep["findings"]:
        assert f"({f['id']}) {f['title']}\n    {f['summary']}" in text
    assert "  matches the paper to 4 significant figures: yes" in text


def test_finding_d_minimum_of_eq21_in_omega():
    """Eq. 21 is a parabola in ω with its minimum at −α₂/(2α₁) = 651.57/(2·28.024) = 11.63 column units (the paper's
    Eq. 28 by hand), outside the tested 1–10."""
    from chainid.damping.audit import EQ28_PAPER

    f = {x["id"]: x for x in audit(Lin())["findings"]}["d"]
    w_min = -EQ28_PAPER[1] / (2 * EQ28_PAPER[0])
    assert f["numbers"]["omega_of_minimum_c_e_column_unit"] == pytest.approx(w_min, rel=1e-3)
    assert f"the minimum of Eq. 21 in omega is at {w_min:.2f} column units, outside the tested 1-10." in f["summary"]


def test_finding_a_column_as_omega_ratio_per_test_by_hand():
    """Finding (a)'s c_e computed with the column used as ω, over the tabulated c_e, per test: F_ac/(col·A)/c_e from
    the paper's Table 1 typed in here (test 2: 1100/(4·0.25)/3503.2 = 0.31400; test 4: 1465/(8·0.25)/2332.8 = 0.31400).
    Bug caught: a floor division in F_ac/(col·A)."""
    col = [1, 4, 6, 8, 10, 6, 6, 6, 6]
    A = [0.25, 0.25, 0.25, 0.25, 0.25, 0.2, 0.3, 0.35, 0.4]
    F_ac = [8000, 1100, 1335, 1465, 1542, 985, 1643, 2017, 2329]
    c_e = [5095.5, 3503.2, 2834.4, 2332.8, 1964.3, 2614.1, 2906.9, 3058.8, 3090.5]
    hand = [f / (w * a) / c for f, w, a, c in zip(F_ac, col, A, c_e)]
    f = {x["id"]: x for x in audit(Lin())["findings"]}["a"]["numbers"]
    np.testing.assert_allclose(f["ce_from_Fac_with_column_as_omega_over_table_ce"], hand, rtol=1e-12)
    assert hand[1] == pytest.approx(0.31400, abs=1e-5) and hand[3] == pytest.approx(0.31400, abs=1e-5)


def test_finding_d_and_e_remaining_numbers_by_hand():
    """The validation case's other numbers by hand from the printed Eq. 28 (ω = 7 Hz·2π = 14π rad/s, A = 0.32 mm):
    the table's unit of 14π is 14π/(π/10) = 140; the tests span column 1–10 = π/10–π rad/s; F_ac of c_e(7) at the
    true velocity c·14π·0.32; the rad/s refit evaluated at 14π equals Eq. 28 at column 140 (ω_col = 10ω/π);
    finding (e)'s W = π·A·F_A·sin φ = π·0.25·19522.1·sin(−0.835); the text's rad/s row α1·(10/π)², α2·10/π, α3..α5.
    Bugs caught: any of these constants or conversions garbled."""
    from chainid.damping.audit import EQ28_PAPER, format_audit

    a = EQ28_PAPER

    def c(w, A):
        return a[0] * w * w + a[1] * w + a[2] * A * A + a[3] * A + a[4]

    rep = audit(Lin())
    f = {x["id"]: x for x in rep["findings"]}
    d = f["d"]["numbers"]
    w = 14 * math.pi
    assert d["omega_in_table_column_unit"] == pytest.approx(140.0, rel=1e-12)
    assert d["table_column_range"] == [1.0, 10.0]
    assert d["table_omega_range_rad_s"] == pytest.approx([math.pi / 10, math.pi], rel=1e-12)
    assert d["F_ac_omega_7_times_true_velocity_N"] == pytest.approx(c(7.0, 0.32) * w * 0.32, rel=1e-3)
    assert d["ratio_14pi_over_7"] == pytest.approx(c(w, 0.32) / c(7.0, 0.32), rel=1e-3)
    assert d["c_e_rad_s_refit_at_14pi"] == pytest.approx(c(140.0, 0.32), rel=1e-3)
    assert d["omega_of_minimum_c_e_column_unit"] == pytest.approx(651.57 / (2 * 28.02), rel=1e-3)
    e = f["e"]["numbers"]
    assert e["W_per_cycle_Nmm"] == pytest.approx(math.pi * 0.25 * 19522.1 * math.sin(-0.835), rel=1e-12)
    assert e["F_ac_eq27"] == 1335.0
    text = format_audit(rep)
    assert "matches the paper to 4 significant figures: yes" in text
    row = next(ln for ln in text.splitlines() if "same fit with omega in rad/s (pi/10 x column): " in ln)
    vals = [float(v) for v in row.split(": ")[1].split(", ")]
    s = 10 / math.pi
    np.testing.assert_allclose(vals, [a[0] * s * s, a[1] * s, a[2], a[3], a[4]], rtol=1e-3)
    assert rep["eq28_alpha_4sf"] == pytest.approx([28.02, -651.6, -8386.0, 7395.0, 4379.0], rel=1e-12)


S = math.pi / 10  # ω [rad/s] = (π/10) × Table 1's column


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
