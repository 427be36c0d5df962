"""Energy of the lumped chain: elastic energy of the generated spring, and the energy balance.

Units: energies in N·mm (= mJ); kinetic energy ½·m[kg]·v[mm/s]²·1e-3 N·mm.

Elastic energy of a segment with x = c_lin·F + c_hertz·F^(2/3) (paper Eq. 15), integrated in closed form:
U(e) = ∫₀^e F_k de' = F·e − ∫₀^F x dF' = F·e − c_lin·F²/2 − (3/5)·c_hertz·F^(5/3),  F = F_k(e) from the kernel.
"""
from __future__ import annotations

import numpy as np
from numba import njit

from chainid.generated.stiffness_paper import force as _force

__all__ = ["elastic_energy", "elastic_energy_array", "balance"]

_FM = {"contract", "arcp", "nsz"}


@njit(cache=True, fastmath=_FM, error_model="numpy")
def elastic_energy(e, c_lin, c_hertz):
    """U [N·mm] stored in a segment at elongation e [mm] (0 when slack)."""
    F = _force(e, c_lin, c_hertz)
    u = np.cbrt(F)
    return F * e - 0.5 * c_lin * F * F - 0.6 * c_hertz * u * u * u * u * u


@njit(cache=True, fastmath=_FM, error_model="numpy")
def elastic_energy_array(e, c_lin, c_hertz):
    """Σ U over segments: e, c_lin, c_hertz 1-D arrays [mm], [mm/N], [mm/N^(2/3)] → N·mm."""
    s = 0.0
    for j in range(e.shape[0]):
        s += elastic_energy(e[j], c_lin[j], c_hertz[j])
    return s


def balance(work_in: np.ndarray, kinetic: np.ndarray, elastic: np.ndarray, dissipated: np.ndarray) -> dict:
    """The energy balance W_in = ΔE_kin + ΔE_el + D over a run (arrays over output times, N·mm).

    Returns
    -------
    dict
        ``work_in``, ``kinetic``, ``elastic``, ``dissipated`` (final values, changes for the stored energies),
        ``residual`` (W − ΔE_kin − ΔE_el − D at the end, N·mm) and ``relative_error`` (the largest |residual|
        over the run / the largest |W| over the run; 0 when no work was done).
    """
    res = work_in - (kinetic - kinetic[0]) - (elastic - elastic[0]) - dissipated
    scale = float(np.max(np.abs(work_in))) if work_in.size else 0.0
    return {
        "work_in": float(work_in[-1]),
        "kinetic": float(kinetic[-1] - kinetic[0]),
        "elastic": float(elastic[-1] - elastic[0]),
        "dissipated": float(dissipated[-1]),
        "residual": float(res[-1]),
        "relative_error": float(np.max(np.abs(res)) / scale) if scale > 0 else 0.0,
    }
