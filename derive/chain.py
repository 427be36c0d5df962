"""The chain: displacement x(F_k), stiffness k_e and the inverse F_k(x) (paper Eq. 15–16).

Model assumptions are explicit (:class:`Assumptions`); each set of assumptions
is one *variant* with its own generated kernel module.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import sympy as sp

from . import hertz, link, section
from .symbols import A_S, E, F_k, G, J_1, J_2, L, R, c_hertz, c_lin, d, mu, n, pitch, u, width, x

__all__ = [
    "Assumptions",
    "VARIANTS",
    "substitutions",
    "link_compliance",
    "chain_displacement",
    "chain_coefficients",
    "stiffness",
    "inverse_cubic",
    "halley_terms",
    "start_value",
    "cardano_root",
    "stiffness_in_u",
]


@dataclass(frozen=True)
class Assumptions:
    """Model assumptions of one kernel variant.

    Attributes
    ----------
    name : str
        Variant name; the kernel module is ``generated/stiffness_<name>.py``.
    contact : {"outer", "inner"}
        Radius along the bend at the contact (paper: outer, −(R + d/2)).
    shear_factor : sympy.Rational
        Shear energy form factor κ (paper: 1; solid circular section: 10/9).
    description : str
        One line for the generated header and the docs.
    """

    name: str
    contact: str = "outer"
    shear_factor: sp.Rational = sp.Integer(1)
    description: str = ""


VARIANTS: dict[str, Assumptions] = {
    a.name: a
    for a in (
        Assumptions("paper", "outer", sp.Integer(1), "the paper's model: contact radius -(R + d/2), no shear form factor"),
        Assumptions("inner_bend", "inner", sp.Integer(1), "contact on the inner bend surface, radius -(R - d/2)"),
        Assumptions("shear", "outer", sp.Rational(10, 9), "shear energy form factor 10/9 of a solid circle"),
        Assumptions(
            "inner_bend_shear", "inner", sp.Rational(10, 9), "inner bend contact and shear form factor 10/9"
        ),
    )
}


def substitutions() -> dict[sp.Symbol, sp.Expr]:
    """Section and material symbols in terms of d, R, E, μ (paper Eq. 4–5; G = E/(2(1 + μ)))."""
    return {
        A_S: section.area(),
        J_1: section.J_straight(),
        J_2: section.J_curved(),
        G: E / (2 * (1 + mu)),
    }


def geometry() -> dict[sp.Symbol, sp.Expr]:
    """R = (b + d)/2 and L = (p − b)/2 in terms of pitch p and inner width b [mm]."""
    return {R: (width + d) / 2, L: (pitch - width) / 2}


@lru_cache(maxsize=None)
def link_compliance(shear_factor: sp.Expr = sp.Integer(1)) -> sp.Expr:
    """Linear compliance of one link, 2ΔL/F_k [mm/N] (paper Eq. 10, 15)."""
    return sp.simplify(link.link_elongation(shear_factor) / F_k)


@lru_cache(maxsize=None)
def chain_displacement(a: Assumptions) -> sp.Expr:
    """x(F_k) = 2n(ΔL₁ + ΔL₂ + ΔL₃) + (n − 1) δ [mm] (paper Eq. 15), section symbols kept."""
    return n * link_compliance(a.shear_factor) * F_k + (n - 1) * hertz.approach(a.contact)


@lru_cache(maxsize=None)
def chain_coefficients(a: Assumptions) -> tuple[sp.Expr, sp.Expr]:
    """(c_lin, c_hertz) with x = c_lin F_k + c_hertz F_k^(2/3), in d, p, b, n, E, μ.

    c_lin [mm/N] is n times the link compliance; c_hertz [mm/N^(2/3)] is
    (n − 1) times the Hertz approach coefficient.
    """
    xs = chain_displacement(a)
    lin = n * link_compliance(a.shear_factor)
    hz = sp.simplify((n - 1) * hertz.approach(a.contact) / F_k ** sp.Rational(2, 3))
    assert not hz.has(F_k) and not lin.has(F_k)
    assert sp.simplify(lin * F_k + hz * F_k ** sp.Rational(2, 3) - xs) == 0
    subs = substitutions()
    geo = geometry()
    lin = lin.subs(subs).subs(geo)
    hz = hz.subs(geo)
    return lin, hz


def stiffness(a: Assumptions) -> sp.Expr:
    """k_e = (∂x/∂F_k)⁻¹ [N/mm] (paper Eq. 16), in terms of F_k and the section symbols."""
    return 1 / sp.diff(chain_displacement(a), F_k)


def generic_displacement() -> sp.Expr:
    """x = c_lin F + c_hertz F^(2/3) [mm] with F = u³ (the form every variant shares)."""
    return c_lin * u**3 + c_hertz * u**2


def inverse_cubic() -> sp.Expr:
    """The cubic c_lin u³ + c_hertz u² − x = 0 in u = F_k^(1/3) (inverse of Eq. 15)."""
    return sp.expand(generic_displacement() - x)


def halley_terms() -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """P(u), P′(u), P″(u) of the inverse cubic, factored for Horner evaluation.

    The kernel takes two Halley steps u ← u − 2PP′/(2P′² − PP″) (cubic
    convergence) and a final Newton step u ← u − P/P′, a fixed number so that
    the loop over an array vectorises.
    """
    P = inverse_cubic()
    d1 = sp.diff(P, u)
    d2 = sp.diff(P, u, 2)
    return sp.horner(P + x, u) - x, sp.horner(d1, u), sp.horner(d2, u)


def start_value() -> sp.Expr:
    """Starting value u₀ of the inverse: 1/u₀² = c_hertz/x + (c_lin/x)^(2/3).

    Each term alone is the root of the cubic with the other coefficient set to
    zero, an upper bound of u; the root-sum of squares blends them within ~6 %.
    """
    return 1 / sp.sqrt(c_hertz / x + (c_lin / x) ** sp.Rational(2, 3))


def cardano_root() -> sp.Expr:
    """The positive root u(x) of the cubic by Cardano, valid where it has one real root.

    With u = (c_hertz/c_lin)·s and x = (c_hertz³/c_lin²)·ξ the cubic is
    s³ + s² = ξ; for ξ > 4/27 it has one real root s = w + 1/(9w) − 1/3 with
    w³ = ξ/2 − 1/27 + √(ξ(ξ − 4/27))/2.  (For ξ ≤ 4/27 the trigonometric form
    applies.)  The kernel uses it only as a reference; see verify.
    """
    xi = sp.Symbol("xi", positive=True)
    w = (xi / 2 - sp.Rational(1, 27) + sp.sqrt(xi * (xi - sp.Rational(4, 27))) / 2) ** sp.Rational(1, 3)
    s_root = w + 1 / (9 * w) - sp.Rational(1, 3)
    return (c_hertz / c_lin * s_root).subs(xi, x * c_lin**2 / c_hertz**3)


def stiffness_in_u() -> sp.Expr:
    """k_e = (dx/dF)⁻¹ with F = u³: 3u/(3 c_lin u + 2 c_hertz) [N/mm] (paper Eq. 16)."""
    Fs = sp.Symbol("F", positive=True)
    xf = c_lin * Fs + c_hertz * Fs ** sp.Rational(2, 3)
    k = 1 / sp.diff(xf, Fs)
    return sp.factor(sp.simplify(k.subs(Fs, u**3)))
