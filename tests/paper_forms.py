"""The paper's closed forms typed by hand in plain Python floats: the independent reference for golden values.

Nothing here imports chainid.  Units: mm, N, MPa.  Sources: paper Eq. 5 (α, J₂), Eq. 7 (M₁; k₀ = M₁/F, the
corrected form; ``k0_factor=2`` gives the printed k₀), Eq. 10 (ΔL₁, ΔL₂, ΔL₃), Eq. 14 (Hertz δ), Eq. 15
(x = 2n(ΔL₁ + ΔL₂ + ΔL₃) + (n − 1)δ).  The built-in chain is the 14×50 chain: d = 14, pitch = 50,
width = 17, n = 16, E = 210 000 MPa, ν = 0.3.
"""
from __future__ import annotations

import math

CHAIN = dict(d=14.0, pitch=50.0, width=17.0, n=16, E=210000.0, nu=0.3)


def coefficients(d=14.0, pitch=50.0, width=17.0, n=16, E=210000.0, nu=0.3, contact="outer", kappa=1.0,
                 k0_factor=1.0):
    """(c_lin [mm/N], c_hertz [mm/N^(2/3)]) with x = c_lin·F + c_hertz·F^(2/3)."""
    R, L = (width + d) / 2, (pitch - width) / 2
    A = math.pi * d**2 / 4
    J1 = math.pi * d**4 / 64
    alpha = R - d**2 / (8 * R * (1 - math.sqrt(1 - (d / (2 * R)) ** 2)))
    J2 = J1 + alpha**2 * A
    G = E / (2 * (1 + nu))
    k0 = k0_factor * (math.pi - 2) * R**2 * J1 / (4 * J2 * L + 2 * J1 * math.pi * R)
    dl1 = 2 * k0**2 * L / (E * J1) + L / (2 * E * A)
    dl2 = R * math.pi / (8 * E * A) + kappa * R * math.pi / (8 * G * A)
    dl3 = R / (2 * E * J2) * (math.pi / 2 * (2 * k0 - R) ** 2 + 2 * R * (2 * k0 - R) + R**2 * math.pi / 4)
    if n < 2:
        return 2 * n * (dl1 + dl2 + dl3), 0.0
    if contact == "outer":  # Eq. 14 as printed: δ = (9 R F² (1-ν²)² / (E² d (2R + d)))^(1/3)
        ch = (9 * R * (1 - nu**2) ** 2 / (E**2 * d * (2 * R + d))) ** (1 / 3)
    else:  # inner bend: ½Σ1/ρ = ½(4/d − 2/(R − d/2))
        rho = 0.5 * (4 / d - 2 / (R - d / 2))
        ch = (9 * (1 - nu**2) ** 2 * rho / (4 * E**2)) ** (1 / 3)
    return 2 * n * (dl1 + dl2 + dl3), (n - 1) * ch


def x_of_F(F, **kw):
    """Eq. 15: elongation [mm] at tension F [N]."""
    cl, ch = coefficients(**kw)
    return cl * F + ch * F ** (2 / 3)


def F_of_x(x, **kw):
    """Inverse of Eq. 15 by bisection [N] (x > 0 mm)."""
    lo, hi = 0.0, 1.0
    while x_of_F(hi, **kw) < x:
        hi *= 2
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if x_of_F(mid, **kw) < x:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def k_e(x, **kw):
    """Eq. 16, tangent stiffness [N/mm] = 1/(dx/dF) at F = F(x)."""
    cl, ch = coefficients(**kw)
    F = F_of_x(x, **kw)
    return 1.0 / (cl + (2 / 3) * ch * F ** (-1 / 3))
