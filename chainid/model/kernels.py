"""Runtime access to the generated kernels (numpy + numba; never SymPy).

Picks the generated module of a model variant, computes a chain's
coefficients once (cached per :class:`~chainid.chain.spec.ChainSpec`) and applies
the kernels to floats or arrays of any shape.

Numba caching: kernels are compiled lazily on first call and cached on disk
(``cache=True``).  Where the installed package directory is read-only, numba
falls back to a per-user cache directory; where that is not writable either,
chainid falls back to a private folder in the temporary directory and then to
no disk cache, with one :class:`~chainid.infra.numba_cache.NumbaCacheWarning`; a
corrupt cache entry is recompiled; ``NUMBA_DISABLE_JIT=1`` runs the kernels as
plain Python (see :mod:`chainid.infra.numba_cache`).  Set ``NUMBA_CACHE_DIR`` to
choose the cache location explicitly.

Input conventions of :func:`force`, :func:`displacement`, :func:`stiffness`
(numpy's for numbers, SciPy's for errors): Python or numpy real scalars,
integer or float arrays of any shape and lists of numbers are accepted (computed
in float64); a 0-d input gives a Python float; a masked array gives a masked
array with the same mask; NaN gives NaN; +inf gives the limit.  bool, complex,
datetime64/timedelta64, None, strings and object arrays raise ``TypeError``.
"""
from __future__ import annotations

import contextlib
import os
from functools import lru_cache
from types import ModuleType
from typing import Any, Union

import numpy as np

from chainid.infra.numba_cache import cache_mode, load_kernel_module
from chainid.chain.spec import ChainSpec, default_chain, load_chain

__all__ = [
    "VARIANTS", "variant_module", "coefficients", "force", "displacement", "stiffness", "damping_residual",
    "resolve_chain", "as_real_array",
]

ArrayLike = Union[float, np.ndarray]
ChainLike = Union[ChainSpec, str, "os.PathLike[str]", None]

VARIANTS: tuple[str, ...] = ("paper", "inner_bend", "shear", "inner_bend_shear")


_MODULES: dict[str, ModuleType] = {}


def variant_module(variant: str = "paper") -> ModuleType:
    """The generated kernel module ``chainid.generated.stiffness_<variant>``."""
    mod = _MODULES.get(variant) if isinstance(variant, str) else None
    if mod is None:
        if variant not in VARIANTS:
            raise ValueError(f"variant = {variant!r} is invalid: valid variants are {list(VARIANTS)}")
        mod = _MODULES[variant] = load_kernel_module(f"stiffness_{variant}")
    return mod


def power_module() -> ModuleType:
    """The generated kernel module of the free-exponent contact law, ``chainid.generated.contact_power``."""
    return load_kernel_module("contact_power")


def resolve_chain(chain: Any) -> ChainSpec:
    """The :class:`ChainSpec` named by ``chain``.

    Parameters
    ----------
    chain : ChainSpec or str or os.PathLike or None
        A spec; ``None`` for the built-in 14x50 chain (n = 16); a str or path is
        passed to :func:`chainid.chain.spec.load_chain` (a TOML file; units mm, MPa, kg/m).

    Raises
    ------
    TypeError
        For any other type (named in the message).
    ValueError
        From :func:`~chainid.chain.spec.load_chain` for a missing or invalid file.
    """
    if chain is None:
        return default_chain()
    if isinstance(chain, ChainSpec):
        return chain
    if isinstance(chain, (str, os.PathLike)):
        return load_chain(chain)
    raise TypeError(
        f"chain must be a ChainSpec, None or a path to a chain TOML file (str or os.PathLike), "
        f"not {type(chain).__name__}"
    )


@lru_cache(maxsize=256)
def _coefficients(chain: ChainSpec, variant: str) -> tuple[float, float]:
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


def coefficients(chain: ChainLike = None, variant: str = "paper") -> tuple[float, float]:
    """(c_lin [mm/N], c_hertz [mm/N^(2/3)]) with x = c_lin·F + c_hertz·F^(2/3) (paper Eq. 15).

    Parameters
    ----------
    chain : ChainSpec or str or os.PathLike or None
        See :func:`resolve_chain` (cached per resolved spec, so a changed file is re-read).
    variant : str
        Model variant (see :data:`VARIANTS`).

    Raises
    ------
    ValueError
        If the variant's contact model does not apply to the geometry (the
        inner-bend contact needs width > d).
    TypeError
        For a ``chain`` of another type.
    """
    if not isinstance(variant, str):
        raise TypeError(f"variant must be a str (one of {list(VARIANTS)}), not {type(variant).__name__}")
    return _coefficients(resolve_chain(chain), variant)


_KIND_NAMES = {"b": "bool", "c": "complex", "M": "datetime64", "m": "timedelta64", "O": "object",
               "U": "str", "S": "bytes", "V": "void"}


def as_real_array(values: Any, name: str, unit: str) -> tuple[np.ndarray, np.ndarray | None, bool]:
    """Check and convert numeric input the way numpy's real-valued functions take it.

    Parameters
    ----------
    values : scalar, array_like or numpy.ma.MaskedArray
        Real numbers (int or float, any shape, lists accepted).
    name, unit : str
        Argument name and unit for the error message (e.g. ``"x"``, ``"mm"``).

    Returns
    -------
    (ndarray, ndarray or None, bool)
        The values as a C-contiguous float64 array (masked entries set to 0), the
        boolean mask of a masked input (else None), and whether the input was 0-d.

    Raises
    ------
    TypeError
        For bool, complex, datetime64/timedelta64, None, str/bytes and object input.
    """
    mask = None
    if isinstance(values, np.ma.MaskedArray):
        mask = np.ma.getmaskarray(values)
        data = np.asarray(values.data)
    elif values is None or isinstance(values, (str, bytes, bool)):
        raise TypeError(f"{name} must be a real number or an array of real numbers [{unit}], "
                        f"not {type(values).__name__}")
    else:
        data = np.asarray(values)
    kind = data.dtype.kind
    if kind not in "iuf":
        raise TypeError(f"{name} must be a real number or an array of real numbers [{unit}], "
                        f"not {_KIND_NAMES.get(kind, str(data.dtype))} (dtype {data.dtype})")
    arr = np.ascontiguousarray(data, dtype=np.float64)
    if mask is not None and mask.any():
        arr = np.where(mask, 0.0, arr)
    return arr, mask, data.ndim == 0


def _finish(out: np.ndarray, mask: np.ndarray | None, scalar: bool) -> Any:
    """Shape the kernel output like the input: Python float for 0-d, masked array for masked input."""
    if mask is not None:
        if scalar:
            return np.ma.masked if bool(mask) else float(out.reshape(()))
        return np.ma.MaskedArray(out, mask=mask.copy())
    if scalar:
        return float(out.reshape(()))
    return out


#: Above this elongation [mm] F_k follows the two-term asymptote of Eq. 15 (the kernels' Halley
#: iteration overflows near 1e200 mm); the neglected term is (c_hertz/c_lin)² (F)^(-2/3) relative,
#: < 1e-30 for any valid chain.
X_LINEAR = 1e60


def _large_x(flat: np.ndarray, out: np.ndarray, kind: str, c_lin: float, c_hertz: float) -> None:
    """Overwrite ``out`` where x > :data:`X_LINEAR` (incl. +inf) by the asymptote of Eq. 15/16."""
    if flat.size == 1:  # the common scalar call: a float comparison instead of array operations
        if not flat[0] > X_LINEAR:
            return
    big = flat > X_LINEAR
    if not big.any():
        return
    with np.errstate(over="ignore", divide="ignore"):
        q = flat[big] / c_lin
        F = q * (1.0 - (c_hertz / c_lin) / np.cbrt(q))
        out[big] = F if kind == "force" else 1.0 / (c_lin + (2.0 / 3.0) * c_hertz / np.cbrt(F))


def _quiet() -> Any:
    """The kernels' numpy error model (no warnings) on the NUMBA_DISABLE_JIT path; compiled code needs nothing."""
    return np.errstate(all="ignore") if cache_mode() == "nojit" else contextlib.nullcontext()


def _elastic(kind: str, x: Any, chain: ChainLike, variant: str) -> Any:
    arr, mask, scalar = as_real_array(x, "x", "mm")
    c = coefficients(chain, variant)
    flat = arr.reshape(-1)
    with _quiet():
        out = getattr(variant_module(variant), f"{kind}_array")(flat, *c)
    _large_x(flat, out, kind, *c)
    return _finish(out.reshape(arr.shape), mask, scalar)


def force(x: ArrayLike, chain: ChainLike = None, variant: str = "paper") -> ArrayLike:
    """Elastic force F_k(x) [N] of the chain at elongation x [mm] (inverse of paper Eq. 15).

    Parameters
    ----------
    x : float, array_like or masked array
        Chain elongation [mm] (int or float; see the module docstring for the conventions).
        x <= 0 gives 0 (a slack chain carries no compression); NaN gives NaN; +inf gives +inf.
    chain : ChainSpec or str or os.PathLike, optional
        The chain; ``None`` is the built-in 14x50 chain (n = 16); a str or path names a chain TOML file.
    variant : str
        Model variant (see :data:`VARIANTS`); default the paper's model.

    Returns
    -------
    float or ndarray or masked array
        F_k [N], same shape as ``x`` (a Python float for a 0-d ``x``).

    Raises
    ------
    TypeError
        For bool, complex, datetime, None, str or object ``x``, or a ``chain`` of another type.
    """
    return _elastic("force", x, chain, variant)


def displacement(F: ArrayLike, chain: ChainLike = None, variant: str = "paper") -> ArrayLike:
    """Chain elongation x(F) [mm] at tension F [N] (paper Eq. 15).

    Parameters
    ----------
    F : float, array_like or masked array
        Tension [N], >= 0 (masked entries are not checked); NaN gives NaN; +inf gives +inf.
    chain, variant
        As for :func:`force`.

    Returns
    -------
    float or ndarray or masked array
        x [mm], same shape as ``F``.

    Raises
    ------
    ValueError
        If any (unmasked) F < 0 (a chain carries no compression).
    TypeError
        As for :func:`force`.
    """
    arr, mask, scalar = as_real_array(F, "F", "N")
    if np.any(arr < 0):
        bad = float(arr[arr < 0].reshape(-1)[0])
        raise ValueError(f"F = {bad!r} N is invalid: a chain carries no compression; valid range F >= 0 N")
    c = coefficients(chain, variant)
    flat = arr.reshape(-1)
    with _quiet():
        out = variant_module(variant).displacement_array(flat, *c)
    out[np.isposinf(flat)] = np.inf
    return _finish(out.reshape(arr.shape), mask, scalar)


def stiffness(x: ArrayLike, chain: ChainLike = None, variant: str = "paper") -> ArrayLike:
    """Tangent stiffness k_e(x) = (dx/dF)⁻¹ [N/mm] at elongation x [mm] (paper Eq. 16).

    0 for x < 0 (slack); at x = 0 the Hertz contact makes it 0 (n >= 2); at x = +inf
    the limit 1/c_lin; NaN gives NaN.  Input conventions and errors as for :func:`force`.
    """
    return _elastic("stiffness", x, chain, variant)


def damping_residual(
    F: np.ndarray, x: np.ndarray, xddot: np.ndarray, chain: ChainLike = None, variant: str = "paper",
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
    chain : ChainSpec or str or os.PathLike, optional
        As for :func:`force`.
    mass_kg : float, optional
        Moving mass [kg]; default the chain's mass (mass_per_m × length).
    """
    chain = resolve_chain(chain)
    m = chain.mass_kg if mass_kg is None else float(mass_kg)
    c = coefficients(chain, variant)
    Fa, xa, aa = (np.ascontiguousarray(np.asarray(v, dtype=np.float64)).reshape(-1) for v in (F, x, xddot))
    if not (Fa.shape == xa.shape == aa.shape):
        raise ValueError(f"F, x, xddot must have the same shape; got {Fa.shape}, {xa.shape}, {aa.shape}")
    with _quiet():
        out = variant_module(variant).damping_residual_array(Fa, xa, aa, m, *c)
    return out.reshape(np.shape(x))
