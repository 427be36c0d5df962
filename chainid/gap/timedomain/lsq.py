"""Bounded linear least squares on Gram matrices, by block: the amplitude fit of the time-domain route.

For fixed shape parameters the model force is linear in its amplitudes a (spring stiffness, mass, damping, the
effects' forces, covariate slopes): F = f + Φ·a.  Per contiguous time block b of a record the weighted Gram
matrix G_b = Φ_bᵀWΦ_b, the projection h_b = Φ_bᵀW(y_b − f_b) and s_b = (y_b − f_b)ᵀW(y_b − f_b) summarise the
block exactly, so

* the fit on any set of blocks (training, a leave-one-block-out set, a bootstrap resample with multiplicities)
  is the bounded minimum of aᵀGa − 2hᵀa with G, h the (weighted) sums of its blocks' — a p×p problem, p the number
  of amplitudes, whatever the number of samples;
* a block's weighted sum of squared residuals at any a is s_b − 2aᵀh_b + aᵀG_b a.

Bounds (a dashpot, a mass, a friction force are >= 0) are kept by a bounded least-squares solve
(``scipy.optimize.lsq_linear``) on a square root of G when the unconstrained solution leaves them.  Columns are
scaled to a unit diagonal first; directions G cannot see (eigenvalues below 1e-10 of the largest) are left at
zero (minimum norm).

Units: whatever the columns carry (N per unit amplitude); weights 1/σ² [1/N²].
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Blocks", "solve", "solve_held", "sse_at"]

#: eigenvalues of the scaled Gram matrix below this fraction of the largest are not fitted (rank deficiency)
RCOND = 1e-10


@dataclass
class Blocks:
    """Per-block sufficient statistics of a weighted linear least-squares problem.

    ``G`` (n_blocks, p, p), ``h`` (n_blocks, p), ``s`` (n_blocks,): weighted Gram, projection, and sum of squares
    of the target; ``w`` (n_blocks,) the weight 1/σ² each block's samples carry (to undo it), ``n`` (n_blocks,) the
    samples per block.
    """

    G: np.ndarray
    h: np.ndarray
    s: np.ndarray
    w: np.ndarray
    n: np.ndarray

    @classmethod
    def from_columns(cls, Phi: np.ndarray, y: np.ndarray, block: np.ndarray, n_blocks: int, weight: float
                     ) -> "Blocks":
        """Statistics of one record: columns ``Phi`` (n, p), target ``y`` (n,) = F − fixed part, the block index of
        every sample, and the record's weight 1/σ² [1/N²]."""
        p = Phi.shape[1]
        G = np.zeros((n_blocks, p, p))
        h = np.zeros((n_blocks, p))
        s = np.zeros(n_blocks)
        n = np.zeros(n_blocks)
        contiguous = block.size < 2 or bool(np.all(block[1:] >= block[:-1]))
        order = np.arange(block.size) if contiguous else np.argsort(block, kind="stable")
        bounds = np.searchsorted(block[order], np.arange(n_blocks + 1))
        for b in range(n_blocks):
            sl = slice(bounds[b], bounds[b + 1])
            A = Phi[sl] if contiguous else Phi[order[sl]]
            r = y[sl] if contiguous else y[order[sl]]
            G[b] = weight * (A.T @ A)
            h[b] = weight * (A.T @ r)
            s[b] = weight * float(r @ r)
            n[b] = r.size
        return cls(G, h, s, np.full(n_blocks, weight), n)

    @classmethod
    def stack(cls, parts: list["Blocks"]) -> "Blocks":
        """One set of blocks from several records' (in order)."""
        return cls(np.concatenate([b.G for b in parts]), np.concatenate([b.h for b in parts]),
                   np.concatenate([b.s for b in parts]), np.concatenate([b.w for b in parts]),
                   np.concatenate([b.n for b in parts]))

    def total(self, mult: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Σ m_b·G_b and Σ m_b·h_b for block multiplicities ``mult`` (0/1 for a subset, counts for a resample)."""
        return np.tensordot(mult, self.G, axes=1), mult @ self.h


def solve(G: np.ndarray, h: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """The bounded minimiser of aᵀGa − 2hᵀa with lo <= a <= hi (see the module docstring)."""
    p = h.size
    if p == 0:
        return np.zeros(0)
    d = np.sqrt(np.maximum(np.diag(G), 0.0))
    d = np.where(d > 0, d, 1.0)
    Gs = G / np.outer(d, d)
    hs = h / d
    w, V = np.linalg.eigh(0.5 * (Gs + Gs.T))
    keep = w > RCOND * max(float(w.max()), 1e-300)
    if not np.any(keep):
        return np.clip(np.zeros(p), lo, hi)
    inv = np.zeros_like(w)
    inv[keep] = 1.0 / w[keep]
    a = (V * inv) @ (V.T @ hs) / d
    if np.all(a >= lo) and np.all(a <= hi):
        return a
    from scipy.optimize import lsq_linear

    sw = np.sqrt(w[keep])
    M = sw[:, None] * V[:, keep].T          # MᵀM = G_s on its range
    z = (V[:, keep].T @ hs) / sw            # Mᵀz = h_s on its range
    lo_s = np.where(np.isfinite(lo), lo * d, -np.inf)
    hi_s = np.where(np.isfinite(hi), hi * d, np.inf)
    res = lsq_linear(M, z, bounds=(lo_s, hi_s), method="bvls", tol=1e-12, max_iter=500)
    return np.clip(res.x / d, lo, hi)


def solve_held(G: np.ndarray, h: np.ndarray, lo: np.ndarray, hi: np.ndarray, names: list[str],
               fix: dict[str, float] | None = None) -> np.ndarray:
    """:func:`solve` for the amplitudes ``names`` with those in ``fix`` held at their values (eliminated: the rest
    minimise aᵀGa − 2hᵀa with the held part moved to the projection)."""
    fix = fix or {}
    held = np.array([k in fix for k in names], bool)
    if not held.any():
        return solve(G, h, lo, hi)
    a = np.array([float(fix[k]) if k in fix else 0.0 for k in names])
    free = ~held
    a[free] = solve(G[np.ix_(free, free)], h[free] - G[np.ix_(free, held)] @ a[held], lo[free], hi[free])
    return a


def sse_at(bl: Blocks, a: np.ndarray) -> np.ndarray:
    """Weighted sum of squared residuals of every block at amplitudes ``a``: s_b − 2aᵀh_b + aᵀG_b a (>= 0)."""
    return np.maximum(bl.s - 2.0 * (bl.h @ a) + np.einsum("i,bij,j->b", a, bl.G, a), 0.0)
