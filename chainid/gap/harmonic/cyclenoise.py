"""The force noise σ of a steady harmonic test: the scatter of its cycles about their synchronous average.

A bin's measured force is the mean of its samples over the steady cycles (a synchronous, time-domain average:
Braun 1975, *Acustica* 32:69–77), and the noise of that mean is the samples' scatter from cycle to cycle at the same
phase, over the number of samples.  What varies *within* a bin from one phase to the next is not noise: it is the
force's shape, which the model is evaluated on (:func:`chainid.gap.harmonic.prepare.phase_grid` evaluates it at
every 1/q of a bin).  A scatter read within whole bins after a straight line in phase (:func:`bin_noise`) counts
any curvature of the shape as noise, and a jump worst of all: a Coulomb force's 2·F_c step at a reversal put σ at
2.1 times the added noise on the benchmark's strongest friction, and at 1.0–5.6 times (median 1.7) what the
cycles repeat to on the 15 shared MR-damper records, each read as one harmonic test (a magneto-rheological fluid's
step at each reversal; a diagnosis of the set takes the time-domain route, its coil currents differing).

:func:`cycle_noise` reads the scatter within the model grid's own cells (the samples of one bin that fall in the
same 1/q of it: the same phase, on different cycles), after a straight line in time shared by the cells of a bin
(a slow drift over the record) and one in phase (what is left of the shape across a cell's width when the
sampling is not commensurate with the cycle).  Its degrees of freedom are the samples less one mean per cell and
the slopes per bin, pooled over the bins:

    σ² = Σ_b rss_b / Σ_b (n_b − cells_b − slopes_b).

On commensurate sampling the cells hold one sample per cycle at exactly the same phase, and a step between two
samples costs nothing.  A step inside a cell (sampling not commensurate, the step's phase drifting across the
cycles) is scatter that the grid cannot resolve either, and is counted.  A record whose cells hold single samples
(phases that never repeat to within a cell), or that spans one cycle only (its cells' samples are neighbours on
one cycle, not repeats), has no such scatter to read: :func:`cycle_noise` then falls back on :func:`bin_noise`.

Units: t s, F N, ψ rad; σ N.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["COLLINEAR", "grid_cells", "bin_noise", "cycle_noise"]

#: the phase is collinear with time within a group when its part that time does not explain holds less than this
#: share of its sum of squares (10⁻⁶ of its spread; round-off leaves about 10⁻³², a real phase spread within a
#: cell, on sampling not commensurate with the cycle, of order 1)
COLLINEAR = 1e-12


def grid_cells(psi: np.ndarray, bins: np.ndarray, B: int, q: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The model grid's cells of the samples: a cell is a sample's own phase bin and its 1/q of that bin (the
    samples' bins decide membership, so a phase rounded across a bin edge stays in its bin).

    Parameters
    ----------
    psi : numpy.ndarray
        Phase ψ in [0, 2π) [rad] of the samples.
    bins : numpy.ndarray of int
        Each sample's phase bin (0 … B − 1).
    B, q : int
        Phase bins per cycle and cells per bin.

    Returns
    -------
    tuple of numpy.ndarray
        The cells' keys (bin·B·q + the sample's 1/(B·q) of the cycle, ascending; a cell's bin is key // (B·q)), each
        sample's cell index into them, and each cell's count of samples.
    """
    sub = np.minimum((psi / (2 * math.pi) * B * q).astype(np.int64), B * q - 1)
    key = np.asarray(bins, np.int64) * (B * q) + sub
    return np.unique(key, return_inverse=True, return_counts=True)


def _slope_fit(u: np.ndarray, v: np.ndarray, f: np.ndarray, group: np.ndarray, G: int
               ) -> tuple[np.ndarray, np.ndarray]:
    """Per group: the residual sum of squares of f [N²] after straight lines in v (time) and u (phase), all three
    already centred within their cells, and the number of slopes spent.

    The lines are fitted in turn (Gram–Schmidt, the phase orthogonalised against time twice over): the time slope
    where v varies, then the phase slope on the part of u that v does not explain, where that part holds more than
    :data:`COLLINEAR` of u's own sum of squares.  On a phase that drifts with time alone (a commensurate record read
    with a slightly wrong ω, or one cycle) the part is round-off, about 10⁻³² of it, and neither a slope nor a degree
    of freedom is spent on it.  The residual is computed from the projected samples, never as a difference of sums,
    so no ill-conditioned solve enters it."""
    def gsum(y: np.ndarray) -> np.ndarray:
        return np.bincount(group, weights=y, minlength=G)

    def off_v(y: np.ndarray, svv: np.ndarray, has_v: np.ndarray) -> np.ndarray:
        beta = np.where(has_v, gsum(y * v) / np.where(has_v, svv, 1.0), 0.0)
        return y - beta[group] * v

    svv = gsum(v * v)
    has_v = svv > 0.0
    f1 = off_v(f, svv, has_v)
    w = off_v(off_v(u, svv, has_v), svv, has_v)  # the phase's part not explained by time, per group
    sww = gsum(w * w)
    has_w = sww > COLLINEAR * gsum(u * u)
    gam = np.where(has_w, gsum(w * f1) / np.where(has_w, sww, 1.0), 0.0)
    r = f1 - gam[group] * w
    return gsum(r * r), has_v.astype(float) + has_w.astype(float)


def bin_noise(t: np.ndarray, F: np.ndarray, psi: np.ndarray, bins: np.ndarray, B: int) -> float:
    """The pooled within-bin scatter of F [N] after a straight line in phase and time per bin (O(N)).

    Counts a force's shape within a bin as noise (module docstring): :func:`cycle_noise`'s fallback where no cell
    repeats.

    Parameters
    ----------
    t, F, psi : numpy.ndarray
        Time [s], force [N] and phase ψ in [0, 2π) [rad] of the samples.
    bins : numpy.ndarray of int
        Each sample's phase bin (0 … B − 1).
    B : int
        Number of phase bins.

    Returns
    -------
    float
        σ [N]: Σ RSS_b / Σ (n_b − 1 − slopes_b) over the bins with at least 5 samples; the standard deviation of F
        when there are none.
    """
    cnt = np.bincount(bins, minlength=B).astype(float)
    ok = cnt >= 5
    if not np.any(ok):
        return float(np.std(F))

    def bmean(y: np.ndarray) -> np.ndarray:
        return np.bincount(bins, weights=y, minlength=B) / np.maximum(cnt, 1)

    rss, slopes = _slope_fit(psi - bmean(psi)[bins], t - bmean(t)[bins], F - bmean(F)[bins], bins, B)
    dof = cnt - 1.0 - slopes
    keep = ok & (dof > 0)
    total = float(np.sum(dof[keep]))
    return math.sqrt(float(np.sum(rss[keep])) / total) if total > 0 else float(np.std(F))


def cycle_noise(t: np.ndarray, F: np.ndarray, psi: np.ndarray, bins: np.ndarray, B: int, q: int) -> float:
    """The force noise σ [N] of a steady harmonic test: its samples' scatter about their cycles' average at the same
    phase (module docstring).

    Parameters
    ----------
    t, F, psi : numpy.ndarray
        Time [s], force [N] and phase ψ = ωt + θ in [0, 2π) [rad] of the steady window's samples.
    bins : numpy.ndarray of int
        Each sample's phase bin (0 … B − 1).
    B : int
        Number of phase bins.
    q : int
        Cells per bin of the model grid (:data:`chainid.gap.harmonic.prepare.Q`).

    Returns
    -------
    float
        σ [N]: Σ RSS_b / Σ (n_b − cells_b − slopes_b) pooled over the bins with a degree of freedom left, the
        residual after each cell's mean and, per bin, straight lines in t and ψ; :func:`bin_noise` when no bin
        has one (every cell a single sample) or the samples (in time order) span less than 1.5 cycles of ψ.
    """
    wraps = int(np.count_nonzero(np.diff(psi) < -math.pi))  # samples in time order: ψ wraps once a cycle
    if psi.size < 2 or wraps + (psi[-1] - psi[0]) / (2 * math.pi) < 1.5:  # about one cycle: nothing repeats
        return bin_noise(t, F, psi, bins, B)
    ukey, cell, counts = grid_cells(psi, bins, B, q)
    cc = counts.astype(float)

    def cmean(y: np.ndarray) -> np.ndarray:
        return np.bincount(cell, weights=y, minlength=ukey.size) / cc

    u, v, f = psi - cmean(psi)[cell], t - cmean(t)[cell], F - cmean(F)[cell]
    rss, slopes = _slope_fit(u, v, f, bins, B)
    n_b = np.bincount(bins, minlength=B).astype(float)
    cells_b = np.bincount((ukey // (B * q)).astype(np.int64), minlength=B).astype(float)
    dof = n_b - cells_b - slopes
    keep = dof > 0
    total = float(np.sum(dof[keep]))
    if total <= 0:
        return bin_noise(t, F, psi, bins, B)
    return math.sqrt(float(np.sum(rss[keep])) / total)
