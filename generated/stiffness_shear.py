# GENERATED FILE - DO NOT EDIT.
# Written by `chainid generate` from chainid.derive (the repository's derive/).
# variant: shear - shear energy form factor 10/9 of a solid circle
# derivation source hash: 57811e3a2443dd06
# generator: SymPy 1.14.0
# To change the model, edit derive/ and run `chainid generate`; `chainid generate --check` fails when this is stale.
"""Kernels of the chain stiffness, variant ``shear`` (shear energy form factor 10/9 of a solid circle).

x(F) = c_lin*F + c_hertz*F**(2/3)  (paper Eq. 15); k_e = (dx/dF)**-1 (Eq. 16).
Units: mm, N, MPa.  Guards: F_k(x <= 0) = 0 (a slack chain carries no
compression; x below X_TINY mm, where F_k underflows, counts as 0);
x(F < 0) = NaN; NaN in gives NaN out.

The inverse solves c_lin*u**3 + c_hertz*u**2 = x for u = F**(1/3): a start
value within ~10 % (a bit-level cube-root estimate in the blend of the two
one-term roots), two Halley steps (cubic convergence: 1e-1 -> 1e-3 ->
1e-9) and one Newton step (quadratic: 1e-9 -> round-off), which is cheaper
than a third Halley step and as accurate.  No data-dependent loop or
branch, and the numpy error model, so that numba vectorises the array loops.
"""
import math

import numpy as np
from numba import njit, prange, types
from numba.extending import intrinsic

VARIANT = "shear"
SOURCE_HASH = "57811e3a2443dd06"
SYMPY_VERSION = "1.14.0"
CONTACT = "outer"
SHEAR_FACTOR = 1.1111111111111112
X_TINY = 1e-290
_CBRT_MAGIC = 0x2A9F7893782DA1CE  # bits of 2**(1023*2/3 - 1023)..., the classic cube-root bias
_FASTMATH = {"contract", "arcp", "nsz"}


@intrinsic
def _bits(typingctx, v):
    """The IEEE-754 bit pattern of a float64, as int64."""
    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], context.get_value_type(types.int64))
    return types.int64(types.float64), codegen


@intrinsic
def _from_bits(typingctx, v):
    """The float64 with a given int64 bit pattern."""
    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], context.get_value_type(types.float64))
    return types.float64(types.int64), codegen


@njit(cache=True, fastmath=_FASTMATH, error_model="numpy", inline="always")
def _cbrt_estimate(y):
    """y**(1/3) within ~3.5 % for y > 0 (exponent / 3 on the bit pattern)."""
    return _from_bits(np.int64(_bits(y) * 0.3333333333333333) + _CBRT_MAGIC)


@njit(cache=True)
def coefficients(d, pitch, width, n, E, nu):
    """(c_lin [mm/N], c_hertz [mm/N**(2/3)]) of a chain: d, pitch, width mm; n links; E MPa; nu."""
    if not (d > 0.0 and width > 0.0 and pitch > width and n >= 1.0 and E > 0.0 and 0.0 < nu < 0.5):
        return math.nan, math.nan
    t0 = nu + 1.0
    t1 = d*d
    t2 = d + width
    t3 = t2*t2
    t4 = t1/(t2 + math.sqrt(-t1 + t3))**2.0 + 1.0
    t5 = math.pi*t2
    t6 = pitch - width
    t7 = t4*t6
    t8 = 1.0/t0
    t9 = t2*t2*t2*t2*t8
    t10 = math.pi**2.0
    t11 = t1*t10*t3*t4
    t12 = t1*t4*t4
    t13 = t5*t6
    t14 = t7*t8
    t15 = t14*t2*t2*t2
    t16 = t12*t8
    c_lin = (0.05555555555555555)*n*t0*(36.0*t1*t14*t5 + 36.0*t10*t9 + 9.0*t11*t8 + 20.0*t11 + 40.0*t12*t13 + 18.0*t13*t16 - 576.0*t15 + 216.0*math.pi*t15 + 72.0*t16*t6*t6 - 288.0*t9)/(math.pi*E*d*d*d*d*t4*(t5 + 2.0*t7))
    c_hertz = (0.5)*np.cbrt(6.0)**2*np.cbrt(t2)*np.cbrt(1.0 - nu*nu)**2*(n - 1.0)/(np.cbrt(E)**2*np.cbrt(d)*np.cbrt(2.0*d + width))
    return c_lin, c_hertz


@njit(cache=True)
def displacement(F, c_lin, c_hertz):
    """Chain elongation x [mm] at tension F [N] (Eq. 15)."""
    if F != F or F < 0.0:
        return math.nan
    u = np.cbrt(F)
    return c_hertz*u*u + c_lin*u*u*u


@njit(cache=True, fastmath=_FASTMATH, error_model="numpy", inline="always")
def root_u(x, c_lin, c_hertz):
    """u = F_k**(1/3) [N**(1/3)] at elongation x > X_TINY [mm]: positive root of c_lin*u**3 + c_hertz*u**2 = x."""
    u = 1.0/math.sqrt(c_hertz/x + _cbrt_estimate(c_lin/x)**2)
    for _ in range(2):
        P = u*u*(c_hertz + c_lin*u) - x
        dP = u*(2.0*c_hertz + 3.0*c_lin*u)
        d2P = 2.0*c_hertz + 6.0*c_lin*u
        u = u - 2.0 * P * dP / (2.0 * dP * dP - P * d2P)
    P = u*u*(c_hertz + c_lin*u) - x
    dP = u*(2.0*c_hertz + 3.0*c_lin*u)
    return u - P / dP


@njit(cache=True, fastmath=_FASTMATH, error_model="numpy", inline="always")
def force(x, c_lin, c_hertz):
    """Tension F_k [N] at elongation x [mm] (inverse of Eq. 15); 0 for x <= 0, NaN for NaN."""
    xs = x if x > X_TINY else 1.0
    u = root_u(xs, c_lin, c_hertz)
    F = u * u * u
    return F if x > X_TINY else (0.0 if x <= X_TINY else x)


@njit(cache=True, fastmath=_FASTMATH, error_model="numpy", inline="always")
def stiffness(x, c_lin, c_hertz):
    """Tangent stiffness k_e [N/mm] at elongation x [mm] (Eq. 16); 0 for x < 0 (slack), NaN for NaN."""
    xs = x if x > X_TINY else 1.0
    u = root_u(xs, c_lin, c_hertz)
    k = 3.0*u/(2.0*c_hertz + 3.0*c_lin*u)
    k0 = 0.0 if (x < 0.0 or c_hertz > 0.0) else 1.0 / c_lin
    return k if x > X_TINY else (k0 if x <= X_TINY else x)


@njit(cache=True, fastmath=_FASTMATH, error_model="numpy", inline="always")
def damping_residual(F, x, xddot, mass_kg, c_lin, c_hertz):
    """F_c = F - m*xddot*1e-3 - F_k(x) [N] (Eq. 17, 20): F N, x mm, xddot mm/s**2, m kg."""
    return F - mass_kg * xddot * 1e-3 - force(x, c_lin, c_hertz)


@njit(cache=True, fastmath=_FASTMATH, error_model="numpy")
def force_array(x, c_lin, c_hertz):
    """force() over a 1-D float64 array [mm] -> [N]."""
    out = np.empty(x.shape[0])
    for i in range(x.shape[0]):
        out[i] = force(x[i], c_lin, c_hertz)
    return out


@njit(cache=True)
def displacement_array(F, c_lin, c_hertz):
    """displacement() over a 1-D float64 array [N] -> [mm]."""
    out = np.empty(F.shape[0])
    for i in range(F.shape[0]):
        out[i] = displacement(F[i], c_lin, c_hertz)
    return out


@njit(cache=True, fastmath=_FASTMATH, error_model="numpy")
def stiffness_array(x, c_lin, c_hertz):
    """stiffness() over a 1-D float64 array [mm] -> [N/mm]."""
    out = np.empty(x.shape[0])
    for i in range(x.shape[0]):
        out[i] = stiffness(x[i], c_lin, c_hertz)
    return out


@njit(cache=True, fastmath=_FASTMATH, error_model="numpy")
def damping_residual_array(F, x, xddot, mass_kg, c_lin, c_hertz):
    """damping_residual() over 1-D float64 arrays -> [N]."""
    out = np.empty(x.shape[0])
    for i in range(x.shape[0]):
        out[i] = damping_residual(F[i], x[i], xddot[i], mass_kg, c_lin, c_hertz)
    return out


@njit(cache=True, parallel=True, fastmath=_FASTMATH, error_model="numpy")
def force_parallel(x, c_lin, c_hertz):
    """force() over a 1-D float64 array on all cores (prange)."""
    out = np.empty(x.shape[0])
    for i in prange(x.shape[0]):
        out[i] = force(x[i], c_lin, c_hertz)
    return out


@njit(cache=True, parallel=True, fastmath=_FASTMATH, error_model="numpy")
def stiffness_parallel(x, c_lin, c_hertz):
    """stiffness() over a 1-D float64 array on all cores (prange)."""
    out = np.empty(x.shape[0])
    for i in prange(x.shape[0]):
        out[i] = stiffness(x[i], c_lin, c_hertz)
    return out
