"""One batched least-squares fit per cycle (or any segment) of a sampled record, several columns at once.

Both the steady-cycle selection (:mod:`chainid.signal.steady`: x per cycle against 1, a drift and sin/cos of
the phase) and the gap's stationarity trends (:mod:`chainid.gap.harmonic.prepare`: F and x per cycle against 1 and
sin/cos) solve many small normal-equation systems, one per cycle; here the per-segment sums are
accumulated with ``np.bincount`` and all systems solved as one batch, so the cost is O(N) in the samples.
Units are those of the columns.
"""
from __future__ import annotations

from typing import Sequence

import numpy as np

__all__ = ["segment_lstsq"]


def segment_lstsq(seg: np.ndarray, n: int, features: Sequence[np.ndarray], targets: Sequence[np.ndarray],
                  valid: np.ndarray | None = None, rss: bool = False) -> tuple[np.ndarray, np.ndarray | None]:
    """Least squares ``y ≈ Σ_i β_i f_i`` separately on each segment, for several targets y at once.

    Parameters
    ----------
    seg : ndarray of int
        Segment index (0 … n−1) of every sample.
    n : int
        Number of segments.
    features : sequence of ndarray
        The p regressor columns f_i (a column of ones for a constant), one value per sample.
    targets : sequence of ndarray
        The q columns to fit, one value per sample.
    valid : ndarray of bool, optional
        Segments to solve (the others get β = 0); default all.  A solved segment must have a regular system.
    rss : bool
        Also return each segment's residual sum of squares per target.

    Returns
    -------
    beta : ndarray, shape (n, p, q)
        Coefficients per segment, regressor and target.
    rss : ndarray, shape (n, q), or None
        Residual sum of squares per segment and target (with ``rss=True``).
    """
    p, q = len(features), len(targets)

    def S(w: np.ndarray) -> np.ndarray:
        return np.bincount(seg, weights=w, minlength=n)

    G = np.empty((n, p, p))
    R = np.empty((n, p, q))
    for i, fi in enumerate(features):
        for j in range(i, p):
            G[:, i, j] = G[:, j, i] = S(fi * features[j])
        for k, y in enumerate(targets):
            R[:, i, k] = S(fi * y)
    if valid is not None:
        G[~valid] = np.eye(p)
        R[~valid] = 0.0
    beta = np.linalg.solve(G, R)
    if not rss:
        return beta, None
    out = np.empty((n, q))
    for k, y in enumerate(targets):
        res = y - sum(beta[seg, i, k] * fi for i, fi in enumerate(features))
        out[:, k] = S(res * res)
    return beta, out
