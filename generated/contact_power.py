# GENERATED FILE - DO NOT EDIT.
# Written by `chainid generate` from chainid.derive (the repository's derive/power.py).
# variant: contact_power - chain with a free contact exponent, x = c_lin*F + c_hertz*F**beta
# derivation source hash: 57811e3a2443dd06
# generator: SymPy 1.14.0
# To change the model, edit derive/ and run `chainid generate`; `chainid generate --check` fails when this is stale.
"""Kernels of a chain with a generalised contact law delta = c_hertz*F**beta (beta = 2/3: Hertz).

Used by the gap diagnosis (effect ``contact_law``).  Units: mm, N.  Guards:
F_k(x <= 0) = 0; x(F < 0) = NaN; NaN in gives NaN out.  The inverse is Newton
in s = ln F (monotone from an upper bound: the residual is convex in s).
"""
import math

import numpy as np
from numba import njit

VARIANT = "contact_power"
SOURCE_HASH = "57811e3a2443dd06"
SYMPY_VERSION = "1.14.0"


@njit(cache=True)
def displacement(F, c_lin, c_hertz, beta):
    """Elongation x [mm] at tension F [N]."""
    if F != F or F < 0.0:
        return math.nan
    if F == 0.0:
        return 0.0
    return F*c_lin + F**beta*c_hertz


@njit(cache=True)
def log_force(x, c_lin, c_hertz, beta, s_guess):
    """ln F_k [ln N] at elongation x [mm] (-inf at x <= 0, inf at x = inf, NaN for NaN), Newton in s = ln F
    started at s_guess (NaN: none) or the upper bound, whichever is lower.  From below the root one step lands
    above it (h is convex); every iterate is kept under the bound, so from there it falls monotonically to the
    root, each step shorter than the last.  It stops at a step within the rounding of s and of the residual (a
    few ulp of s plus ~eps/beta), or at a step no shorter than the one before (the rounding, not the root, moves
    it): ln F to a few ulp."""
    if x != x:
        return math.nan
    if x <= 0.0:
        return -math.inf
    if x == math.inf:
        return math.inf
    s_hi = math.log(x / c_lin)
    if c_hertz > 0.0:
        s_hi = min(s_hi, math.log(x / c_hertz) / beta)
    s = s_hi
    if s_guess < s_hi:
        s = s_guess
    tol = 8.9e-16 * (abs(s_hi) + 2.0 / beta)
    last = math.inf
    for _ in range(200):
        F = math.exp(s)
        G = math.exp(beta * s)
        step = (F*c_lin + G*c_hertz - x)/(F*c_lin + G*beta*c_hertz)
        s = min(s - step, s_hi)
        if abs(step) <= tol or (abs(step) >= last and abs(step) <= 1e3 * tol):
            break
        last = abs(step)
    return s


@njit(cache=True)
def force(x, c_lin, c_hertz, beta):
    """Tension F_k [N] at elongation x [mm]."""
    return math.exp(log_force(x, c_lin, c_hertz, beta, math.nan))


@njit(cache=True)
def stiffness(x, c_lin, c_hertz, beta):
    """Tangent stiffness k_e [N/mm] at elongation x [mm]; 0 for x < 0."""
    if x != x:
        return math.nan
    if x < 0.0:
        return 0.0
    if x == 0.0:
        if c_hertz > 0.0 and beta < 1.0:
            return 0.0
        if c_hertz > 0.0 and beta == 1.0:
            return 1.0 / (c_lin + c_hertz)
        return 1.0 / c_lin
    F = force(x, c_lin, c_hertz, beta)
    return F/(F*c_lin + F**beta*beta*c_hertz)


@njit(cache=True)
def force_array(x, c_lin, c_hertz, beta):
    """force() over a 1-D float64 array [mm] -> [N]; each sample's Newton starts at the last finite ln F (a
    record's next sample is close)."""
    out = np.empty(x.shape[0])
    s_last = math.nan
    for i in range(x.shape[0]):
        s = log_force(x[i], c_lin, c_hertz, beta, s_last)
        out[i] = math.exp(s)
        if math.isfinite(s):
            s_last = s
    return out


@njit(cache=True)
def stiffness_array(x, c_lin, c_hertz, beta):
    """stiffness() over a 1-D float64 array [mm] -> [N/mm]."""
    out = np.empty(x.shape[0])
    for i in range(x.shape[0]):
        out[i] = stiffness(x[i], c_lin, c_hertz, beta)
    return out


@njit(cache=True)
def displacement_array(F, c_lin, c_hertz, beta):
    """displacement() over a 1-D float64 array [N] -> [mm]."""
    out = np.empty(F.shape[0])
    for i in range(F.shape[0]):
        out[i] = displacement(F[i], c_lin, c_hertz, beta)
    return out
