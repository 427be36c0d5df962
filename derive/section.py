"""Section properties of the straight and the curved bar (paper Eq. 5).

The curved bar's neutral axis is derived from first principles (Winkler):
a pure bending moment gives zero axial force when ∫ (r − r_n)/r dA = 0, so
r_n = A / ∫ dA/r.  For a circular section of radius c = d/2 centred at radius
R, ∫ dA/r = 2π (R − √(R² − c²)); the offset α = R − r_n is the paper's α.
J₂ = J₁ + α² A_S is the parallel-axis theorem about that axis (the paper's
model; a Winkler curved-beam energy would use A·α·R instead — see verify).
"""
from __future__ import annotations

from functools import lru_cache

import sympy as sp

from .symbols import R, d

__all__ = ["area", "J_straight", "disc_inverse_radius_integral", "neutral_axis_offset", "neutral_axis_offset_stable", "J_curved"]


def area() -> sp.Expr:
    """A_S = π d²/4 [mm²] (paper Eq. 4–5)."""
    return sp.pi * d**2 / 4


@lru_cache(maxsize=None)
def J_straight() -> sp.Expr:
    """J₁ = π d⁴/64 [mm⁴], second moment of a solid circle (paper Eq. 5, second line)."""
    y = sp.Symbol("y", real=True)
    c = d / 2
    # ∫ y² dA over the disc, in strips of width 2√(c² − y²); SymPy's manual integration (the substitution
    # y = c·sin ψ) takes ~0.03 s where its default route through Meijer G-functions takes ~3 s
    return sp.simplify(sp.integrate(y**2 * 2 * sp.sqrt(c**2 - y**2), (y, -c, c), manual=True))


@lru_cache(maxsize=None)
def disc_inverse_radius_integral() -> sp.Expr:
    """∫ dA / r over the bar section at centre radius R [mm] (needed by Eq. 5).

    The disc y = c·sin ψ, strip width 2c·cos ψ, is integrated with the
    tangent half-angle substitution t = tan(ψ/2); R = c + h with h > 0 tells
    SymPy that the section does not reach the bend centre.  The rational
    integrand is integrated term by term over its partial fractions in t
    (~0.3 s; SymPy's integral of the whole fraction takes ~10 s).
    atan(z) + atan(1/z) = π/2 with z = √(R + c)/√(R − c) then gives
    2π (R − √(R² − c²)).
    """
    c = d / 2
    h = sp.Symbol("h", positive=True)
    t = sp.Symbol("t", real=True)
    sn = 2 * t / (1 + t**2)
    cs = (1 - t**2) / (1 + t**2)
    integrand = sp.cancel((2 * c**2 * cs**2 / (R + c * sn) * 2 / (1 + t**2)).subs(R, c + h))
    # each term factored: its coefficient h(d + h) then cancels against the √h·√(d + h) below it
    val = sp.Add(*(sp.factor(sp.integrate(p, (t, -1, 1))) for p in sp.Add.make_args(sp.apart(integrand, t))))
    # atan(z) + atan(1/z) = π/2 for z > 0 (R + c = 2c + h, R − c = h); together() brings each argument to z or 1/z
    z = sp.sqrt(2 * c + h) / sp.sqrt(h)
    val = val.replace(sp.atan, lambda arg: sp.atan(sp.together(arg)))
    val = sp.expand(val.subs(sp.atan(1 / z), sp.pi / 2 - sp.atan(z)))
    assert not val.has(sp.atan), val
    return sp.simplify(sp.expand(val.subs(h, R - c)))


@lru_cache(maxsize=None)
def neutral_axis_offset() -> sp.Expr:
    """α = R − r_n, r_n = A_S / ∫dA/r: offset of the curved bar's neutral axis [mm] (paper Eq. 5, third line)."""
    return sp.simplify(R - area() / disc_inverse_radius_integral())


@lru_cache(maxsize=None)
def neutral_axis_offset_stable() -> sp.Expr:
    """α in a cancellation-free form, c²/(2(R + √(R² − c²))) with c = d/2 [mm].

    R − √(R² − c²) loses digits when d ≪ R; multiplying by the conjugate gives
    this form, which the kernels use.  Checked equal to :func:`neutral_axis_offset`.
    """
    c = d / 2
    stable = c**2 / (2 * (R + sp.sqrt(R**2 - c**2)))
    assert sp.simplify(sp.radsimp(neutral_axis_offset() - stable)) == 0
    return stable


@lru_cache(maxsize=None)
def J_curved() -> sp.Expr:
    """J₂ = J₁ + α² A_S [mm⁴] (paper Eq. 5, first two lines): parallel axis to the neutral axis."""
    return J_straight() + neutral_axis_offset_stable() ** 2 * area()
