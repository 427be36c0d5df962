"""chainid.model.practice against hand computations from the cited sources (catalogue EA, proof and breaking loads,
contact stress, the elastic-contact limit, load warnings).  Units mm, N, MPa."""
from __future__ import annotations

import math

import pytest

from chainid.chain import presets
from chainid.chain.spec import PAPER_CHAIN, default_chain
from chainid.model import kernels, practice
from chainid.model.practice import (
    catalogue_ea_N,
    chain_practice,
    contact_limit_load_N,
    grade,
    sigma_max_MPa,
    tangent_ea_N,
)


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


@pytest.mark.slow
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


@pytest.mark.slow
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


def test_format_practice_lists_the_explanation():
    """The audit text ends its chain part with the ratios behind the EA ratio (one line, 3 decimals)."""
    from chainid.model.practice import explain_ratio, format_practice, practice_section

    text = format_practice(practice_section())
    e = explain_ratio()
    line = next(ln for ln in text.splitlines() if "why the model is softer" in ln)
    assert f"ratio {e['ratio']:.3f}" in line and f"shear {e['shear']:.3f}" in line


# ---------------------------------------------------------------- seed-21 survivors (issue 20 §5)
def _runtime(s):
    """The string s built at run time (as from the command line: not the interned literal)."""
    return "".join(list(s))


def test_chain_practice_studlink_kind_from_a_runtime_string():
    """`--kind studlink` read from the command line is a run-time string: it must select the stud-link proof
    force of the makers' table (d = 50 R4: 2160 kN stud-link, 1920 kN studless; IACS W22 / DNV-OS-E302).
    Bug caught: `knd == "studlink"` → `knd is "studlink"` (true only for the interned literal)."""
    from chainid.chain import presets
    from chainid.model.practice import chain_practice

    c = presets.chain("studless:50")
    row = chain_practice(c, grade_name=_runtime("R4"), kind=_runtime("studlink"))
    assert row["kind"] == "studlink" and row["proof_load_N"] == pytest.approx(2160e3, rel=1e-3)
    assert row["working_load_N"] == pytest.approx(1080e3, rel=1e-3)
    assert chain_practice(c, grade_name="R4")["proof_load_N"] == pytest.approx(1920e3, rel=1e-3)
    # the DNV ratio is the model's EA over the DNV catalogue EA of that grade (its documented definition)
    assert row["ratio_model_dnv"] == pytest.approx(row["EA_model_N"] / row["EA_catalogue_dnv_R4_N"], rel=1e-12)


def test_explain_ratio_secant_by_root_finding():
    """The secant EA between 10 % and 50 % of the breaking force, from x(F) found by root-finding F_k(x) = F
    (brentq on the force kernel, not the displacement kernel): 0.4·MBL·L/(x₅₀ − x₁₀) over the catalogue EA."""
    from scipy.optimize import brentq

    from chainid.chain import presets
    from chainid.model import kernels
    from chainid.model.practice import chain_practice, explain_ratio

    c = presets.chain("studless:50")
    p = chain_practice(c)
    mbl = p["breaking_load_N"]
    x1, x2 = (brentq(lambda x, F=F: kernels.force(x, c) - F, 0.0, 1e4, xtol=1e-13, rtol=1e-14)
              for F in (0.1 * mbl, 0.5 * mbl))
    want = 0.4 * mbl * c.length_mm / (x2 - x1) / p["EA_catalogue_orcaflex_N"]
    assert explain_ratio(c)["secant_10_50_mbl"] == pytest.approx(want, rel=1e-9)


def _sigma(F, c, contact="outer"):
    """Paper Eq. 11–12 by hand: ρ = ½(2/(d/2) + 2/ρ′), ρ′ = −(R ± d/2); e = (3πF·2k/(4ρ))^⅓; σ = 3F/(2πe²)."""
    rp = -(c.R + c.d / 2) if contact == "outer" else -(c.R - c.d / 2)
    rho = 0.5 * (2 / (c.d / 2) + 2 / rp)
    k = (1 - c.nu ** 2) / (math.pi * c.E)
    e = (3 * math.pi * F * 2 * k / (4 * rho)) ** (1 / 3)
    return 3 * F / (2 * math.pi * e * e)


def test_chain_practice_numbers_by_hand():
    """The paper chain (14 × 50, DIN 22252 grade C; DNV's studless R3 modulus as the reference): every EA and
    stress of chain_practice from the formulas of the module docstring."""
    c = default_chain()
    p = chain_practice(c)
    ell = c.n * c.pitch
    cl, ch = kernels.coefficients(c, "paper")
    assert p["EA_bar_N"] == pytest.approx(c.E * 2 * math.pi * c.d ** 2 / 4, rel=1e-12)
    assert p["EA_model_shear_N"] == pytest.approx(ell / kernels.coefficients(c, "shear")[0], rel=1e-12)
    for key, F in (("EA_tangent_10pct_mbl_N", 0.1 * p["breaking_load_N"]), ("EA_tangent_proof_N", p["proof_load_N"])):
        assert p[key] == pytest.approx(ell / (cl + 2 / 3 * ch * F ** (-1 / 3)), rel=1e-12)
    dnv = (5.40 - 0.0040 * c.d) * 1e4 * 2 * math.pi * c.d ** 2 / 4
    assert p["EA_catalogue_dnv_N"] == pytest.approx(dnv, rel=1e-12)
    assert p["EA_catalogue_dnv_R3_N"] == p["EA_catalogue_dnv_N"]
    assert p["ratio_model_dnv"] == pytest.approx(p["EA_model_N"] / dnv, rel=1e-12)
    assert p["ratio_tangent_proof_catalogue"] == pytest.approx(p["EA_tangent_proof_N"] / p["EA_catalogue_orcaflex_N"],
                                                               rel=1e-12)
    g = grade("C")
    assert (p["yield_MPa"], p["tensile_MPa"]) == (g["yield"], g["tensile"])
    assert p["sigma_max_at_paper_load_MPa"] == pytest.approx(_sigma(11117.0, c), rel=1e-12)
    assert p["sigma_max_at_proof_MPa"] == pytest.approx(_sigma(p["proof_load_N"], c), rel=1e-12)
    F_lim = (g["yield"] / _sigma(1.0, c)) ** 3
    assert p["contact_limit_load_N"] == pytest.approx(F_lim, rel=1e-12)
    assert p["first_yield_load_N"] == pytest.approx(1.60 ** 3 * F_lim, rel=1e-12)
    assert p["first_yield_over_proof"] == pytest.approx(1.60 ** 3 * F_lim / p["proof_load_N"], rel=1e-12)
    assert p["working_load_N"] == pytest.approx(0.5 * p["proof_load_N"], rel=1e-15)
    assert sigma_max_MPa(5e4, c, "inner") == pytest.approx(_sigma(5e4, c, "inner"), rel=1e-12)
    assert sigma_max_MPa(0.0, c) == 0.0


@pytest.mark.parametrize("grade_name, c0, c1", [("R3S", 5.40, 0.0040), ("R4", 5.45, 0.0025),
                                                ("R4S", 5.45, 0.0025), ("R5", 6.00, 0.0033)])
def test_dnv_modulus_by_grade_and_the_studlink_value(grade_name, c0, c1):
    """DNV-OS-E301: studless E = (c0 − c1·d)·1e10 N/m² by grade, stud link 5.6e10, times 2·πd²/4 (d = 76 mm)."""
    area = 2 * math.pi * 76.0 ** 2 / 4
    want = (c0 - c1 * 76.0) * 1e4 * area
    assert catalogue_ea_N(76.0, "studless", "dnv", grade_name) == pytest.approx(want, rel=1e-12)
    assert catalogue_ea_N(76.0, "studlink", "dnv", grade_name) == pytest.approx(5.6e4 * area, rel=1e-12)


def test_practice_refusals_name_the_field_value_and_valid_values():
    c = default_chain()
    for call, msg in (
            (lambda: catalogue_ea_N(76.0, "stud"), "kind = 'stud' is invalid: valid values are 'studless', 'studlink'"),
            (lambda: catalogue_ea_N(76.0, source="api"),
             "source = 'api' is invalid: valid values are 'orcaflex', 'dnv'"),
            (lambda: catalogue_ea_N(76.0, source="dnv", grade_name="C"),
             "grade = 'C' is invalid for the DNV formula: valid grades are ['R3', 'R3S', 'R4', 'R4S', 'R5']"),
            (lambda: catalogue_ea_N(0.0), "d = 0.0 mm is invalid: valid range is d > 0 mm"),
            (lambda: sigma_max_MPa(1e3, c, "side"), "contact = 'side' is invalid: valid values are 'outer', 'inner'"),
            (lambda: sigma_max_MPa(-1.0, c), "F = -1.0 N is invalid: valid range is F >= 0 N"),
            (lambda: contact_limit_load_N(c, 0.0), "sigma_y = 0.0 MPa is invalid: valid range is sigma_y > 0 MPa"),
            (lambda: contact_limit_load_N(c, 500.0, "tresca"),
             "criterion = 'tresca' is invalid: valid values are 'sigma_max', 'first_yield'"),
            (lambda: tangent_ea_N(0.0, c), "F = 0.0 N is invalid: valid range is F > 0 N")):
        with pytest.raises(ValueError) as exc:
            call()
        assert str(exc.value) == msg


def test_explain_ratio_narrows_the_inner_width_by_one_and_by_two_millimetres():
    """``width_minus_1mm`` / ``width_minus_2mm`` (docstring): the model EA of the chain with its inner width w − 1
    and w − 2 mm over the catalogue EA.  A narrower link has a smaller bend radius, so less bending compliance:
    the ratio grows as the width shrinks (1 mm less, then 2 mm less)."""
    from chainid.model.practice import chain_practice, explain_ratio, model_ea_N

    c = presets.chain("studless:50")
    e = explain_ratio(c)
    cat = chain_practice(c)["EA_catalogue_orcaflex_N"]
    assert {k for k in e if k.startswith("width_minus_")} == {"width_minus_1mm", "width_minus_2mm"}
    for dw in (1.0, 2.0):
        assert e[f"width_minus_{dw:g}mm"] == pytest.approx(model_ea_N(c.replace(width=c.width - dw)) / cat,
                                                           rel=1e-12)
    assert e["ratio"] < e["width_minus_1mm"] < e["width_minus_2mm"]
