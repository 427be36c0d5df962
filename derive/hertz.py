"""Hertz contact between two crossed links (paper Eq. 11–14).

Starts from the general Hertz relations with the four principal radii as
inputs.  Body 1 has principal radii ρ₁ (the bar section, d/2, convex) and
ρ₁′ (along the bend, concave, negative); body 2 the same, its principal
planes turned by ω_c (π/2 for a chain: consecutive links are crossed).

General Hertz (Timoshenko & Goodier §140; Johnson, Contact Mechanics §4.2):
    A + B = ½ (1/ρ₁ + 1/ρ₁′ + 1/ρ₂ + 1/ρ₂′)
    B − A = ½ √[(1/ρ₁ − 1/ρ₁′)² + (1/ρ₂ − 1/ρ₂′)² + 2(1/ρ₁ − 1/ρ₁′)(1/ρ₂ − 1/ρ₂′) cos 2ω_c]
and, for a circular contact of radius e under the pressure
p(r) = p₀ √(1 − r²/e²), the normal surface displacement inside the contact
is w(r) = π² k p₀ (2e² − r²)/(4e) with k = (1 − μ²)/(π E) (Boussinesq).
The gap between the surfaces is h(r) = A r² (A = B); contact closes it:
w₁ + w₂ = δ − h.  Equating the r⁰ and r² terms and the load F = ∫ p dA gives
e, p₀ = σ_max and δ.
"""
from __future__ import annotations

from functools import lru_cache

import sympy as sp

from .symbols import E, F_k, R, d, delta, e, k_1, k_2, mu, omega_c, phi, r, rho, rho_1, rho_1p, rho_2, rho_2p

#: Peak contact pressure symbol σ_max [MPa] used by :func:`approach_by_integral`.
SIGMA_MAX = sp.Symbol("sigma_max", positive=True)

__all__ = [
    "curvature_sum",
    "curvature_difference",
    "link_radii",
    "compliance_k",
    "hertz_solution",
    "pressure",
    "approach_by_integral",
    "approach",
]


def curvature_sum() -> sp.Expr:
    """A + B = ½ Σ 1/ρ [1/mm], the paper's ρ (Eq. 11, first equality)."""
    return (1 / rho_1 + 1 / rho_1p + 1 / rho_2 + 1 / rho_2p) / 2


def curvature_difference() -> sp.Expr:
    """B − A [1/mm] for principal planes at angle ω_c (general Hertz; not in the paper)."""
    a1 = 1 / rho_1 - 1 / rho_1p
    a2 = 1 / rho_2 - 1 / rho_2p
    return sp.sqrt(a1**2 + a2**2 + 2 * a1 * a2 * sp.cos(2 * omega_c)) / 2


def link_radii(contact: str = "outer") -> dict[sp.Symbol, sp.Expr]:
    """Principal radii of two identical crossed links at their contact [mm] (paper Eq. 11).

    Parameters
    ----------
    contact : {"outer", "inner"}
        Radius along the bend.  ``"outer"`` is the paper's ρ′ = −(R + d/2), the
        outer fibre; ``"inner"`` is −(R − d/2), the inner bend surface, which is
        the surface that actually touches the next link.
    """
    if contact == "outer":
        rp = -(R + d / 2)
    elif contact == "inner":
        rp = -(R - d / 2)
    else:
        raise ValueError(f"contact = {contact!r} is invalid: valid values are 'outer', 'inner'")
    return {rho_1: d / 2, rho_2: d / 2, rho_1p: rp, rho_2p: rp}


def compliance_k() -> sp.Expr:
    """k₁ = k₂ = (1 − μ²)/(π E) [1/MPa] (paper, below Eq. 12)."""
    return (1 - mu**2) / (sp.pi * E)


@lru_cache(maxsize=None)
def hertz_solution() -> dict[str, sp.Expr]:
    """Solve the circular Hertz problem for e, p₀ (= σ_max) and δ (paper Eq. 12, 14).

    Unknowns e, p₀, δ; inputs F_k, A + B = ρ (A = B = ρ/2), k₁ + k₂.
    Returns a dict with keys ``"e"`` [mm], ``"sigma_max"`` [MPa], ``"delta"`` [mm].
    Conditions: w₁ + w₂ = δ − (ρ/2) r² for all r ≤ e, and ∫ p dA = F_k.
    """
    p0 = sp.Symbol("p_0", positive=True)
    ksum = k_1 + k_2
    w = sp.pi**2 * ksum * p0 * (2 * e**2 - r**2) / (4 * e)  # w₁ + w₂
    gap = delta - rho / 2 * r**2
    poly = sp.Poly(sp.expand(w - gap), r)
    load = sp.integrate(p0 * sp.sqrt(1 - r**2 / e**2) * 2 * sp.pi * r, (r, 0, e)) - F_k
    eqs = [poly.coeff_monomial(r**2), poly.coeff_monomial(1), load]
    sol = sp.solve(eqs, [p0, delta, e], dict=True)
    sol = [s for s in sol if all(v.is_positive is not False for v in s.values())]
    assert len(sol) == 1, sol
    return {"e": sp.simplify(sol[0][e]), "sigma_max": sp.simplify(sol[0][p0]), "delta": sp.simplify(sol[0][delta])}


def pressure() -> sp.Expr:
    """σ(r) = σ_max √(1 − r²/e²) [MPa] (paper Eq. 13, with r² = x² + y²)."""
    return hertz_solution()["sigma_max"] * sp.sqrt(1 - r**2 / e**2)


def approach_by_integral() -> sp.Expr:
    """δ = (k₁ + k₂) ∬ σ/r ds over the contact, the paper's route (Eq. 14, middle) [mm].

    ds = r dr dφ, so σ/r ds = σ dr dφ; this is the displacement at the centre.
    """
    sig = SIGMA_MAX
    integral = sp.integrate(sp.integrate(sig * sp.sqrt(1 - r**2 / e**2), (r, 0, e)), (phi, 0, 2 * sp.pi))
    return (k_1 + k_2) * integral


def approach(contact: str = "outer") -> sp.Expr:
    """Mutual approach δ(F_k) of two links for the chain geometry [mm] (paper Eq. 14, right side)."""
    sol = hertz_solution()
    radii = link_radii(contact)
    rho_val = sp.simplify(curvature_sum().subs(radii))
    k = compliance_k()
    expr = sol["delta"].subs({rho: rho_val, k_1: k, k_2: k})
    return sp.simplify(sp.powsimp(sp.expand_power_base(expr, force=True), force=True))
