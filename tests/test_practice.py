"""chainid.model.practice against hand computations from the cited sources (units mm, N, MPa)."""
from __future__ import annotations

import math

import pytest

from chainid.model import kernels, practice
from chainid.chain import presets
from chainid.chain.spec import PAPER_CHAIN


def test_orcaflex_ea_at_two_diameters():
    # OrcaFlex: EA = 0.854e8 d² kN studless, 1.01e8 d² kN studlink, d in m
    assert practice.catalogue_ea_N(14, "studless") == pytest.approx(16_738.4e3, rel=1e-9)   # 0.854e8 * 1.96e-4 kN
    assert practice.catalogue_ea_N(76, "studless") == pytest.approx(493_270.4e3, rel=1e-9)  # 0.854e8 * 5.776e-3 kN
    assert practice.catalogue_ea_N(76, "studlink") == pytest.approx(583_376.0e3, rel=1e-9)  # 1.01e8 * 5.776e-3 kN
    assert practice.catalogue_ea_N(14, "studlink") == pytest.approx(19_796.0e3, rel=1e-9)


def test_dnv_ea_at_two_diameters():
    # DNV-OS-E301: E = (5.40 - 0.0040 d) 1e10 N/m² (R3), (5.45 - 0.0025 d) 1e10 (R4); A = 2 π d²/4
    # 76 mm R3: E = 5.096e10 N/m², A = 9.07292e-3 m² -> 4.62356e8 N
    assert practice.catalogue_ea_N(76, "studless", "dnv", "R3") == pytest.approx(4.62356e8, rel=1e-5)
    # 120 mm R4: E = 5.15e10 N/m², A = 2.261947e-2 m² -> 1.164903e9 N
    assert practice.catalogue_ea_N(120, "studless", "dnv", "R4") == pytest.approx(1.164903e9, rel=1e-5)
    # stud link, any grade: 5.6e10 N/m²; 76 mm -> 5.08083e8 N
    assert practice.catalogue_ea_N(76, "studlink", "dnv") == pytest.approx(5.08083e8, rel=1e-5)


def test_w22_loads_against_makers_table():
    # pilotfits.com table (IACS W22 / DNV-OS-E302), kN: d=34 R3 proof 745, break 1065; d=50 R4 studless proof 1920,
    # stud proof 2160, break 2740; d=70 R3 break 4196
    assert practice.breaking_load_N(34, "R3") == pytest.approx(1065e3, rel=1.5e-3)
    assert practice.proof_load_N(34, "R3") == pytest.approx(745e3, rel=1.5e-3)
    assert practice.breaking_load_N(50, "R4") == pytest.approx(2740e3, rel=1e-3)
    assert practice.proof_load_N(50, "R4") == pytest.approx(1920e3, rel=1e-3)
    assert practice.proof_load_N(50, "R4", studlink=True) == pytest.approx(2160e3, rel=1e-3)
    assert practice.breaking_load_N(70, "R3") == pytest.approx(4196e3, rel=1e-3)
    assert practice.working_load_N(50, "R4") == pytest.approx(960e3, rel=1e-3)


def test_din_grade_c_breaking_force_against_makers_table():
    # 800 N/mm² over two bar sections; the makers' table rounds to 250 / 850 / 1450 kN
    for d, kN in ((14, 250), (26, 850), (34, 1450)):
        assert practice.breaking_load_N(d, "C") == pytest.approx(kN * 1e3, rel=0.02)
    assert practice.proof_load_N(14, "C") / practice.breaking_load_N(14, "C") == pytest.approx(0.8)


def _hand_sigma_max(F, d, width, E, nu):
    """Paper Eq. 11-12 by hand: ρ = 4R/(d(2R + d)), e³ = 3πF(k1 + k2)/(4ρ), σ = 3F/(2πe²)."""
    R = (width + d) / 2
    rho = 4 * R / (d * (2 * R + d))
    k = (1 - nu ** 2) / (math.pi * E)
    e = (3 * math.pi * F * 2 * k / (4 * rho)) ** (1 / 3)
    return 3 * F / (2 * math.pi * e ** 2)


def test_sigma_max_at_paper_test_load():
    # R = 15.5, ρ = 62/630 1/mm, e³ = 3·11117·0.91/(2·210000·62/630) = 0.734262 mm³, e = 0.90207 mm,
    # σ_max = 3·11117/(2π·0.813735) = 6521.7 MPa
    hand = _hand_sigma_max(11117.0, 14.0, 17.0, 210000.0, 0.3)
    assert hand == pytest.approx(6521.7, rel=2e-5)
    assert practice.sigma_max_MPa(11117.0, PAPER_CHAIN) == pytest.approx(hand, rel=1e-12)


def test_sigma_max_against_sympy_hertz_solution():
    sp = pytest.importorskip("sympy")
    from chainid.derive import hertz
    from chainid.derive.symbols import E, F_k, R, d, k_1, k_2, mu, rho

    sol = hertz.hertz_solution()["sigma_max"]
    rho_val = hertz.curvature_sum().subs(hertz.link_radii("outer"))
    k = hertz.compliance_k()
    expr = sol.subs({rho: rho_val, k_1: k, k_2: k})
    val = float(expr.subs({F_k: 11117.0, R: 15.5, d: 14.0, E: 210000.0, mu: 0.3}).evalf())
    assert practice.sigma_max_MPa(11117.0, PAPER_CHAIN) == pytest.approx(val, rel=1e-10)


def test_inner_bend_contact_is_more_conformal():
    # ρ_inner = ½(4/d − 2/(R − d/2)) = ½(2/7 − 2/8.5) = 0.0252101; σ ∝ ρ^(2/3) at fixed F
    rho_o, rho_i = 62 / 630, 0.5 * (2 / 7 - 2 / 8.5)
    expected = practice.sigma_max_MPa(11117.0, PAPER_CHAIN) * (rho_i / rho_o) ** (2 / 3)
    assert practice.sigma_max_MPa(11117.0, PAPER_CHAIN, "inner") == pytest.approx(expected, rel=1e-10)
    assert expected == pytest.approx(2630.5, rel=1e-4)


def test_contact_limit_load_reaches_yield():
    F = practice.contact_limit_load_N(PAPER_CHAIN, 1000.0)
    assert practice.sigma_max_MPa(F, PAPER_CHAIN) == pytest.approx(1000.0, rel=1e-10)
    # σ ∝ F^(1/3): F_lim = 11117 (1000/6521.7)³ ≈ 40.08 N
    assert F == pytest.approx(11117.0 * (1000.0 / 6521.7) ** 3, rel=1e-4)
    assert practice.contact_limit_load_N(PAPER_CHAIN, 1000.0, "first_yield") == pytest.approx(1.6 ** 3 * F)


def test_model_ea_of_paper_chain():
    # README: x = 6.3358e-05 F + ..., chain length 16 x 50 = 800 mm -> EA = 800/6.3358e-5 = 1.26267e7 N
    assert practice.model_ea_N(PAPER_CHAIN) == pytest.approx(800 / 6.3358e-5, rel=1e-4)
    ratio = practice.model_ea_N(PAPER_CHAIN) / (0.854e8 * 0.014 ** 2 * 1e3)
    assert ratio == pytest.approx(0.7543, abs=5e-4)  # the "about 0.75" confirmed
    # EA does not depend on n (the linear term grows with n, and so does the length)
    assert practice.model_ea_N(PAPER_CHAIN.replace(n=64)) == pytest.approx(practice.model_ea_N(PAPER_CHAIN), rel=1e-12)


def test_tangent_ea_against_finite_difference():
    F, h = 50_000.0, 1.0
    dx = kernels.displacement(F + h, PAPER_CHAIN) - kernels.displacement(F - h, PAPER_CHAIN)
    assert practice.tangent_ea_N(F, PAPER_CHAIN) == pytest.approx(800 * 2 * h / dx, rel=1e-6)
    assert practice.tangent_ea_N(F, PAPER_CHAIN) < practice.model_ea_N(PAPER_CHAIN)


def test_load_warnings_thresholds():
    # paper chain = DIN 22252 14x50 grade C: contact limit 40.08 N, working 98.5 kN, proof 197.0 kN, break 246.3 kN
    assert practice.load_warnings(30.0) == []
    assert len(practice.load_warnings(1000.0)) == 1 and "elastic-contact limit" in practice.load_warnings(1000.0)[0]
    assert len(practice.load_warnings(150e3)) == 2
    assert len(practice.load_warnings(200e3)) == 3
    w = practice.load_warnings(300e3)
    assert len(w) == 4 and "minimum breaking force" in w[-1]
    with pytest.raises(ValueError, match="F_max"):
        practice.load_warnings(-1.0)


def test_chain_practice_of_presets():
    row = practice.chain_practice(presets.chain("studlink:76"))
    assert row["model_has_no_stud"] and row["grade"] == "R3"
    assert row["EA_catalogue_orcaflex_N"] == pytest.approx(583_376.0e3)
    din = practice.chain_practice(presets.chain("din22252:34x126"))
    assert din["breaking_load_N"] == pytest.approx(800 * math.pi * 34 ** 2 / 2)
    assert din["contact_limit_over_proof"] < 1e-3


@pytest.mark.parametrize("call", [
    lambda: practice.catalogue_ea_N(-1),
    lambda: practice.catalogue_ea_N(50, "chain"),
    lambda: practice.catalogue_ea_N(50, source="api"),
    lambda: practice.breaking_load_N(50, "R9"),
    lambda: practice.sigma_max_MPa(float("nan")),
    lambda: practice.contact_limit_load_N(None, 0.0),
])
def test_bad_input_raises(call):
    with pytest.raises(ValueError):
        call()


def test_report_step_writes_table_and_figures(tmp_path):
    import json

    from chainid.report.build import step_practice

    md = step_practice(tmp_path, PAPER_CHAIN, lambda s: None)
    assert "## 2b. The model against practice" in md and "| din22252:42x146 |" in md
    for fig in ("practice_ea.png", "practice_limits.png"):
        assert (tmp_path / "figures" / fig).stat().st_size > 10_000
    doc = json.loads((tmp_path / "json" / "practice.json").read_text())
    assert doc["chain"]["ratio_model_catalogue"] == pytest.approx(0.7543, abs=5e-4)
    assert doc["explanation"]["bar_catalogue"] == pytest.approx(0.854e8 * 1e-3 / (210000 * math.pi / 2), rel=1e-9)


def test_cli_stiffness_warns_beyond_the_contact_limit(capsys):
    import json

    from chainid.cli import main

    assert main(["stiffness", "--x", "2.2", "--chain", "din22252:14x50", "--json"]) == 0
    cap = capsys.readouterr()
    doc = json.loads(cap.out)
    assert len(doc["warnings"]) == 1 and "elastic-contact limit" in doc["warnings"][0]
    assert "warning: F_max" in cap.err


def test_cli_identify_warns(tmp_path, capsys):
    from chainid.cli import main

    data = tmp_path / "sim.csv"
    assert main(["simulate", str(data), "--law", "viscous", "--params", "2834.4", "--seed", "3", "--cycles", "3",
                 "--samples-per-cycle", "64"]) == 0
    capsys.readouterr()
    assert main(["identify", str(data), "--quiet", "--chain", "din22252:14x50"]) == 0
    assert "exceeds the elastic-contact limit" in capsys.readouterr().err
