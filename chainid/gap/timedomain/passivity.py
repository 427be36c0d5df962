"""A dashpot law over record features that stays passive on every record: the time route's c_r >= 0 by construction.

The time route's dashpot may follow the records' features (the paper's c_e(ω, A) carried to any excitation,
:class:`chainid.gap.timedomain.design.Base`):

    c_r = c + b_w·(ω_r − w_ref) + b_A·(A_r − A_ref)        [N·s/mm; ω rad/s, A mm]

fitted by least squares with the other amplitudes.  Left free, the slopes can take another force's equivalent
damping (a friction's 4F_c/(πωA)) and extrapolate to a negative dashpot at a record of the set — a passive device
fed energy, which ``predict`` and ``dynamics`` refuse.  A linear law is >= 0 on the box of the records' features
[ω_lo, ω_hi] × [A_lo, A_hi] exactly when it is >= 0 at the box's corners, and those laws are exactly the
non-negative combinations

    c_r = z₁·u_r + z₂·(1 − u_r) + z₃·v_r + z₄·(1 − v_r),   z >= 0,
    u_r = (ω_r − ω_lo)/(ω_hi − ω_lo),  v_r = (A_r − A_lo)/(A_hi − A_lo)

(given c >= 0 at every corner, take z₁ − z₂ = b_w·(ω_hi − ω_lo), z₃ − z₄ = b_A·(A_hi − A_lo), the smaller
of each pair 0 plus a share of the least corner value).  :func:`law_map` writes (c, b_w, b_A) = L·z, so the bounded
least squares on z (:func:`chainid.gap.timedomain.lsq.solve`, z >= 0) is the best passive law; the map has a
one-dimensional null space (z₁ + z₂ = z₃ + z₄ trade), which the solver's minimum-norm rule handles.  A feature
whose records all share one value drops out (its slope is 0).  The box is that of every record of the set, held-out
ones included: their features are the measured displacement's, known before any force is predicted.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np

from chainid.gap.timedomain.lsq import solve
from chainid.model.timedamping import feature_c

__all__ = ["LAW_AMPS", "LAW_FEATURES", "HELD_WEIGHT", "law_box", "law_map", "corner_minimum", "lifted", "passive_solve"]

#: the amplitudes of the dashpot law, in the order of the map's rows
LAW_AMPS = ("damping.c", "damping_law.b_w", "damping_law.b_A")
#: the record features the law reads, by its feature key (:func:`chainid.gap.timedomain.design.law_features`)
LAW_FEATURES = (("w", "omega_c"), ("A", "A_c"))


def _spans(box: dict[str, float]) -> list[tuple[str, float, float]]:
    """The law's features with a non-zero span over the records: (name, low, span)."""
    out = []
    for k in ("w", "A"):
        lo, hi = float(box[f"{k}_lo"]), float(box[f"{k}_hi"])
        if hi - lo > 1e-12 * max(abs(hi), abs(lo), 1.0):
            out.append((k, lo, hi - lo))
    return out


def law_map(amps: Sequence[str], lo: np.ndarray, hi: np.ndarray, refs: dict[str, float], box: dict[str, float]
            ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The map a = L·z from the passive coordinates z to the amplitudes ``amps`` (which hold :data:`LAW_AMPS`), and
    the bounds of z.

    Every amplitude other than the law's is its own coordinate, with its bounds ``lo``, ``hi``; the law's three
    take two coordinates z >= 0 per feature with a non-zero span over the records (``box``: ``w_lo``, ``w_hi``
    [rad/s], ``A_lo``, ``A_hi`` [mm]), the corner shares of the module docstring, or one coordinate (c >= 0) when
    neither feature varies.  ``refs``: ``w_ref`` [rad/s] and ``A_ref`` [mm], where c is the law's value.  Returns
    L (len(amps), q) and the coordinates' lower and upper bounds (q,).
    """
    amps = list(amps)
    idx = {k: amps.index(k) for k in LAW_AMPS}
    others = [i for i, k in enumerate(amps) if k not in LAW_AMPS]
    spans = _spans(box)
    q = len(others) + max(2 * len(spans), 1)
    L = np.zeros((len(amps), q))
    zlo, zhi = np.zeros(q), np.full(q, np.inf)
    for j, i in enumerate(others):
        L[i, j] = 1.0
        zlo[j], zhi[j] = lo[i], hi[i]
    j0 = len(others)
    if not spans:
        L[idx["damping.c"], j0] = 1.0
        return L, zlo, zhi
    for s, (k, f_lo, span) in enumerate(spans):
        u_ref = (float(refs[f"{k}_ref"]) - f_lo) / span
        a, b = j0 + 2 * s, j0 + 2 * s + 1           # z·u and z·(1 − u)
        L[idx["damping.c"], a] = u_ref
        L[idx["damping.c"], b] = 1.0 - u_ref
        slope = idx["damping_law.b_w" if k == "w" else "damping_law.b_A"]
        L[slope, a] = 1.0 / span
        L[slope, b] = -1.0 / span
    return L, zlo, zhi


def corner_minimum(c: float, b_w: float, b_A: float, refs: dict[str, float], box: dict[str, float]) -> float:
    """The law's least value over the corners of the records' feature box [N·s/mm] (>= 0: passive on every
    record of the set)."""
    vals = [feature_c(c, b_w, b_A, w, A, refs["w_ref"], refs["A_ref"])
            for w in (box["w_lo"], box["w_hi"]) for A in (box["A_lo"], box["A_hi"])]
    return float(min(vals))


def law_box(records: Sequence[Any], feats: Sequence[str], refs: dict[str, float]) -> dict[str, float]:
    """The box of every record's features (``omega_c`` [rad/s], ``A_c`` [mm]; held-out records included), over
    which the law is kept passive; a feature the law does not follow (not in ``feats``) has no span (its
    reference, ``refs["w_ref"]`` or ``refs["A_ref"]``)."""
    out = {}
    for k, attr in LAW_FEATURES:
        vals = [float(getattr(d, attr)) for d in records]
        lo, hi = (min(vals), max(vals)) if k in feats else (refs[f"{k}_ref"], refs[f"{k}_ref"])
        out[f"{k}_lo"], out[f"{k}_hi"] = lo, hi
    return out


#: a held amplitude of the law is an equality on the passive coordinates, weighed this much over the data's Gram
#: matrix (the weighting method of equality-constrained least squares, Lawson & Hanson ch. 22); the held value is
#: then set exactly
HELD_WEIGHT = 1e6


def passive_solve(G: np.ndarray, h: np.ndarray, lo: np.ndarray, hi: np.ndarray, amps: Sequence[str],
                  refs: dict[str, float], box: dict[str, float], a: np.ndarray,
                  fix: dict[str, float] | None = None) -> np.ndarray:
    """The bounded least-squares amplitudes ``amps`` (minimising aᵀGa − 2hᵀa, lo <= a <= hi) whose dashpot law
    (:data:`LAW_AMPS`, all in ``amps``) is >= 0 on the records' feature box, from the box-bounded optimum ``a``
    (:func:`chainid.gap.timedomain.lsq.solve_held`); amplitudes in ``fix`` are held at their values [their units].

    ``a`` is the answer when its law is passive (every passive law is inside the box bounds: c >= 0 at the
    reference point, inside the box); else the optimum over the passive coordinates of :func:`law_map`, a held law
    amplitude an equality of weight :data:`HELD_WEIGHT`.  A least corner value below 0 by round-off is lifted to 0
    through c (when c is not held)."""
    amps = list(amps)
    fix = dict(fix or {})
    law = [amps.index(k) for k in LAW_AMPS]
    if corner_minimum(*a[law], refs, box) >= 0.0:
        return a
    a = a.copy()
    held = np.array([k in fix for k in amps], bool)
    other = held.copy()
    other[law] = False                              # held amplitudes outside the law: eliminated
    keep = ~other
    names = [k for k, m in zip(amps, keep) if m]
    L, zlo, zhi = law_map(names, lo[keep], hi[keep], refs, box)
    Gz = L.T @ G[np.ix_(keep, keep)] @ L
    hz = L.T @ (h[keep] - G[np.ix_(keep, other)] @ a[other])
    rows = [names.index(k) for k in LAW_AMPS if k in fix]
    if rows:
        E, e = L[rows], np.array([float(fix[names[r]]) for r in rows])
        w = HELD_WEIGHT * max(float(np.max(np.diag(Gz))), 1e-300) / max(float(np.max(np.diag(E.T @ E))), 1e-300)
        Gz, hz = Gz + w * (E.T @ E), hz + w * (E.T @ e)
    a[keep] = L @ solve(Gz, hz, zlo, zhi)
    a[held] = [float(fix[k]) for k, m in zip(amps, held) if m]
    if "damping.c" not in fix:
        a[law[0]] = lifted(*a[law], refs, box)
    return a


def lifted(c: float, b_w: float, b_A: float, refs: dict[str, float], box: dict[str, float]) -> float:
    """c [N·s/mm] raised until the law's least corner value is >= 0 as computed (a boundary optimum's round-off):
    by the shortfall, or by one unit in the last place where adding the shortfall rounds back to c."""
    for _ in range(64):
        gap = corner_minimum(c, b_w, b_A, refs, box)
        if gap >= 0.0:
            break
        c = max(c - gap, float(np.nextafter(c, np.inf)))
    return c
