"""The segment spring of the chain line and its memoryless companion (a dead band with hardening stops), in numba.

Units: elongation mm, force N, stiffness N/mm, energy N·mm.

A segment's spring is the chain kernel with the stiffness-side effects of a diagnosed model applied (see
:class:`chainid.dynamics.model.ChainLine`): its argument is a = (play output or elongation e) − s [mm] (s the
segment's slack), and x(F) = c_lin·F + c_hertz·F^β:

* β flag 0 — the generated Hertz kernel (β = 2/3, paper Eq. 15, ``chainid.generated.stiffness_paper``: every
  variant differs only in its coefficients);
* β > 0 — the generated free-exponent contact kernel (``chainid.generated.contact_power``).

Its stored energy is U(a) = ∫₀^a F da' = F·a − c_lin·F²/2 − c_hertz·F^(β+1)/(β+1) (0 when slack).  The dead band
(effect ``deadband``) is F = k_d·sgn(u)·max(|u| − g, 0)^p with u = e − x_c, potential k_d·max(|u| − g, 0)^(p+1)/(p+1).
Spring table ``sp`` of a line, one row per segment: (β flag, s [mm], k_d [N/mm^p], g [mm], p [-], x_c [mm]).
"""
from __future__ import annotations

import numpy as np
from numba import njit

from chainid.dynamics.energy import elastic_energy
from chainid.generated import contact_power as _power
from chainid.generated.stiffness_paper import force as _force
from chainid.generated.stiffness_paper import stiffness as _stiffness

__all__ = ["spring_force", "spring_stiffness", "spring_energy", "deadband", "deadband_energy",
           "static_elongations", "SP_COLUMNS"]

#: columns of the spring table
SP_COLUMNS = ("beta", "slack", "k_d", "g", "p", "x_c")
_FM = {"contract", "arcp", "nsz"}


@njit(cache=True, fastmath=_FM, error_model="numpy")
def spring_force(a, cl, ch, beta):
    """Spring force [N] at argument a [mm] (0 for a <= 0); β = 0: the Hertz kernel."""
    if beta == 0.0:
        return _force(a, cl, ch)
    return _power.force(a, cl, ch, beta)


@njit(cache=True, fastmath=_FM, error_model="numpy")
def spring_stiffness(a, cl, ch, beta):
    """Tangent stiffness [N/mm] of the spring at argument a [mm] (0 when slack)."""
    if beta == 0.0:
        return _stiffness(a, cl, ch)
    return _power.stiffness(a, cl, ch, beta)


@njit(cache=True, fastmath=_FM, error_model="numpy")
def spring_energy(a, cl, ch, beta):
    """Stored energy U(a) [N·mm] of the spring (0 when slack)."""
    if beta == 0.0:
        return elastic_energy(a, cl, ch)
    if not a > 0.0:
        return 0.0
    F = _power.force(a, cl, ch, beta)
    return F * a - 0.5 * cl * F * F - ch * F ** (beta + 1.0) / (beta + 1.0)


@njit(cache=True, fastmath=_FM, error_model="numpy")
def deadband(u, kd, g, p):
    """(force [N], tangent [N/mm]) of the dead band at u = e − x_c [mm]: k_d·sgn(u)·max(|u| − g, 0)^p."""
    pen = abs(u) - g
    if kd == 0.0 or not pen > 0.0:
        return 0.0, 0.0
    f = kd * pen ** p
    k = kd * p * pen ** (p - 1.0)
    return (f if u > 0.0 else -f), k


@njit(cache=True, fastmath=_FM, error_model="numpy")
def deadband_energy(u, kd, g, p):
    """Potential [N·mm] of the dead band at u = e − x_c [mm]: k_d·max(|u| − g, 0)^(p+1)/(p+1)."""
    pen = abs(u) - g
    if kd == 0.0 or not pen > 0.0:
        return 0.0
    return kd * pen ** (p + 1.0) / (p + 1.0)


@njit(cache=True)
def _static_total(e, cl, ch, beta, s, kd, g, p, xc):
    return spring_force(e - s, cl, ch, beta) + deadband(e - xc, kd, g, p)[0]


@njit(cache=True)
def _static_one(T, cl, ch, beta, s, kd, g, p, xc):
    """sup{e : spring(e − s) + deadband(e − x_c) <= T} by bracketing and bisection (the static total is
    nondecreasing in e)."""
    e0 = s + cl * T + ch * (np.cbrt(T) ** 2 if beta == 0.0 else T ** beta)
    if kd == 0.0:
        return e0
    lo = min(s, xc - g) - 1.0
    hi = max(e0, xc + g)
    step = 1.0 + abs(hi)
    for _ in range(200):
        if _static_total(hi, cl, ch, beta, s, kd, g, p, xc) > T:
            break
        lo = hi
        hi += step
        step *= 2.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid == lo or mid == hi:
            break
        if _static_total(mid, cl, ch, beta, s, kd, g, p, xc) <= T:
            lo = mid
        else:
            hi = mid
    return lo


@njit(cache=True)
def static_elongations(T, cl, ch, sp):
    """Static elongation [mm] of every segment carrying the tension T [N] (>= 0) with its elements unstressed:
    the inverse of spring(e − s) + deadband(e − x_c) = T (closed form without a dead band: s + c_lin·T + c_h·T^β)."""
    out = np.empty(cl.shape[0])
    for j in range(cl.shape[0]):
        out[j] = _static_one(T, cl[j], ch[j], sp[j, 0], sp[j, 1], sp[j, 2], sp[j, 3], sp[j, 4], sp[j, 5])
    return out
