"""Natural frequencies and mode shapes of the pre-tensioned chain about its static state.

The equations of motion linearised about the uniform pretension (every segment at e_pre, the drive node
held, a fixed far end held or a tensioner node free with its take-up stiffness) are M·ü + K·u = 0 with the
lumped masses M [kg] and the tridiagonal tangent stiffness K [N/mm] of the segment tangents k_j = k_e(e_pre)
(the generated stiffness kernel, Eq. 16).  With ü in mm/s² (m·ü·1e-3 = N), ω² are the eigenvalues of
1e3·M^(-1/2) K M^(-1/2), a symmetric tridiagonal matrix: scipy.linalg.eigh_tridiagonal computes only the
lowest ``n_modes`` (bisection + inverse iteration, O(N) memory per mode; 20 000 masses in well under a second
for 4 modes, where a dense eigh needs N² memory).  Units: ω rad/s, f Hz, shapes dimensionless.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from scipy.linalg import eigh_tridiagonal

from chainid.dynamics.model import ChainLine

__all__ = ["Modes", "modes", "tangent_system", "tangent_tridiagonal"]


@dataclass(frozen=True)
class Modes:
    """Modes of the pre-tensioned chain.

    Attributes
    ----------
    omega : (n,) rad/s, ascending
    frequency_hz : (n,) Hz
    shapes : (n_free, n) mass-normalised mode shapes scaled to max |φ| = 1 (columns)
    nodes : (n_free,) node indices of the free nodes (1 .. N or N−1)
    positions : (n_free,) positions of the free nodes from the drive [mm]
    """

    omega: np.ndarray
    frequency_hz: np.ndarray
    shapes: np.ndarray
    nodes: np.ndarray
    positions: np.ndarray


def tangent_tridiagonal(line: ChainLine) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(M [kg], diagonal [N/mm], off-diagonal [N/mm] of K, free node indices) linearised about the pretension.

    K_aa = k_(i-1) + k_i (k_N = the tensioner stiffness for the free tensioner node), K_a,a+1 = −k_i, with the
    segment tangents k_j = k_e(e_pre) of the generated kernel (:meth:`ChainLine.static_tangent`: with the diagnosed
    spring modifiers and dead band; a play taken engaged, the memory elements not counted).
    """
    k = line.static_tangent()
    N = line.n_masses
    last = N if line.far_end == "tensioner" else N - 1
    nodes = np.arange(1, last + 1)
    k_next = np.append(k[1:], line.tensioner_stiffness)[:last]  # k_i for node i (k_N: the take-up spring)
    diag = k[:last] + k_next
    off = -k[1:last]
    return line.node_masses()[nodes], diag, off, nodes


def tangent_system(line: ChainLine) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(M [kg] diagonal, K [N/mm] tridiagonal matrix as a dense array, free node indices); small N only."""
    M, d, e, nodes = tangent_tridiagonal(line)
    K = np.diag(d) + np.diag(e, 1) + np.diag(e, -1)
    return M, K, nodes


def modes(line: ChainLine, n_modes: int | None = None) -> Modes:
    """Natural frequencies and mode shapes about the pre-tensioned static state (drive end held).

    Parameters
    ----------
    line : ChainLine
    n_modes : int, optional
        Keep the lowest n_modes (>= 1); default all.

    Returns
    -------
    Modes
        Empty arrays when no node is free (one segment with a fixed far end).
    """
    if n_modes is not None and (isinstance(n_modes, bool) or not isinstance(n_modes, (int, np.integer))
                                or n_modes < 1):
        raise ValueError(f"n_modes = {n_modes!r} is invalid: valid range None or an int >= 1")
    M, d, e, nodes = tangent_tridiagonal(line)
    pos = np.concatenate([[0.0], np.cumsum(line.segment_lengths())])[nodes]
    if nodes.size == 0:
        z = np.zeros(0)
        return Modes(z, z, np.zeros((0, 0)), nodes, pos)
    s = 1.0 / np.sqrt(M)
    n = nodes.size
    k = n if n_modes is None else min(int(n_modes), n)
    lam, y = eigh_tridiagonal(1e3 * d * s * s, 1e3 * e * s[:-1] * s[1:], select="i", select_range=(0, k - 1))
    lam = np.clip(lam, 0.0, None)
    phi = s[:, None] * y
    phi /= np.max(np.abs(phi), axis=0)[None, :]
    phi *= np.sign(phi[np.argmax(np.abs(phi), axis=0), np.arange(phi.shape[1])])[None, :]
    w = np.sqrt(lam)
    return Modes(w, w / (2.0 * math.pi), phi, nodes, pos)
