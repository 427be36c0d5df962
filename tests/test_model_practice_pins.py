"""Pins of chainid.model.practice's remaining numbers and refusals (issue 20 §5, own mutation seeds of mutH),
each by hand from the docstrings' formulas: the bar and shear EA, the tangent EA at 10 % MBL and at the proof
force, the DNV effective modulus, the Hertz pressure of Eq. 11–12 and the first-yield load.  Units: mm, N, MPa."""
from __future__ import annotations

import math

import pytest

from chainid.chain.spec import default_chain
from chainid.model import kernels
from chainid.model.practice import (catalogue_ea_N, chain_practice, contact_limit_load_N, grade,
                                    sigma_max_MPa, tangent_ea_N)


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
