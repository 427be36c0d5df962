"""Energy of the lumped chain: elastic energy of the generated spring, and the energy balance.

Units: energies in N·mm (= mJ); kinetic energy ½·m[kg]·v[mm/s]²·1e-3 N·mm.

Elastic energy of a segment with x = c_lin·F + c_hertz·F^(2/3) (paper Eq. 15), integrated in closed form:
U(e) = ∫₀^e F_k de' = F·e − ∫₀^F x dF' = F·e − c_lin·F²/2 − (3/5)·c_hertz·F^(5/3),  F = F_k(e) from the kernel.
"""
from __future__ import annotations

import math

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


def balance(work_in: np.ndarray, kinetic: np.ndarray, elastic: np.ndarray, dissipated: np.ndarray,
            t: np.ndarray | None = None) -> dict:
    """The energy balance W_in = ΔE_kin + ΔE_el + D over a run (arrays over output times, N·mm), at its WORST point.

    The residual r(t) = W − ΔE_kin − ΔE_el − D is evaluated at every output time; the balance reports the
    output time where |r| is largest (not the last one: an error that later cancels must not hide).

    Parameters
    ----------
    work_in, kinetic, elastic, dissipated : ndarray
        Energies over the output times [N·mm].
    t : ndarray, optional
        Output times [s] (for ``worst_t_s``).

    Returns
    -------
    dict
        ``work_in``, ``kinetic``, ``elastic``, ``dissipated`` (final values, changes for the stored energies),
        ``residual`` (at the end, N·mm), ``worst_residual`` (the largest |r|, signed, N·mm), ``worst_t_s`` (its
        time, or its output index without ``t``), ``relative_error`` (|worst_residual| / the energy scale,
        floored as below),
        ``scale`` (the energy scale: the largest over the run of |W|, |ΔE_kin|, |ΔE_el| and |D|, N·mm; so
        that a free vibration without work input is measured too) and ``finite`` (all energies finite).
        ``relative_error`` is 0 when nothing happened (scale 0) and nan when an energy is not finite.  Its
        denominator is at least 1e-9 of the largest stored energy |E_kin|, |E_el|: the round-off of the stored
        energies (a chain at rest) is not an integration error.
    """
    dk = kinetic - kinetic[0]
    de = elastic - elastic[0]
    res = work_in - dk - de - dissipated
    finite = bool(np.all(np.isfinite(res)))
    if not finite:
        return {"work_in": float(work_in[-1]), "kinetic": float(dk[-1]), "elastic": float(de[-1]),
                "dissipated": float(dissipated[-1]), "residual": float(res[-1]), "worst_residual": math.nan,
                "worst_t_s": math.nan, "relative_error": math.nan, "scale": math.nan, "finite": False}
    scale = float(max(np.max(np.abs(work_in)), np.max(np.abs(dk)), np.max(np.abs(de)), np.max(np.abs(dissipated))))
    k = int(np.argmax(np.abs(res)))
    den = max(scale, 1e-9 * float(max(np.max(np.abs(kinetic)), np.max(np.abs(elastic)))))
    return {
        "work_in": float(work_in[-1]),
        "kinetic": float(dk[-1]),
        "elastic": float(de[-1]),
        "dissipated": float(dissipated[-1]),
        "residual": float(res[-1]),
        "worst_residual": float(res[k]),
        "worst_t_s": float(t[k]) if t is not None else float(k),
        "relative_error": float(abs(res[k]) / den) if den > 0 else 0.0,
        "scale": scale,
        "finite": True,
    }
