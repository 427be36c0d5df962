"""Stiffness models: the chain of the paper, and a linear spring for other parts.

A :class:`StiffnessModel` maps elongation x [mm] to the elastic force [N]
and the tangent stiffness [N/mm], and knows the moving mass [kg].  The
identification and the gap diagnosis work with any of them.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Protocol, runtime_checkable

import numpy as np

from chainid.model import kernels
from chainid.chain.spec import ChainSpec, default_chain

__all__ = ["StiffnessModel", "ChainModel", "LinearModel", "model_for"]


@runtime_checkable
class StiffnessModel(Protocol):
    """What the identification needs of a spring model."""

    name: str

    @property
    def mass_kg(self) -> float:  # pragma: no cover - protocol
        """Moving mass [kg]."""

    def force(self, x: np.ndarray) -> np.ndarray:  # pragma: no cover - protocol
        """Elastic force [N] at elongation x [mm]."""

    def stiffness(self, x: np.ndarray) -> np.ndarray:  # pragma: no cover - protocol
        """Tangent stiffness [N/mm] at elongation x [mm]."""


@dataclass(frozen=True)
class ChainModel:
    """The paper's chain spring F_k(x) from the generated kernels (Eq. 15–16).

    Parameters
    ----------
    chain : ChainSpec or str or os.PathLike, optional
        The chain (``None``: the built-in 14x50 chain; a str or path: a chain TOML file,
        see :func:`chainid.model.kernels.resolve_chain`).
    variant : str
        Kernel variant: "paper", "inner_bend", "shear", "inner_bend_shear".
    slack : float
        Displacement offset [mm]: the chain starts to carry load at x = slack
        (permanent elongation, clearance or a sensor zero shift; may be negative).
    compliance : float
        Extra series compliance [mm/N] (test machine / fixture spring, >= 0).
        A series spring adds to the linear term of Eq. 15, so it is the same
        kernel with c_lin + compliance.
    hertz_scale : float
        Factor (> 0) on the contact coefficient c_hertz: < 1 a more conformal
        contact (plastic set after proof loading), > 1 a softer one.
    contact_exponent : float or None
        Contact exponent β in δ = c·F^β (None: Hertz, 2/3, the variant's kernel).
        With β set, the generated ``contact_power`` kernel is used and c is chosen
        so that δ equals the variant's Hertz approach (times ``hertz_scale``) at
        ``contact_ref_force``.
    contact_ref_force : float
        Reference force [N] for ``contact_exponent`` (default 10 kN).
    ea_scale : float
        Factor (> 0) on the links' own linear axial stiffness (the straight + curved bar terms of Eq. 15):
        the linear compliance c_lin becomes c_lin / ea_scale.  The "stiffness level" of the gap diagnosis
        (a base model that is itself stiffer or softer than the derivation; unlike ``compliance`` it can
        also stiffen the chain).
    """

    chain: ChainSpec = field(default_factory=default_chain)
    variant: str = "paper"
    slack: float = 0.0
    compliance: float = 0.0
    hertz_scale: float = 1.0
    contact_exponent: float | None = None
    contact_ref_force: float = 1.0e4
    ea_scale: float = 1.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "chain", kernels.resolve_chain(self.chain))
        if not np.isfinite(self.slack):
            raise ValueError(f"ChainModel.slack = {self.slack!r} is invalid: must be a finite number of mm")
        if not (np.isfinite(self.compliance) and self.compliance >= 0):
            raise ValueError(f"ChainModel.compliance = {self.compliance!r} is invalid: valid range >= 0 mm/N")
        if not (np.isfinite(self.hertz_scale) and self.hertz_scale > 0):
            raise ValueError(f"ChainModel.hertz_scale = {self.hertz_scale!r} is invalid: valid range > 0")
        if self.contact_exponent is not None and not (0.2 <= self.contact_exponent <= 1.5):
            raise ValueError(
                f"ChainModel.contact_exponent = {self.contact_exponent!r} is invalid: valid range 0.2 to 1.5 "
                "(Hertz: 2/3)"
            )
        if not (np.isfinite(self.contact_ref_force) and self.contact_ref_force > 0):
            raise ValueError(f"ChainModel.contact_ref_force = {self.contact_ref_force!r} is invalid: valid range > 0 N")
        if not (np.isfinite(self.ea_scale) and 1e-3 <= self.ea_scale <= 1e3):
            raise ValueError(f"ChainModel.ea_scale = {self.ea_scale!r} is invalid: valid range 0.001 to 1000")
        kernels.variant_module(self.variant)  # validates the name

    @property
    def name(self) -> str:
        return f"chain[{self.variant}]"

    @property
    def mass_kg(self) -> float:
        """Total mass of the links [kg]."""
        return self.chain.mass_kg

    @property
    def coefficients(self) -> tuple[float, ...]:
        """Kernel coefficients: (c_lin + compliance [mm/N], c_hertz [mm/N^β]) and β if set."""
        c_lin, c_h = kernels.coefficients(self.chain, self.variant)
        c_lin /= self.ea_scale
        c_h *= self.hertz_scale
        if self.contact_exponent is None:
            return c_lin + self.compliance, c_h
        beta = float(self.contact_exponent)
        return c_lin + self.compliance, c_h * self.contact_ref_force ** (2.0 / 3.0 - beta), beta

    def _call(self, kernel: str, x: np.ndarray) -> np.ndarray:
        if self.contact_exponent is None:
            mod = kernels.variant_module(self.variant)
        else:
            mod = kernels.power_module()
        arr = np.asarray(x, dtype=np.float64) - self.slack
        flat = np.ascontiguousarray(arr).reshape(-1)
        c = self.coefficients
        with kernels._quiet():  # the kernels' numpy error model, also with NUMBA_DISABLE_JIT=1
            out = getattr(mod, kernel)(flat, *c)
        if self.contact_exponent is None:
            kernels._large_x(flat, out, kernel.removesuffix("_array"), *c)
        else:  # x = +inf: F = inf; k -> 1/(c_lin + c·β·F^(β-1)) as F -> inf
            inf = np.isposinf(flat)
            c_lin, c_h, beta = c
            k_inf = 1.0 / c_lin if beta < 1.0 else (1.0 / (c_lin + c_h) if beta == 1.0 else 0.0)
            out[inf] = np.inf if kernel == "force_array" else k_inf
        return out.reshape(arr.shape)

    def force(self, x: np.ndarray) -> np.ndarray:
        """F_k [N] at elongation x [mm]."""
        return self._call("force_array", x)

    def stiffness(self, x: np.ndarray) -> np.ndarray:
        """Tangent k_e [N/mm] at elongation x [mm]."""
        return self._call("stiffness_array", x)


@dataclass(frozen=True)
class LinearModel:
    """A linear spring F = k·(x − x_ref), for parts other than chains (``--model linear``).

    Parameters
    ----------
    k : float
        Stiffness [N/mm], >= 0.
    x_ref : float
        Elongation at zero force [mm].
    mass : float
        Moving mass [kg], >= 0.
    """

    k: float
    x_ref: float = 0.0
    mass: float = 0.0
    name: str = "linear"

    def __post_init__(self) -> None:
        if not (np.isfinite(self.k) and self.k >= 0):
            raise ValueError(f"LinearModel.k = {self.k!r} is invalid: valid range >= 0 N/mm")
        if not np.isfinite(self.x_ref):
            raise ValueError(f"LinearModel.x_ref = {self.x_ref!r} is invalid: must be finite (mm)")
        if not (np.isfinite(self.mass) and self.mass >= 0):
            raise ValueError(f"LinearModel.mass = {self.mass!r} is invalid: valid range >= 0 kg")

    @property
    def mass_kg(self) -> float:
        """Moving mass [kg]."""
        return self.mass

    def force(self, x: np.ndarray) -> np.ndarray:
        """k·(x − x_ref) [N]."""
        return self.k * (np.asarray(x, dtype=np.float64) - self.x_ref)

    def stiffness(self, x: np.ndarray) -> np.ndarray:
        """k [N/mm] everywhere."""
        return np.full(np.shape(x), self.k, dtype=np.float64)

    @classmethod
    def fit(cls, x: np.ndarray, F: np.ndarray, mass: float = 0.0) -> "LinearModel":
        """Least-squares F = k(x − x_ref) on samples x [mm], F [N] (numpy.linalg.lstsq)."""
        x = np.asarray(x, dtype=np.float64).reshape(-1)
        F = np.asarray(F, dtype=np.float64).reshape(-1)
        if x.shape != F.shape or x.size < 2:
            raise ValueError(f"LinearModel.fit needs x and F of equal length >= 2; got {x.size} and {F.size}")
        A = np.column_stack([x, np.ones_like(x)])
        (k, b), *_ = np.linalg.lstsq(A, F, rcond=None)
        k = max(float(k), 0.0)
        x_ref = -float(b) / k if k > 0 else 0.0
        return cls(k=k, x_ref=x_ref, mass=mass)


def model_for(chain: ChainSpec | None = None, variant: str = "paper") -> ChainModel:
    """The chain model of a spec (``None``: the built-in chain)."""
    return ChainModel(chain or default_chain(), variant)
