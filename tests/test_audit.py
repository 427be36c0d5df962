"""Audit of the paper's Table 1 / Eq. 25–28 and the identify/simulate/audit CLI."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

import paper_forms  # tests/paper_forms.py: the paper's closed forms in plain Python

from chainid.damping.audit import EQ28_PAPER, audit, eq28, format_audit, load_table1
from chainid.cli.identify import main as cli
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
