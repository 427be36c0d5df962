"""Figures of a chain-line simulation (matplotlib, Agg): tension heat map, drive-end tension, mode shapes.

Every function draws on a new figure and returns it; :func:`save` writes it atomically (chainid.fileio)
and refuses to overwrite an existing file without ``force``.
Units: t s, positions m (from the drive), tension kN.
"""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from chainid.infra.fileio import save_figure  # noqa: E402
from chainid.dynamics.simulation import SimResult  # noqa: E402
from chainid.dynamics.modes import Modes  # noqa: E402

__all__ = ["plot_heatmap", "plot_drive_tension", "plot_modes", "save"]


def plot_heatmap(res: SimResult, title: str = "Tension along the chain") -> plt.Figure:
    """Segment tension [kN] over position along the chain [m] and time [s]."""
    mid = 0.5 * (res.positions[:-1] + res.positions[1:]) * 1e-3
    fig, ax = plt.subplots(figsize=(8.0, 4.4))
    im = ax.pcolormesh(res.t, mid, res.tension.T * 1e-3, shading="nearest", cmap="viridis", rasterized=True)
    fig.colorbar(im, ax=ax, label="tension [kN]")
    ax.set_xlabel("time t [s]")
    ax.set_ylabel("position from the drive [m]")
    ax.set_title(title)
    fig.tight_layout()
    return fig


def plot_drive_tension(res: SimResult, title: str = "Drive-end tension") -> plt.Figure:
    """Tension of the first segment and the drive force [kN] over time [s], with the static level."""
    fig, ax = plt.subplots(figsize=(8.0, 3.6))
    ax.plot(res.t, res.tension[:, 0] * 1e-3, label="segment 1 tension")
    ax.plot(res.t, res.drive_force * 1e-3, lw=0.8, alpha=0.7, label="drive force (incl. drive-node inertia)")
    if res.static_tension > 0:
        ax.axhline(res.static_tension * 1e-3, color="k", ls="--", lw=0.8, label="static (steady) tension")
    ax.set_xlabel("time t [s]")
    ax.set_ylabel("tension [kN]")
    ax.set_title(f"{title} (peak {res.peak_tension * 1e-3:.3g} kN, dynamic factor {res.dynamic_factor:.3g})")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def plot_modes(md: Modes, n: int = 4, title: str = "Mode shapes about the pretension") -> plt.Figure:
    """The first ``n`` mode shapes (normalised to max |φ| = 1) over position [m]."""
    fig, ax = plt.subplots(figsize=(8.0, 3.6))
    x = np.concatenate([[0.0], md.positions]) * 1e-3
    for k in range(min(n, md.omega.size)):
        ax.plot(x, np.concatenate([[0.0], md.shapes[:, k]]), marker=".",
                label=f"mode {k + 1}: {md.frequency_hz[k]:.4g} Hz")
    ax.set_xlabel("position from the drive [m]")
    ax.set_ylabel("shape φ [-]")
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def save(fig: plt.Figure, path: str | Path, force: bool = False, dpi: int = 120) -> Path:
    """Write ``fig`` to ``path`` atomically (chainid.fileio); OutputError (a ValueError) if it exists without ``force``."""
    try:
        return save_figure(fig, path, force=force, what="--plots", dpi=dpi)
    finally:
        plt.close(fig)
