"""Stiffness figures (matplotlib, Agg): the paper's Fig. 8a and 8b from the generated kernels."""
from __future__ import annotations

from pathlib import Path
from typing import Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from chainid.model import kernels  # noqa: E402
from chainid.chain.spec import ChainSpec, default_chain  # noqa: E402

__all__ = ["plot_stiffness_vs_length", "plot_stiffness_vs_modulus", "plot_variants"]


def _finish(fig: plt.Figure, ax: plt.Axes, path: str | Path, title: str) -> Path:
    ax.set_xlabel("chain elongation x [mm]")
    ax.set_ylabel("tangent stiffness $k_e$ [N/mm]")
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=9)
    fig.tight_layout()
    from chainid.infra.fileio import save_figure  # temp file + rename

    try:
        return save_figure(fig, path, force=True, dpi=120)
    finally:
        plt.close(fig)


def plot_stiffness_vs_length(path: str | Path, chain: ChainSpec | None = None,
                             n_values: Sequence[int] = (8, 16, 32, 64), x_max: float = 10.0) -> Path:
    """Paper Fig. 8a: k_e(x) for several chain lengths n (x in mm, k_e in N/mm)."""
    chain = chain or default_chain()
    x = np.linspace(0.0, x_max, 600)
    fig, ax = plt.subplots(figsize=(8.4, 4.2))
    for n in n_values:
        c = chain.replace(n=int(n))
        ax.plot(x, kernels.stiffness(x, c), label=f"n = {n} ({c.length_mm:.0f} mm)")
    return _finish(fig, ax, path, f"Stiffness vs chain length (d = {chain.d:g} mm, E = {chain.E:g} MPa)")


def plot_stiffness_vs_modulus(path: str | Path, chain: ChainSpec | None = None,
                              factors: Sequence[float] = (0.5, 0.75, 1.0, 1.25, 1.5), x_max: float = 10.0) -> Path:
    """Paper Fig. 8b: k_e(x) for several Young's moduli E = factor × E₀ (n fixed)."""
    chain = chain or default_chain()
    x = np.linspace(0.0, x_max, 600)
    fig, ax = plt.subplots(figsize=(8.4, 4.2))
    for f in factors:
        c = chain.replace(E=chain.E * f)
        ax.plot(x, kernels.stiffness(x, c), label=f"E = {f:g} E₀ = {c.E / 1000:g} GPa")
    return _finish(fig, ax, path, f"Stiffness vs Young's modulus (n = {chain.n}, E₀ = {chain.E / 1000:g} GPa)")


def plot_variants(path: str | Path, chain: ChainSpec | None = None, x_max: float = 5.0) -> Path:
    """k_e(x) of every model variant (contact curvature, shear factor) for one chain."""
    chain = chain or default_chain()
    x = np.linspace(0.0, x_max, 600)
    fig, ax = plt.subplots(figsize=(8.4, 4.2))
    for v in kernels.VARIANTS:
        try:
            ax.plot(x, kernels.stiffness(x, chain, v), label=v)
        except ValueError:
            continue
    return _finish(fig, ax, path, "Stiffness of the model variants")
