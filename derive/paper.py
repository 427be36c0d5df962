"""The paper's closed forms, transcribed exactly as printed (for comparison only).

Nothing here is used to build kernels; :mod:`.verify` compares each form with
the first-principles derivation.  Symbols as in :mod:`.symbols`.
"""
from __future__ import annotations

import sympy as sp

from .symbols import A_S, E, F_k, G, J_1, J_2, L, N, R, d, mu, n

__all__ = [
    "eq5_alpha", "eq5_J2", "eq7_M1", "eq7_k0", "eq8_U", "eq10_dL", "eq11_rho",
    "eq12_e", "eq12_sigma_max", "eq14_delta", "eq15_x",
]


def eq5_alpha() -> sp.Expr:
    """Eq. 5: α = R − d² (8R (1 − √(1 − (d/2R)²)))⁻¹."""
    return R - d**2 / (8 * R * (1 - sp.sqrt(1 - (d / (2 * R)) ** 2)))


def eq5_J2() -> sp.Expr:
    """Eq. 5: J₂ = π d⁴/64 + α² A_S."""
    return sp.pi * d**4 / 64 + eq5_alpha() ** 2 * A_S


def eq7_M1() -> sp.Expr:
    """Eq. 7, first equality: M₁ = (π − 2) R² J₁ F_k / (4 J₂ L + 2 J₁ π R)."""
    return (sp.pi - 2) * R**2 * J_1 * F_k / (4 * J_2 * L + 2 * J_1 * sp.pi * R)


def eq7_k0() -> sp.Expr:
    """Eq. 7, as defined below it: k₀ = (π − 2) J₁ R² / (2 L J₂ + π R J₁)."""
    return (sp.pi - 2) * J_1 * R**2 / (2 * L * J_2 + sp.pi * R * J_1)


def eq8_U(k0: sp.Expr) -> sp.Expr:
    """Eq. 8: U(N) with a given k₀ (the paper writes M₁ = k₀ F_k)."""
    return (
        2 * k0**2 * L / (E * J_1)
        + L / (2 * E * A_S)
        + R * sp.pi / (8 * E * A_S)
        + R * sp.pi / (8 * G * A_S)
        + R / (2 * E * J_2) * (sp.pi / 2 * (2 * k0 - R) ** 2 + 2 * R * (2 * k0 - R) + R**2 * sp.pi / 4)
    ) * N**2


def eq10_dL(k0: sp.Expr) -> dict[str, sp.Expr]:
    """Eq. 10: ΔL₁, ΔL₂, ΔL₃ with a given k₀."""
    return {
        "dL1": (2 * k0**2 * L / (E * J_1) + L / (2 * E * A_S)) * F_k,
        "dL2": (R * sp.pi / (8 * E * A_S) + R * sp.pi / (8 * G * A_S)) * F_k,
        "dL3": R / (2 * E * J_2) * (sp.pi / 2 * (2 * k0 - R) ** 2 + 2 * R * (2 * k0 - R) + R**2 * sp.pi / 4) * F_k,
    }


def eq11_rho() -> sp.Expr:
    """Eq. 11: ρ = 4R / (d (2R + d))."""
    return 4 * R / (d * (2 * R + d))


def eq12_e(rho: sp.Expr) -> sp.Expr:
    """Eq. 12: e = (3π F_k (k₁ + k₂) / (4ρ))^(1/3), k₁ = k₂ = (1 − μ²)/(πE)."""
    k = (1 - mu**2) / (sp.pi * E)
    return (3 * sp.pi * F_k * 2 * k / (4 * rho)) ** sp.Rational(1, 3)


def eq12_sigma_max(e: sp.Expr) -> sp.Expr:
    """Eq. 12: σ_max = 3 F_k / (2π e²)."""
    return 3 * F_k / (2 * sp.pi * e**2)


def eq14_delta() -> sp.Expr:
    """Eq. 14: δ = ∛(9 R F_k² (1 − μ²)² / (E² d (2R + d)))."""
    return (9 * R * F_k**2 * (1 - mu**2) ** 2 / (E**2 * d * (2 * R + d))) ** sp.Rational(1, 3)


def eq15_x(k0: sp.Expr) -> sp.Expr:
    """Eq. 15: x = 2n(ΔL₁ + ΔL₂ + ΔL₃) + (n − 1) δ."""
    return 2 * n * sp.Add(*eq10_dL(k0).values()) + (n - 1) * eq14_delta()
