"""The model against practice: catalogue EA, grades, proof/breaking loads, Hertz validity limit.

Units: mm, N, MPa (= N/mm²), kg.  Formulas and their sources are in
``chainid/data/chains.toml`` (header); the numbers are computed here.

* Catalogue axial stiffness EA [N] of chain (OrcaFlex's line-type wizard;
  DNV-OS-E301's effective modulus by grade).
* The model's EA: x = c_lin·F + c_hertz·F^(2/3) (paper Eq. 15) over the chain
  length between the fixtures ℓ = n·pitch (README), so the large-load EA is
  ℓ/c_lin and the tangent EA at F is ℓ·k_e(F) = ℓ/(c_lin + ⅔ c_hertz F^(-1/3)).
* The Hertz peak pressure σ_max(F) of paper Eq. 11–12 and the load at which it
  reaches the grade's yield (σ_max = σ_y) or first yield below the surface
  (p₀ = 1.60 σ_y, Johnson 1985 §6.2), against the proof and breaking loads.
"""
from __future__ import annotations

import math
from typing import Any

from chainid.model import kernels
from chainid.chain.catalogue import canonical_grade
from chainid.chain.presets import Preset, data, listed, match
from chainid.chain.spec import ChainSpec, default_chain

__all__ = [
    "PAPER_TEST_LOAD_N", "FIRST_YIELD_FACTOR", "catalogue_ea_N", "grade", "breaking_load_N", "proof_load_N",
    "working_load_N", "sigma_max_MPa", "contact_limit_load_N", "model_ea_N", "tangent_ea_N", "chain_practice",
    "comparison_table", "explain_ratio", "load_warnings", "practice_section", "format_practice",
]

#: The paper's test pretension F₀ [N] (Eq. 26).
PAPER_TEST_LOAD_N = 11117.0
#: p₀ / σ_y at first (von Mises) yield below an axisymmetric Hertz contact, ν = 0.3 (Johnson, Contact Mechanics §6.2).
FIRST_YIELD_FACTOR = 1.60


def _check_d(d_mm: float) -> float:
    d = float(d_mm)
    if not (math.isfinite(d) and d > 0):
        raise ValueError(f"d = {d_mm!r} mm is invalid: valid range is d > 0 mm")
    return d


def catalogue_ea_N(d_mm: float, kind: str = "studless", source: str = "orcaflex", grade_name: str = "R3") -> float:
    """Catalogue axial stiffness EA [N] of chain of bar diameter d [mm].

    Parameters
    ----------
    d_mm : float
        Nominal bar diameter [mm], > 0.
    kind : {"studless", "studlink"}
        Chain type.
    source : {"orcaflex", "dnv"}
        ``orcaflex``: EA = 0.854e8 d² kN (studless), 1.01e8 d² kN (studlink), d in m (OrcaFlex help, "Chain").
        ``dnv``: DNV-OS-E301 effective modulus, studless E = (5.40 − 0.0040 d)·1e10 N/m² (R3),
        (5.45 − 0.0025 d)·1e10 (R4), (6.00 − 0.0033 d)·1e10 (R5), stud link 5.6e10, times A = 2·π d²/4.
    grade_name : str
        Grade for ``dnv`` studless (R3, R3S → R3 formula; R4, R4S → R4; R5).

    Returns
    -------
    float
        EA [N].
    """
    d = _check_d(d_mm)
    if kind not in ("studless", "studlink"):
        raise ValueError(f"kind = {kind!r} is invalid: valid values are 'studless', 'studlink'")
    if source == "orcaflex":
        coeff_kN = 0.854e8 if kind == "studless" else 1.01e8
        return coeff_kN * (d * 1e-3) ** 2 * 1e3
    if source == "dnv":
        area = 2.0 * math.pi * d * d / 4.0  # mm²
        if kind == "studlink":
            E_MPa = 5.6e4
        else:
            table = {"R3": (5.40, 0.0040), "R3S": (5.40, 0.0040), "R4": (5.45, 0.0025), "R4S": (5.45, 0.0025),
                     "R5": (6.00, 0.0033)}
            if grade_name not in table:
                raise ValueError(f"grade = {grade_name!r} is invalid for the DNV formula: valid grades are {list(table)}")
            c0, c1 = table[grade_name]
            E_MPa = (c0 - c1 * d) * 1e4  # 1e10 N/m² = 1e4 MPa
        return E_MPa * area
    raise ValueError(f"source = {source!r} is invalid: valid values are 'orcaflex', 'dnv'")


def grade(name: str) -> dict[str, Any]:
    """The grade's entry of the data file (``kind``, strengths [MPa], load coefficients, ``source``)."""
    g = data()["grades"]
    key = str(name).strip().upper()
    if key not in g:
        raise ValueError(f"grade = {name!r} is invalid: valid grades are {sorted(g)}")
    return dict(g[key])


def _w22_force_N(coeff: float, d: float) -> float:
    return coeff * d * d * (44.0 - 0.08 * d) * 1e3  # kN -> N


def breaking_load_N(d_mm: float, grade_name: str) -> float:
    """Minimum breaking force [N] of chain of bar diameter d [mm] and grade.

    DIN 22252 grade C: breaking stress × 2·π d²/4; mooring grades: c·d²(44 − 0.08 d) kN (IACS W22).
    """
    d, g = _check_d(d_mm), grade(grade_name)
    if g["kind"] == "nominal_stress":
        return g["breaking_stress"] * 2.0 * math.pi * d * d / 4.0
    return _w22_force_N(g["mbl_coeff"], d)


def proof_load_N(d_mm: float, grade_name: str, studlink: bool = False) -> float:
    """Proof (test) force [N] of chain of bar diameter d [mm] and grade (see :func:`breaking_load_N`)."""
    d, g = _check_d(d_mm), grade(grade_name)
    if g["kind"] == "nominal_stress":
        return g["test_stress"] * 2.0 * math.pi * d * d / 4.0
    return _w22_force_N(g["proof_coeff_studlink" if studlink else "proof_coeff_studless"], d)


def working_load_N(d_mm: float, grade_name: str, studlink: bool = False) -> float:
    """Working load [N]: half the proof force (the usual rule, see the data file's ``swl_half``)."""
    return 0.5 * proof_load_N(d_mm, grade_name, studlink)


def _curvature_sum(chain: ChainSpec, contact: str) -> float:
    """ρ = ½ Σ 1/ρᵢ [1/mm] of paper Eq. 11 (``outer``: ρ′ = −(R + d/2), the paper; ``inner``: −(R − d/2))."""
    if contact == "outer":
        rp = -(chain.R + chain.d / 2.0)
    elif contact == "inner":
        rp = -(chain.R - chain.d / 2.0)
    else:
        raise ValueError(f"contact = {contact!r} is invalid: valid values are 'outer', 'inner'")
    return 0.5 * (2.0 / (chain.d / 2.0) + 2.0 / rp)


def sigma_max_MPa(F_N: float, chain: ChainSpec | None = None, contact: str = "outer") -> float:
    """Peak Hertz contact pressure σ_max [MPa] between two links at tension F [N] (paper Eq. 11–12).

    e = (3π F (k₁ + k₂)/(4ρ))^(1/3) [mm], σ_max = 3F/(2π e²), k₁ = k₂ = (1 − ν²)/(π E).
    """
    chain = chain or default_chain()
    F = float(F_N)
    if not (math.isfinite(F) and F >= 0):
        raise ValueError(f"F = {F_N!r} N is invalid: valid range is F >= 0 N")
    rho = _curvature_sum(chain, contact)
    if rho <= 0:
        raise ValueError(f"chain {chain} gives a non-convex contact (ρ = {rho:.4g} 1/mm) for contact {contact!r}")
    k = (1.0 - chain.nu ** 2) / (math.pi * chain.E)
    e = (3.0 * math.pi * F * 2.0 * k / (4.0 * rho)) ** (1.0 / 3.0)
    return 0.0 if F == 0 else 3.0 * F / (2.0 * math.pi * e * e)


def contact_limit_load_N(chain: ChainSpec | None, sigma_y_MPa: float, criterion: str = "sigma_max",
                         contact: str = "outer") -> float:
    """Tension [N] at which the elastic Hertz contact stops being valid.

    ``criterion="sigma_max"``: σ_max(F) = σ_y; ``"first_yield"``: σ_max = 1.60 σ_y (first yield below the
    surface).  σ_max ∝ F^(1/3), so F = (σ / σ_max(1 N))³.
    """
    s = float(sigma_y_MPa)
    if not (math.isfinite(s) and s > 0):
        raise ValueError(f"sigma_y = {sigma_y_MPa!r} MPa is invalid: valid range is sigma_y > 0 MPa")
    if criterion == "first_yield":
        s *= FIRST_YIELD_FACTOR
    elif criterion != "sigma_max":
        raise ValueError(f"criterion = {criterion!r} is invalid: valid values are 'sigma_max', 'first_yield'")
    return (s / sigma_max_MPa(1.0, chain, contact)) ** 3


def model_ea_N(chain: ChainSpec | None = None, variant: str = "paper") -> float:
    """The model's large-load axial stiffness EA = ℓ / c_lin [N], ℓ = n·pitch the length between the fixtures [mm]."""
    chain = chain or default_chain()
    c_lin, _ = kernels.coefficients(chain, variant)
    return chain.length_mm / c_lin


def tangent_ea_N(F_N: float, chain: ChainSpec | None = None, variant: str = "paper") -> float:
    """Tangent EA = ℓ·k_e at tension F [N]: ℓ / (c_lin + ⅔ c_hertz F^(-1/3)) [N] (Eq. 15–16)."""
    chain = chain or default_chain()
    F = float(F_N)
    if not (math.isfinite(F) and F > 0):
        raise ValueError(f"F = {F_N!r} N is invalid: valid range is F > 0 N")
    c_lin, c_h = kernels.coefficients(chain, variant)
    return chain.length_mm / (c_lin + (2.0 / 3.0) * c_h * F ** (-1.0 / 3.0))


def _ea_label(family: str | None, kind: str) -> str:
    """What the "catalogue" EA of a chain is: the OrcaFlex formula of its own type, or for DIN 22252 chain (for
    which no catalogue EA exists) the studless mooring-chain formula used as a reference only."""
    formula = "0.854e8 d^2 kN" if kind == "studless" else "1.01e8 d^2 kN"
    if family in ("studless", "studlink"):
        return f"OrcaFlex {kind} mooring chain, {formula} (d in m)"
    return (f"studless mooring-chain formula (OrcaFlex {formula}, d in m) as a reference: no catalogue EA exists "
            f"for DIN 22252 chain")


def _preset_of(chain: ChainSpec) -> Preset | None:
    return match(chain)


def chain_practice(chain: ChainSpec | None = None, grade_name: str | None = None, kind: str | None = None,
                   preset: Preset | None = None) -> dict[str, Any]:
    """Every practice number of one chain (EA model vs catalogue, loads, Hertz limits).

    Parameters
    ----------
    chain : ChainSpec, optional
        Default the built-in chain.  Its grade and family are the chain's own (:attr:`ChainSpec.grade`,
        :attr:`ChainSpec.family`); when not stated, those of the preset with the same dimensions; a chain that
        matches none is treated as DIN 22252 grade C (the paper's kind of chain).
    grade_name, kind : str, optional
        Override the grade (``C``, ``R3`` … ``R5``) and the type (``studless``/``studlink``).
    """
    chain = chain or default_chain()
    preset = preset or _preset_of(chain)
    g = grade_name or chain.grade or (preset.grade if preset else "C")
    family = chain.family or (preset.family if preset else None)
    if chain.family is None and family is not None:
        try:  # a stated grade of the other kind (R4 on DIN 22252 dimensions): the grade wins, family unknown
            canonical_grade(g, family)
        except ValueError:
            family = None
    g = canonical_grade(g, family)
    knd = kind or ("studlink" if family == "studlink" else "studless")
    gr = grade(g)
    stud = knd == "studlink"
    ea_m = model_ea_N(chain)
    ea_cat = catalogue_ea_N(chain.d, knd, "orcaflex")
    dnv_grade = g if g in ("R3", "R3S", "R4", "R4S", "R5") else "R3"
    ea_dnv = catalogue_ea_N(chain.d, knd, "dnv", dnv_grade)
    mbl = breaking_load_N(chain.d, g)
    proof = proof_load_N(chain.d, g, stud)
    F_lim = contact_limit_load_N(chain, gr["yield"])
    F_fy = contact_limit_load_N(chain, gr["yield"], "first_yield")
    return {
        "preset": preset.name if preset else None,
        "family": family,
        "grade": g,
        "kind": knd,
        "d_mm": chain.d, "pitch_mm": chain.pitch, "width_mm": chain.width, "n": chain.n,
        "length_mm": chain.length_mm,
        "EA_model_N": ea_m,
        "EA_model_shear_N": model_ea_N(chain, "shear"),
        "EA_bar_N": chain.E * 2.0 * math.pi * chain.d ** 2 / 4.0,
        "EA_tangent_10pct_mbl_N": tangent_ea_N(0.1 * mbl, chain),
        "EA_tangent_proof_N": tangent_ea_N(proof, chain),
        "EA_catalogue_orcaflex_N": ea_cat,
        "EA_catalogue_label": _ea_label(family, knd),
        f"EA_catalogue_dnv_{dnv_grade}_N": ea_dnv,
        "EA_catalogue_dnv_N": ea_dnv,
        "ratio_model_catalogue": ea_m / ea_cat,
        "ratio_model_dnv": ea_m / ea_dnv,
        "ratio_tangent_proof_catalogue": tangent_ea_N(proof, chain) / ea_cat,
        "breaking_load_N": mbl,
        "proof_load_N": proof,
        "working_load_N": 0.5 * proof,
        "yield_MPa": gr["yield"],
        "tensile_MPa": gr["tensile"],
        "sigma_max_at_proof_MPa": sigma_max_MPa(proof, chain),
        "sigma_max_at_paper_load_MPa": sigma_max_MPa(PAPER_TEST_LOAD_N, chain),
        "contact_limit_load_N": F_lim,
        "first_yield_load_N": F_fy,
        "contact_limit_over_proof": F_lim / proof,
        "first_yield_over_proof": F_fy / proof,
        "model_has_no_stud": stud,
    }


def comparison_table(presets: list[Preset] | None = None) -> list[dict[str, Any]]:
    """:func:`chain_practice` for every listed preset (DIN 22252, studless and stud-link mooring chain)."""
    return [chain_practice(p.chain, preset=p) for p in (presets if presets is not None else listed())]


def load_warnings(F_max_N: float, chain: ChainSpec | None = None, grade_name: str | None = None) -> list[str]:
    """Warnings when a record's largest force F_max [N] leaves the model's range of validity for ``chain``.

    One line each when F_max exceeds: the elastic-contact limit (Hertz σ_max of Eq. 12 reaches the grade's
    yield; the F^(2/3) contact law then describes a contact that has yielded: a proof-loaded chain has
    conformal contacts, the ``contact_law`` effect of the diagnosis); the working load (half the proof force);
    the proof force; the minimum breaking force.  Empty list when F_max is within all of them.

    Parameters
    ----------
    F_max_N : float
        Largest tension in the record [N] (>= 0).
    chain : ChainSpec, optional
        Default the built-in chain; grade from the matching preset, else DIN 22252 grade C.
    grade_name : str, optional
        Override the grade.
    """
    F = float(F_max_N)
    if not (math.isfinite(F) and F >= 0):
        raise ValueError(f"F_max = {F_max_N!r} N is invalid: valid range is F_max >= 0 N")
    p = chain_practice(chain, grade_name)
    out: list[str] = []
    tag = f"(d = {p['d_mm']:g} mm, grade {p['grade']})"
    if F > p["contact_limit_load_N"]:
        out.append(
            f"F_max = {F:.6g} N exceeds the elastic-contact limit {p['contact_limit_load_N']:.4g} N {tag}: "
            f"the Hertz peak pressure sigma_max = {sigma_max_MPa(F, chain or default_chain()):.4g} MPa is above the "
            f"yield {p['yield_MPa']:g} MPa, so the contact has yielded (conformal after proof loading) and the "
            f"model's F^(2/3) contact term overstates the compliance (see the contact_law effect)")
    for key, label in (("working_load_N", "the working load (half the proof force)"),
                       ("proof_load_N", "the proof force"), ("breaking_load_N", "the minimum breaking force")):
        if F > p[key]:
            out.append(f"F_max = {F:.6g} N exceeds {label} {p[key]:.4g} N {tag}")
    return out


def explain_ratio(chain: ChainSpec | None = None) -> dict[str, float]:
    """Numbers behind the model/catalogue EA ratio of one chain (all ratios to the OrcaFlex studless EA).

    ``bar_model`` / ``bar_catalogue``: EA over that of two straight bars E·2A (the link's bending share);
    ``width_minus_1mm`` / ``width_minus_2mm``: the model with the inner width reduced as by proof-load set;
    ``shear``: with the shear term (variant ``shear``); ``secant_10_50_mbl``: the model's secant EA between 10 %
    and 50 % of the breaking force including the Hertz term; ``tangent_proof``: tangent EA at the proof force.
    """
    chain = chain or default_chain()
    p = chain_practice(chain)
    cat, bar = p["EA_catalogue_orcaflex_N"], p["EA_bar_N"]
    mbl = p["breaking_load_N"]
    x1, x2 = kernels.displacement(0.1 * mbl, chain), kernels.displacement(0.5 * mbl, chain)
    out = {"ratio": p["ratio_model_catalogue"], "bar_model": p["EA_model_N"] / bar, "bar_catalogue": cat / bar,
           "shear": p["EA_model_shear_N"] / cat,
           "secant_10_50_mbl": 0.4 * mbl / (x2 - x1) * chain.length_mm / cat,
           "tangent_proof": p["ratio_tangent_proof_catalogue"]}
    for dw in (1.0, 2.0):
        if chain.width - dw > chain.d:
            out[f"width_minus_{dw:g}mm"] = model_ea_N(chain.replace(width=chain.width - dw)) / cat
    return out


def practice_section(chain: ChainSpec | None = None) -> dict[str, Any]:
    """The audit's practice section: the given chain, the reasons for its EA ratio, the table over the presets."""
    chain = chain or default_chain()
    rows = comparison_table()
    din = [r for r in rows if r["family"] == "din22252"]
    sl = [r for r in rows if r["family"] == "studless"]
    return {
        "chain": chain_practice(chain),
        "explanation": explain_ratio(chain),
        "table": rows,
        "summary": {
            "ratio_model_catalogue_din22252": [min(r["ratio_model_catalogue"] for r in din),
                                               max(r["ratio_model_catalogue"] for r in din)],
            "ratio_model_catalogue_studless": [min(r["ratio_model_catalogue"] for r in sl),
                                               max(r["ratio_model_catalogue"] for r in sl)],
            "contact_limit_over_proof_max": max(r["contact_limit_over_proof"] for r in rows),
            "first_yield_over_proof_max": max(r["first_yield_over_proof"] for r in rows),
        },
    }


def format_practice(sec: dict[str, Any]) -> str:
    """Readable text of :func:`practice_section`."""
    c = sec["chain"]
    lines = [
        "The model against practice (chain EA, validity of the elastic contact):",
        f"  chain d = {c['d_mm']:g} mm, pitch = {c['pitch_mm']:g} mm, width = {c['width_mm']:g} mm, n = {c['n']}"
        f" ({c['preset'] or 'no preset'}, grade {c['grade']}, {c['kind']})",
        f"  model EA = l/c_lin = {c['EA_model_N']:.4g} N; {c['EA_catalogue_label']}: {c['EA_catalogue_orcaflex_N']:.4g} N"
        f" -> ratio {c['ratio_model_catalogue']:.3f}; DNV-OS-E301 {c['EA_catalogue_dnv_N']:.4g} N -> {c['ratio_model_dnv']:.3f}",
        f"  tangent EA at the proof force {c['EA_tangent_proof_N']:.4g} N ({c['ratio_tangent_proof_catalogue']:.3f} x catalogue)",
        f"  sigma_max(11117 N) = {c['sigma_max_at_paper_load_MPa']:.5g} MPa; elastic-contact limit (sigma_max = yield "
        f"{c['yield_MPa']:g} MPa) at {c['contact_limit_load_N']:.4g} N, first yield (1.60 yield) at "
        f"{c['first_yield_load_N']:.4g} N; proof {c['proof_load_N']:.4g} N, breaking {c['breaking_load_N']:.4g} N",
        f"  -> the elastic contact holds up to {100 * c['contact_limit_over_proof']:.3g} % of the proof force "
        f"({100 * c['first_yield_over_proof']:.3g} % to first yield)",
        "  why the model is softer (ratios to the catalogue EA): "
        + ", ".join(f"{k} {v:.3f}" for k, v in sec.get("explanation", {}).items()),
        "",
        f"  {'preset':16s} {'d':>5s} {'EA model N':>11s} {'EA cat. N':>11s} {'ratio':>6s} {'F_lim N':>9s} "
        f"{'proof N':>10s} {'F_lim/proof':>11s}",
    ]
    for r in sec["table"]:
        lines.append(f"  {r['preset']:16s} {r['d_mm']:5g} {r['EA_model_N']:11.4g} {r['EA_catalogue_orcaflex_N']:11.4g} "
                     f"{r['ratio_model_catalogue']:6.3f} {r['contact_limit_load_N']:9.4g} {r['proof_load_N']:10.4g} "
                     f"{r['contact_limit_over_proof']:11.2e}" + ("  (model has no stud)" if r["model_has_no_stud"] else "")
                     + ("  (EA cat.: studless formula as reference)" if r["family"] == "din22252" else ""))
    lines.append("  EA cat. of the DIN 22252 rows: the studless mooring-chain formula as a reference; no catalogue EA "
                 "exists for DIN 22252 chain")
    return "\n".join(lines)
