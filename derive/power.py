"""A generalised contact law for the gap diagnosis: δ = c_hertz·F^β instead of Hertz's β = 2/3.

The chain displacement becomes x = c_lin·F + c_hertz·F^β (paper Eq. 15 with the
contact exponent free): β = 2/3 is Hertz (point contact), β → 1 a conformal
contact after proof loading (plastic set), β < 2/3 a stiffening contact.
The inverse has no closed form; with F = e^s the residual
h(s) = c_lin·e^s + c_hertz·e^(βs) − x is increasing and convex in s, so Newton
from an upper bound converges monotonically.
"""
from __future__ import annotations

import sympy as sp

from .symbols import c_hertz, c_lin, x

__all__ = ["beta", "s_log", "displacement", "log_residual", "newton_update_log", "stiffness"]

beta = sp.Symbol("beta", positive=True)   # contact exponent
s_log = sp.Symbol("s", real=True)         # ln F
F = sp.Symbol("F", positive=True)         # tension, N
G = sp.Symbol("G", positive=True)         # F^β, the contact term's power of the tension


def displacement() -> sp.Expr:
    """x = c_lin F + c_hertz F^β [mm] (Eq. 15 with a free contact exponent)."""
    return c_lin * F + c_hertz * F**beta


def log_residual() -> sp.Expr:
    """h(s) = x(e^s) − x, the inverse problem in s = ln F."""
    return displacement().subs(F, sp.exp(s_log)) - x


def newton_update_log() -> sp.Expr:
    """The Newton step h(s)/h′(s), written in F = e^s and G = e^(βs) = F^β (the kernel computes both from s with
    one exponential each, no power)."""
    h = log_residual()
    step = sp.simplify(h / sp.diff(h, s_log))
    return sp.simplify(step.subs(sp.exp(beta * s_log), G).subs(sp.exp(s_log), F))


def stiffness() -> sp.Expr:
    """k_e = (dx/dF)⁻¹ = 1/(c_lin + β c_hertz F^(β−1)) [N/mm] (Eq. 16)."""
    return sp.simplify(1 / sp.diff(displacement(), F))
