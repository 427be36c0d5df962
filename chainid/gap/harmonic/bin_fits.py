"""Closed-form least-squares fits on the bin means of harmonic tests, before any effect is fitted.

* :func:`linear_start`: a linear base's spring, offset and (optionally) mass, with each test's own viscous c_e —
  the start of the nonlinear fit of a linear base (paper Eq. 1 with F_k linear);
* :func:`damping_separable`: whether the plan's frequencies and amplitudes can separate the damping forms of
  Eq. 21.

Units: mm, N, s, kg.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from chainid.gap.harmonic import law_choice as L
from chainid.gap.harmonic.prepare import TestData

__all__ = ["linear_start", "damping_separable"]


def linear_start(train: Sequence[TestData], fit_mass: bool, mass_kg: float = 0.0) -> dict[str, float]:
    """A linear base's spring k [N/mm], x_ref [mm] and, with ``fit_mass``, mass m [kg] >= 0, by linear least squares
    on the training tests' bin means: F̄ = k·x + b + m·ẍ·1e-3 + c_i·ẋ with one viscous c_i per test (each test's
    own c_e, as the harmonic route scores it), rows weighted by √count/σ; x_ref = −b/k.  Without ``fit_mass`` the
    mass is ``mass_kg``.  A resonant device's inertia is in the start (a static fit of F on x reads m·ω² as a
    softer spring, and near resonance as none at all).  Returns {} (the caller keeps its own start) when k <= 0 or
    the columns, each scaled to unit norm, have a condition number over 1e8 (one frequency cannot separate k from
    m).

    Parameters
    ----------
    train : the training tests (bin means F̄ [N], the grid's x [mm], ẋ [mm/s], ẍ [mm/s²], counts, σ [N])
    fit_mass : whether m is fitted
    mass_kg : the mass [kg] when it is not

    Returns
    -------
    dict
        ``spring.k`` [N/mm], ``spring.x_ref`` [mm] and, with ``fit_mass``, ``spring.m`` [kg]; or {}.
    """
    n = len(train)
    p = 2 + int(fit_mass) + n
    rows, ys = [], []
    for i, d in enumerate(train):
        g = d.grid
        xb, vb, ab = d.gridmean(g["x"]), d.gridmean(g["xd"]), d.gridmean(g["xdd"]) * 1e-3
        X = np.zeros((xb.size, p))
        X[:, 0], X[:, 1] = xb, 1.0
        if fit_mass:
            X[:, 2] = ab
        X[:, 2 + int(fit_mass) + i] = vb
        w = np.sqrt(d.counts) / max(d.sigma, 1e-300)
        rows.append(w[:, None] * X)
        ys.append(w * (d.Fbar - (0.0 if fit_mass else mass_kg * ab)))
    A, y = np.vstack(rows), np.concatenate(ys)
    norms = np.linalg.norm(A, axis=0)
    if not np.all(norms > 0) or np.linalg.cond(A / norms) > 1e8:  # e.g. one frequency: k and m not separable
        return {}
    coef, _, rank, _ = np.linalg.lstsq(A, y, rcond=None)
    k = float(coef[0])
    if rank < p or not np.all(np.isfinite(coef)) or k <= 0.0:
        return {}
    out = {"spring.k": k, "spring.x_ref": -float(coef[1]) / k}
    if fit_mass:
        out["spring.m"] = max(float(coef[2]), 0.0)
    return out


def damping_separable(data: Sequence[TestData]) -> tuple[bool, str]:
    """Whether the plan can separate damping forms: >= 3 distinct ω and >= 3 distinct A, full-rank Eq. 21."""
    w = np.array([d.omega for d in data])
    A = np.array([d.A for d in data])
    nw = np.unique(np.round(w / w.max(), 3)).size
    nA = np.unique(np.round(A / A.max(), 3)).size
    X = L.design("polynomial", w, A, np.ones_like(w))
    Xn = X / np.linalg.norm(X, axis=0)
    cond = float(np.linalg.cond(Xn))
    if nw < 3 or nA < 3 or cond > 1e8 or len(data) < 6:
        return False, (
            f"the training plan has {len(data)} tests at {nw} distinct frequencies and {nA} distinct amplitudes "
            f"(cond {cond:.3g}); damping forms (viscous ∝ 1, Coulomb ∝ 1/(ωA), hysteretic ∝ 1/ω, polynomial "
            "Eq. 21) cannot all be separated: add tests at >= 3 frequencies and >= 3 amplitudes"
        )
    return True, ""
