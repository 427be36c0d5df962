"""Forward prediction, paper Eq. 1: F = m xddot + F_k(x) + c_e xdot.

:func:`inertia_force_N` converts the mass term to consistent units and
:func:`predict_force` evaluates the one-mass model for a displacement record.
Both are re-exported by :mod:`chainid.damping.identify`.

Units: mm, N, s, kg; omega in rad/s.
"""
from __future__ import annotations

from typing import Any

import numpy as np

from chainid.signal.harmonic import estimate_harmonic
from chainid.model.laws import CombinedLaw, DampingLaw, HystereticLaw, StiffnessLike

__all__ = ["inertia_force_N", "predict_force"]


def inertia_force_N(m_kg: float | np.ndarray, xddot_mm_s2: float | np.ndarray) -> float | np.ndarray:
    """Inertial force F_m = m xddot (Eq. 1) in consistent units.

    Parameters
    ----------
    m_kg : float or ndarray
        Mass [kg].
    xddot_mm_s2 : float or ndarray
        Acceleration [mm/s²].

    Returns
    -------
    float or ndarray
        Force [N] = m [kg] · xddot [mm/s²] · 1e-3 [m/mm].
    """
    return np.multiply(m_kg, xddot_mm_s2) * 1e-3


def predict_force(
    t: Any,
    x: Any,
    model: StiffnessLike,
    law_or_ce: DampingLaw | float,
    *,
    omega: float | None = None,
    A: float | None = None,
    x0: float | None = None,
    xdot: Any = None,
    xddot: Any = None,
    mass_kg: float | None = None,
) -> np.ndarray:
    """Force response F = m xddot + F_k(x) + c_e xdot (Eq. 1).

    Parameters
    ----------
    t : array_like
        Time [s].
    x : array_like
        Elongation [mm].
    model : StiffnessModel
        F_k(x) [N] and mass [kg].
    law_or_ce : DampingLaw or float
        A fitted law evaluated at (omega, A, x0), or a constant c_e [N·s/mm].
    omega, A, x0 : float, optional
        Test parameters [rad/s, mm, mm] for the law; estimated from x(t) if omitted.
    xdot, xddot : array_like, optional
        Velocity [mm/s] and acceleration [mm/s²]; by default ``numpy.gradient`` of x.
    mass_kg : float, optional
        Default ``model.mass_kg``.

    Returns
    -------
    ndarray
        F [N], same shape as x.
    """
    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float)
    v = np.gradient(x, t) if xdot is None else np.asarray(xdot, dtype=float)
    acc = np.gradient(v, t) if xddot is None else np.asarray(xddot, dtype=float)
    if isinstance(law_or_ce, DampingLaw):
        if omega is None or A is None or (x0 is None and isinstance(law_or_ce, (HystereticLaw, CombinedLaw))):
            est = estimate_harmonic(t, x)
            omega = est.omega if omega is None else omega
            A = est.A if A is None else A
            x0 = est.x0 if x0 is None else x0
        c = float(law_or_ce.predict(omega, A, x0)[0])
    else:
        c = float(law_or_ce)
    m = float(model.mass_kg if mass_kg is None else mass_kg)
    return inertia_force_N(m, acc) + np.asarray(model.force(x), dtype=float) + c * v
