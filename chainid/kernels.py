"""Runtime access to the generated kernels (numpy + numba; never SymPy).

Picks the generated module of a model variant, computes a chain's
coefficients once (cached per :class:`~chainid.spec.ChainSpec`) and applies
the kernels to floats or arrays of any shape.

Numba caching: kernels are compiled lazily on first call and cached on disk
(``cache=True``).  Where the installed package directory is read-only, numba
falls back to a per-user cache directory; set ``NUMBA_CACHE_DIR`` to choose
the cache location explicitly.
"""
from __future__ import annotations

import importlib
from functools import lru_cache
from types import ModuleType
from typing import Union

import numpy as np

from .spec import ChainSpec, default_chain

__all__ = ["VARIANTS", "variant_module", "coefficients", "force", "displacement", "stiffness", "damping_residual"]

ArrayLike = Union[float, np.ndarray]

VARIANTS: tuple[str, ...] = ("paper", "inner_bend", "shear", "inner_bend_shear")


def variant_module(variant: str = "paper") -> ModuleType:
    """The generated kernel module ``chainid.generated.stiffness_<variant>``."""
    if variant not in VARIANTS:
        raise ValueError(f"variant = {variant!r} is invalid: valid variants are {list(VARIANTS)}")
    return importlib.import_module(f"chainid.generated.stiffness_{variant}")


def power_module() -> ModuleType:
    """The generated kernel module of the free-exponent contact law, ``chainid.generated.contact_power``."""
    return importlib.import_module("chainid.generated.contact_power")


@lru_cache(maxsize=256)
def coefficients(chain: ChainSpec | None = None, variant: str = "paper") -> tuple[float, float]:
    """(c_lin [mm/N], c_hertz [mm/N^(2/3)]) with x = c_lin·F + c_hertz·F^(2/3) (paper Eq. 15).

    Raises
    ------
    ValueError
        If the variant's contact model does not apply to the geometry (the
        inner-bend contact needs width > d).
    """
    chain = chain or default_chain()
    mod = variant_module(variant)
    if mod.CONTACT == "inner" and not chain.width > chain.d:
        raise ValueError(
            f"ChainSpec.width = {chain.width!r} is invalid for variant {variant!r}: the inner-bend contact "
            f"radius R - d/2 needs width > d = {chain.d} mm"
        )
    c_lin, c_hertz = mod.coefficients(chain.d, chain.pitch, chain.width, float(chain.n), chain.E, chain.nu)
    if not (np.isfinite(c_lin) and np.isfinite(c_hertz) and c_lin > 0 and c_hertz >= 0):
        raise ValueError(f"chain {chain} gives invalid coefficients c_lin={c_lin}, c_hertz={c_hertz}")
    return float(c_lin), float(c_hertz)


def _apply(kernel_array, values: ArrayLike, *args: float) -> ArrayLike:
    arr = np.asarray(values, dtype=np.float64)
    flat = np.ascontiguousarray(arr).reshape(-1)
    out = kernel_array(flat, *args).reshape(arr.shape)
    if np.ndim(values) == 0:
        return float(out)
    return out


def force(x: ArrayLike, chain: ChainSpec | None = None, variant: str = "paper") -> ArrayLike:
    """Elastic force F_k(x) [N] of the chain at elongation x [mm] (inverse of paper Eq. 15).

    Parameters
    ----------
    x : float or ndarray
        Chain elongation [mm].  x <= 0 gives 0 (a slack chain carries no compression); NaN gives NaN.
    chain : ChainSpec, optional
        The chain; ``None`` is the built-in 14x50 chain (n = 16).
    variant : str
        Model variant (see :data:`VARIANTS`); default the paper's model.

    Returns
    -------
    float or ndarray
        F_k [N], same shape as ``x``.
    """
    c = coefficients(chain, variant)
    return _apply(variant_module(variant).force_array, x, *c)


def displacement(F: ArrayLike, chain: ChainSpec | None = None, variant: str = "paper") -> ArrayLike:
    """Chain elongation x(F) [mm] at tension F [N] (paper Eq. 15).

    Raises
    ------
    ValueError
        If any F < 0 (a chain carries no compression).  NaN gives NaN.
    """
    arr = np.asarray(F, dtype=np.float64)
    if np.any(arr < 0):
        bad = float(arr[arr < 0].reshape(-1)[0])
        raise ValueError(f"F = {bad!r} N is invalid: a chain carries no compression; valid range F >= 0 N")
    c = coefficients(chain, variant)
    return _apply(variant_module(variant).displacement_array, F, *c)


def stiffness(x: ArrayLike, chain: ChainSpec | None = None, variant: str = "paper") -> ArrayLike:
    """Tangent stiffness k_e(x) = (dx/dF)⁻¹ [N/mm] at elongation x [mm] (paper Eq. 16).

    0 for x < 0 (slack); at x = 0 the Hertz contact makes it 0 (n >= 2).
    """
    c = coefficients(chain, variant)
    return _apply(variant_module(variant).stiffness_array, x, *c)


def damping_residual(
    F: np.ndarray, x: np.ndarray, xddot: np.ndarray, chain: ChainSpec | None = None, variant: str = "paper",
    mass_kg: float | None = None,
) -> np.ndarray:
    """Dissipative force F_c = F − m·ẍ·1e-3 − F_k(x) [N] (paper Eq. 17, 20).

    Parameters
    ----------
    F : ndarray
        Measured force [N].
    x : ndarray
        Elongation [mm].
    xddot : ndarray
        Acceleration [mm/s²]; m·ẍ [kg·mm/s²] × 1e-3 = N.
    mass_kg : float, optional
        Moving mass [kg]; default the chain's mass (mass_per_m × length).
    """
    chain = chain or default_chain()
    m = chain.mass_kg if mass_kg is None else float(mass_kg)
    c = coefficients(chain, variant)
    Fa, xa, aa = (np.ascontiguousarray(np.asarray(v, dtype=np.float64)).reshape(-1) for v in (F, x, xddot))
    if not (Fa.shape == xa.shape == aa.shape):
        raise ValueError(f"F, x, xddot must have the same shape; got {Fa.shape}, {xa.shape}, {aa.shape}")
    return variant_module(variant).damping_residual_array(Fa, xa, aa, m, *c).reshape(np.shape(x))
