"""The force shapes of each library effect: unit columns times amplitudes, on any sampled motion.

An effect's force is linear in its *amplitude* parameters (:mod:`.library`): for given shape parameters it is
Σ amplitude·column, each column a unit force shape on the motion (a Coulomb sign, a Dahl or Bouc–Wen state, a
dead-band penetration, a cubic).  :func:`columns` gives those columns — the time-domain fit solves for the
amplitudes by least squares — and :func:`effect_force` the effect's whole undamped force on a base model (the
harmonic route's phase grid, the augmented model, ``simulate --effect``; :mod:`.compose` puts them on a base
model).

Memory operators (:mod:`chainid.model.operators`) run on the whole series: ``periodic`` for one period of a
steady cycle (the operator's periodic steady state), otherwise forward from their stated initial state.

Units: x mm, ẋ mm/s, ẍ mm/s², F N, t s, ω rad/s, A mm, m kg (m·ẍ·1e-3 = N).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from chainid.model import operators as ops

__all__ = ["columns", "play_operator", "dahl_operator", "bouc_wen_operator", "stick_slip",
           "sliding_sign", "coulomb_sign", "series_compliance_force", "is_chain"]

#: sgn(ẋ) of Coulomb sliding with 0 at a reversal (one implementation: :func:`chainid.model.operators.coulomb_sign`)
coulomb_sign = ops.coulomb_sign


def is_chain(model: Any) -> bool:
    """Whether a base model is the chain model (its kernel can be modified by the stiffness-side effects)."""
    return hasattr(model, "hertz_scale") and hasattr(model, "compliance") and hasattr(model, "slack")


def play_operator(x: np.ndarray, half_width: float, periodic: bool = True) -> np.ndarray:
    """Backlash (play) operator: output follows x with a dead band ±half_width [mm] (:func:`chainid.model.operators.play`).

    With ``periodic`` the series is run twice and the second pass returned (steady state of a periodic input).
    """
    x = np.ascontiguousarray(x, dtype=np.float64)
    if half_width <= 0:
        return x.copy()
    return ops.play(x, float(half_width), periodic=periodic)


def dahl_operator(x: np.ndarray, F_h: float, x_h: float, periodic: bool = True) -> np.ndarray:
    """Rate-independent Dahl hysteresis force z(x) [N] (:func:`chainid.model.operators.dahl`, z₀ = 0).

    dz/dx = (F_h/x_h)(1 − sgn(ẋ) z/F_h), solved exactly between samples:
    z → ±F_h exponentially over a travel x_h [mm] after each reversal.
    """
    x = np.ascontiguousarray(x, dtype=np.float64)
    if F_h == 0:
        return np.zeros_like(x)
    return ops.dahl(x, float(F_h), max(float(x_h), 1e-9), 0.0, periodic=periodic)[0]


def bouc_wen_operator(x: np.ndarray, F_y: float, x_y: float, n: float, r: float, periodic: bool = True) -> np.ndarray:
    """Bouc–Wen force F_y·z(x) [N] (:func:`chainid.model.operators.bouc_wen`, z₀ = 0)."""
    x = np.ascontiguousarray(x, dtype=np.float64)
    if F_y == 0:
        return np.zeros_like(x)
    return ops.bouc_wen(x, float(F_y), max(float(x_y), 1e-9), float(n), min(max(float(r), 0.0), 1.0),
                        periodic=periodic)[0]


def sliding_sign(xd: np.ndarray, periodic: bool = True, v_err: float | np.ndarray = 0.0) -> np.ndarray:
    """The sign of sliding friction: sgn(ẋ) with 0 at a reversal (:func:`coulomb_sign`) for exact velocities; for a
    velocity estimated with an RMS error ``v_err`` [mm/s] > 0, its expectation given the estimate,
    E[sgn(ẋ) | ẋ̂] = erf(ẋ̂/(√2·v_err)) — the least-squares force where the direction is uncertain (near a
    reversal, at rest), instead of a full 2·F_c jump at a noise-decided sample.  ``v_err`` may vary per sample.

    An instant on a turning point (the one :func:`coulomb_sign` sets to 0: |ẋ| at round-off, the set-valued force at
    its midpoint) is 0 with an estimated velocity too, so the expectation tends to :func:`coulomb_sign` as
    ``v_err`` → 0; an instant near one is still moving and keeps its expectation."""
    ve = np.asarray(v_err, float)
    hard = coulomb_sign(xd, periodic)
    if np.any(ve > 0.0):
        from scipy.special import erf

        soft = erf(np.asarray(xd, float) / (math.sqrt(2.0) * np.maximum(ve, 1e-300)))
        soft = np.where(hard == 0.0, 0.0, soft)
        return np.where(ve > 0.0, soft, hard) if np.any(ve <= 0.0) else soft
    return hard


def stick_slip(x: np.ndarray, xd: np.ndarray, x_s: float, periodic: bool = True,
               v_err: float | np.ndarray = 0.0) -> np.ndarray:
    """Normalised Coulomb friction with elastic stick (Jenkins element), in [-1, 1].

    After a reversal the contact sticks elastically over a travel 2·x_s [mm] before sliding again
    (:func:`chainid.model.operators.jenkins` with F_c = 1); x_s = 0 (or below 1e-4 of the stroke) gives the sign of
    sliding, pure Coulomb friction (:func:`sliding_sign`, with the velocity's error ``v_err`` [mm/s]).
    """
    x = np.asarray(x, dtype=float)
    if x_s <= 1e-4 * (float(np.ptp(x)) if x.size else 0.0):
        # a stick travel below 1e-4 of the stroke is not resolved by any record: pure Coulomb sliding.
        return sliding_sign(xd, periodic, v_err)
    return ops.jenkins(x, 1.0, float(x_s), periodic=periodic)[0]


def series_compliance_force(model: Any, x: np.ndarray, c: float, iters: int = 8) -> np.ndarray:
    """Force of the spring ``model`` in series with a compliance c [mm/N] at total x [mm].

    Solves F = F_k(x − c·F) by Newton iteration (numpy; any StiffnessModel).
    """
    x = np.asarray(x, dtype=float)
    F = np.asarray(model.force(x), dtype=float)
    if c == 0:
        return F
    for _ in range(iters):
        xs = x - c * F
        g = F - np.asarray(model.force(xs), dtype=float)
        k = np.asarray(model.stiffness(xs), dtype=float)
        F = F - g / (1.0 + c * k)
    return F


def columns(name: str, p: dict[str, float], x: np.ndarray, xd: np.ndarray, xdd: np.ndarray,
            Fk: np.ndarray | None = None, periodic: bool = False, v_err: float | np.ndarray = 0.0) -> dict[str, np.ndarray]:
    """Unit force columns [N per unit amplitude] of a force- or mass-kind effect at shape parameters ``p``.

    The effect's force is Σ_a p[a]·columns[a] over its amplitude parameters a.  ``Fk`` is the base spring force
    [N] (``friction``'s load-dependent part μ·|F_k|); omitted columns are those the base cannot carry.  ``v_err``
    [mm/s]: the RMS error of an estimated velocity (the sign of sliding, :func:`sliding_sign`).

    Raises
    ------
    ValueError
        ``name`` is not a force- or mass-kind effect.
    """
    if name == "friction":
        s = stick_slip(x, xd, p.get("x_s", 0.0), periodic, v_err)
        out = {"F_c": s}
        if Fk is not None:
            out["mu"] = np.abs(Fk) * s
        return out
    if name == "stribeck":
        s = sliding_sign(xd, periodic, v_err)
        v_s = max(float(p.get("v_s", 1.0)), 1e-12)
        return {"F_c": s, "dF_s": np.exp(-(np.asarray(xd, float) / v_s) ** 2) * s, "dF": np.abs(s)}
    if name == "hysteresis":
        return {"F_h": dahl_operator(x, 1.0, p.get("x_h", 0.05), periodic)}
    if name == "bouc_wen":
        return {"F_y": bouc_wen_operator(x, 1.0, p.get("x_y", 0.05), p.get("n", 1.0), p.get("r", 1.0), periodic)}
    if name == "deadband":
        u = np.asarray(x, float) - p.get("x_c", 0.0)
        pen = np.maximum(np.abs(u) - p.get("g", 0.0), 0.0)
        return {"k_d": np.sign(u) * pen ** p.get("p", 1.0)}
    if name == "hardening":
        u = np.asarray(x, float) - p.get("x_ref", 0.0)
        return {"k3": u ** 3, "k2": u ** 2}
    if name == "fixture_mass":
        return {"m_f": np.asarray(xdd, float) * 1e-3}
    raise ValueError(f"effect {name!r} has no force columns (a stiffness-side, play, delay or damping effect)")

