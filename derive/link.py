"""One round link: internal forces, strain energy, Menabrea, Castigliano (paper Eq. 2–10).

A quarter of the link is analysed: the straight half-side AB (length L, A at
the symmetry section) and the quarter bend BC (angle θ from B, radius R, C on
the chain axis where the next link bears).  By symmetry each side carries
N = F_k/2, the shear at A vanishes and the moment M₁ at A is redundant.
"""
from __future__ import annotations

from functools import lru_cache

import sympy as sp

from .symbols import A_S, E, F_k, G, J_1, J_2, L, M_1, N, R, s, theta

__all__ = [
    "internal_forces_straight",
    "internal_forces_curved",
    "strain_energy_parts",
    "strain_energy_quarter",
    "menabrea_moment",
    "energy_in_N",
    "elongation_parts",
    "side_elongation",
    "link_elongation",
]


def internal_forces_straight() -> dict[str, sp.Expr]:
    """Straight segment AB: M = M₁, N = F_k/2, Q = 0 (paper Eq. 2)."""
    return {"M": M_1, "N": F_k / 2, "Q": sp.Integer(0)}


def internal_forces_curved() -> dict[str, sp.Expr]:
    """Curved segment BC at angle θ (paper Eq. 3).

    Equilibrium of the free body from A to the section at θ: the side force
    F_k/2 acts along the chain axis at lever arm R(1 − cos θ) from the
    section, so M_c = M₁ − (F_k/2)·R(1 − cos θ); its components along the
    tangent and the normal of the bar are (F_k/2)cos θ and −(F_k/2)sin θ.
    """
    return {
        "M": M_1 - F_k / 2 * R * (1 - sp.cos(theta)),
        "N": F_k / 2 * sp.cos(theta),
        "Q": -F_k / 2 * sp.sin(theta),
    }


def strain_energy_parts(shear_factor: sp.Expr = sp.Integer(1)) -> dict[str, sp.Expr]:
    """Strain energy of a quarter link by part [N·mm] (paper Eq. 4, integrated).

    Parameters
    ----------
    shear_factor : sympy expression
        Shear energy form factor κ multiplying Q²/(2GA) (paper: 1; solid circle: 10/9).

    Returns
    -------
    dict with keys ``straight`` (axial + bending over AB), ``curved_axial_shear``
    and ``curved_bending`` (over BC, ds = R dθ).
    """
    return dict(_strain_energy_parts(shear_factor))


@lru_cache(maxsize=None)
def _strain_energy_parts(shear_factor: sp.Expr) -> tuple[tuple[str, sp.Expr], ...]:
    """The integrals of :func:`strain_energy_parts`, once per shear factor (the verification, the emission and
    the variants all start from them)."""
    st = internal_forces_straight()
    cu = internal_forces_curved()
    U_AB = sp.integrate(st["N"] ** 2 / (2 * E * A_S) + st["M"] ** 2 / (2 * E * J_1), (s, 0, L))
    U_ax = sp.integrate(
        (cu["N"] ** 2 / (2 * E * A_S) + shear_factor * cu["Q"] ** 2 / (2 * G * A_S)) * R, (theta, 0, sp.pi / 2)
    )
    U_b = sp.integrate(cu["M"] ** 2 / (2 * E * J_2) * R, (theta, 0, sp.pi / 2))
    return (("straight", U_AB), ("curved_axial_shear", U_ax), ("curved_bending", U_b))


def strain_energy_quarter(shear_factor: sp.Expr = sp.Integer(1)) -> sp.Expr:
    """U = U_AB + U_BC of a quarter link as a function of F_k and M₁ [N·mm] (paper Eq. 4)."""
    return sp.Add(*strain_energy_parts(shear_factor).values())


@lru_cache(maxsize=None)
def menabrea_moment() -> sp.Expr:
    """M₁ from θ_A = ∂U/∂M₁ = 0 (paper Eq. 6–7) [N·mm].

    Result: M₁ = (π − 2) R² J₁ F_k / (4 J₂ L + 2 π R J₁).  The shear term does
    not contain M₁, so the result is the same for any shear factor.
    """
    U = strain_energy_quarter()
    sol = sp.solve(sp.Eq(sp.diff(U, M_1), 0), M_1)
    assert len(sol) == 1
    return sp.factor(sol[0])


def energy_in_N(shear_factor: sp.Expr = sp.Integer(1)) -> dict[str, sp.Expr]:
    """Quarter-link energy with M₁ eliminated, as a function of N = F_k/2 (paper Eq. 8), by part."""
    M1 = menabrea_moment()
    return {
        k: sp.expand(v.subs(M_1, M1).subs(F_k, 2 * N)) for k, v in strain_energy_parts(shear_factor).items()
    }


def elongation_parts(shear_factor: sp.Expr = sp.Integer(1)) -> dict[str, sp.Expr]:
    """ΔL₁, ΔL₂, ΔL₃ = ∂U_part/∂N, written in F_k [mm] (paper Eq. 9–10).

    ΔL₁ from the straight segment, ΔL₂ from axial and shear strain of the bend,
    ΔL₃ from bending of the bend.
    """
    parts = energy_in_N(shear_factor)
    names = {"straight": "dL1", "curved_axial_shear": "dL2", "curved_bending": "dL3"}
    return {names[k]: sp.factor(sp.diff(v, N).subs(N, F_k / 2)) for k, v in parts.items()}


def side_elongation(shear_factor: sp.Expr = sp.Integer(1)) -> sp.Expr:
    """ΔL = ∂U/∂N = ΔL₁ + ΔL₂ + ΔL₃ [mm] (paper Eq. 9)."""
    return sp.Add(*elongation_parts(shear_factor).values())


def link_elongation(shear_factor: sp.Expr = sp.Integer(1)) -> sp.Expr:
    """Elongation of one whole link, ∂(4U)/∂F_k by Castigliano [mm] (used in paper Eq. 15).

    The link is four quarters with energy U each, so the elongation is
    4 ∂U/∂F_k = 4 (∂U/∂N)(∂N/∂F_k) = 4 ΔL / 2 = 2 ΔL — the factor 2 of Eq. 15.
    (Menabrea makes ∂U/∂M₁ = 0, so the total and partial derivatives agree.)
    """
    U = strain_energy_quarter(shear_factor).subs(M_1, menabrea_moment())
    return sp.factor(sp.diff(4 * U, F_k))
