"""Damping laws c_e(omega, A, x0) and their least-squares fit (paper Eq. 21–24).

Laws are linear in their parameters, c_e = X(omega, A, x0) @ p, with a
scikit-learn-like ``fit``/``predict`` interface (:class:`PolynomialLaw` = Eq. 21,
:class:`ViscousLaw`, :class:`HystereticLaw`, :class:`CoulombLaw`,
:class:`CombinedLaw`).  :func:`fit_law` solves by ``numpy.linalg.lstsq`` and by
the paper's normal equations ``G A = C`` (Eq. 23–24), and reports condition
numbers, standard errors and leave-one-out residuals from the leverages (:func:`leverages`)
(memory linear in the number of tests M, never an M×M matrix);
:func:`rank_laws` orders laws by LOO error.

Units: omega [rad/s], A [mm], x0 [mm], c_e [N·s/mm].
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Protocol, Sequence

import numpy as np

__all__ = [
    "DampingLaw",
    "PolynomialLaw",
    "ViscousLaw",
    "HystereticLaw",
    "CoulombLaw",
    "CombinedLaw",
    "LawFit",
    "fit_law",
    "rank_laws",
    "default_laws",
    "law_from_dict",
    "leverages",
    "MIN_TESTS",
]

#: Minimum number of tests for fitting a damping law (paper: M > 5).
MIN_TESTS = 6


class StiffnessLike(Protocol):  # the StiffnessModel contract of chainid.model.base
    name: str
    mass_kg: float

    def force(self, x: np.ndarray) -> np.ndarray: ...

    def stiffness(self, x: np.ndarray) -> np.ndarray: ...


# ----------------------------------------------------------------------------
# Damping laws (Eq. 21 and alternatives)
# ----------------------------------------------------------------------------
def as_arrays(omega: Any, A: Any, x0: Any = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    w = np.atleast_1d(np.asarray(omega, dtype=float))
    a = np.atleast_1d(np.asarray(A, dtype=float))
    if x0 is None:
        x = np.full(np.broadcast(w, a).shape, np.nan)
    else:
        x = np.atleast_1d(np.asarray(x0, dtype=float))
    w, a, x = np.broadcast_arrays(w, a, x)
    return w, a, x


class DampingLaw:
    """Base class: a damping law linear in its parameters, c_e = X(omega, A, x0) @ p.

    Subclasses define ``name``, ``param_names`` and :meth:`design`.  Use
    :meth:`fit` (least squares, details in :attr:`fit_`) and :meth:`predict`.
    """

    name: str = "law"
    param_names: tuple[str, ...] = ()
    param_units: tuple[str, ...] = ()

    def __init__(self, params: Sequence[float] | None = None) -> None:
        # a one-parameter law may be given its value alone (ViscousLaw(0.05)): params are always a 1-D array
        arr = None if params is None else np.asarray(params, dtype=float)
        if arr is not None and arr.ndim > 1:
            raise ValueError(f"{self.name}: params must be a flat list of {len(self.param_names)} values "
                             f"({', '.join(self.param_names)}); got an array of shape {arr.shape}")
        self.params: np.ndarray | None = None if arr is None else arr.reshape(-1)
        self.fit_: LawFit | None = None
        if self.params is not None and self.params.size != len(self.param_names):
            raise ValueError(
                f"{self.name}: params has {self.params.size} values; expected {len(self.param_names)} "
                f"({', '.join(self.param_names)})"
            )
        if self.params is not None and not np.all(np.isfinite(self.params)):
            raise ValueError(f"{self.name}: params = {[float(v) for v in self.params]} must be finite numbers "
                             f"({', '.join(self.param_names)} in {', '.join(self.param_units)})")

    @property
    def n_params(self) -> int:
        return len(self.param_names)

    def design(self, omega: np.ndarray, A: np.ndarray, x0: np.ndarray) -> np.ndarray:
        """Design matrix X, shape (M, n_params), with c_e = X @ params."""
        raise NotImplementedError

    def fit(self, omega: Any, A: Any, c_e: Any, x0: Any = None) -> "DampingLaw":
        """Fit the parameters by least squares; see :func:`fit_law`.

        Parameters
        ----------
        omega : array_like
            [rad/s].
        A : array_like
            [mm].
        c_e : array_like
            Identified damping [N·s/mm].
        x0 : array_like, optional
            Mean elongation [mm] (needed by :class:`HystereticLaw`).
        """
        self.fit_ = fit_law(self, omega, A, c_e, x0)
        self.params = self.fit_.params
        return self

    def predict(self, omega: Any, A: Any, x0: Any = None) -> np.ndarray:
        """Damping c_e [N·s/mm] at omega [rad/s], A [mm] (x0 [mm])."""
        if self.params is None:
            raise ValueError(f"{self.name}: not fitted and no params given")
        w, a, x = as_arrays(omega, A, x0)
        return self.design(w, a, x) @ self.params

    def formula(self) -> str:
        """Human-readable formula."""
        return self.name

    def to_dict(self) -> dict[str, Any]:
        d: dict[str, Any] = {"name": self.name, "formula": self.formula(), "param_names": list(self.param_names)}
        d["params"] = None if self.params is None else [float(v) for v in self.params]
        if self.fit_ is not None:
            d.update(self.fit_.to_dict())
        return d


class PolynomialLaw(DampingLaw):
    """Paper Eq. 21: c_e = α1 ω² + α2 ω + α3 A² + α4 A + α5 [N·s/mm], ω rad/s, A mm."""

    name = "polynomial"
    param_names = ("alpha1", "alpha2", "alpha3", "alpha4", "alpha5")
    param_units = ("N s^3/(mm rad^2)", "N s^2/(mm rad)", "N s/mm^3", "N s/mm^2", "N s/mm")

    def design(self, omega: np.ndarray, A: np.ndarray, x0: np.ndarray) -> np.ndarray:
        return np.column_stack([omega**2, omega, A**2, A, np.ones_like(omega)])

    def formula(self) -> str:
        return "c_e = a1*w^2 + a2*w + a3*A^2 + a4*A + a5 (Eq. 21)"


class ViscousLaw(DampingLaw):
    """Constant viscous damping c_e = c [N·s/mm]."""

    name = "viscous"
    param_names = ("c",)
    param_units = ("N s/mm",)

    def design(self, omega: np.ndarray, A: np.ndarray, x0: np.ndarray) -> np.ndarray:
        return np.ones((omega.size, 1))

    def formula(self) -> str:
        return "c_e = c"


class CoulombLaw(DampingLaw):
    """Coulomb friction, equivalent viscous damping c_e = 4 F_f / (π ω A) [N·s/mm]; F_f [N]."""

    name = "coulomb"
    param_names = ("F_f",)
    param_units = ("N",)

    def design(self, omega: np.ndarray, A: np.ndarray, x0: np.ndarray) -> np.ndarray:
        return (4.0 / (math.pi * omega * A))[:, None]

    def formula(self) -> str:
        return "c_e = 4*F_f/(pi*w*A)"


class HystereticLaw(DampingLaw):
    """Rate-independent (hysteretic) damping c_e = η k_e(x0) / ω [N·s/mm].

    Parameters
    ----------
    model : StiffnessModel
        Gives k_e(x0) [N/mm] via ``model.stiffness``.
    params : sequence, optional
        [η] (loss factor, dimensionless).
    """

    name = "hysteretic"
    param_names = ("eta",)
    param_units = ("-",)

    def __init__(self, model: StiffnessLike, params: Sequence[float] | None = None) -> None:
        super().__init__(params)
        self.model = model

    def design(self, omega: np.ndarray, A: np.ndarray, x0: np.ndarray) -> np.ndarray:
        if np.any(~np.isfinite(x0)):
            raise ValueError("hysteretic law needs x0 [mm] for every test (k_e is evaluated at x0)")
        ke = np.asarray(self.model.stiffness(x0), dtype=float)
        return (ke / omega)[:, None]

    def formula(self) -> str:
        return "c_e = eta*k_e(x0)/w"


class CombinedLaw(DampingLaw):
    """Sum of several laws, c_e = Σ_j law_j (parameters concatenated).

    Default parts: viscous + Coulomb.
    """

    name = "combined"

    def __init__(self, parts: Sequence[DampingLaw] | None = None, params: Sequence[float] | None = None) -> None:
        self.parts = list(parts) if parts is not None else [ViscousLaw(), CoulombLaw()]
        self.param_names = tuple(n for p in self.parts for n in p.param_names)  # type: ignore[misc]
        self.param_units = tuple(u for p in self.parts for u in p.param_units)  # type: ignore[misc]
        self.name = "+".join(p.name for p in self.parts)
        super().__init__(params)

    def design(self, omega: np.ndarray, A: np.ndarray, x0: np.ndarray) -> np.ndarray:
        return np.column_stack([p.design(omega, A, x0) for p in self.parts])

    def formula(self) -> str:
        return " + ".join(p.formula().replace("c_e = ", "") for p in self.parts)


@dataclass
class LawFit:
    """Least-squares fit of a damping law to identified c_e.

    Attributes
    ----------
    params : ndarray
        From ``numpy.linalg.lstsq`` (numerically stable, SVD).
    params_normal : ndarray
        From the paper's normal equations G A = C (Eq. 23–24), ``numpy.linalg.solve``.
    stderr : ndarray
        Standard errors sqrt(diag(s² (XᵀX)⁻¹)), s² = RSS/(M - p).
    cond_X, cond_G : float
        2-norm condition numbers of the design matrix and of G = XᵀX.
    residuals : ndarray
        c_e - prediction [N·s/mm].
    rmse : float
        Root-mean-square residual [N·s/mm].
    loo_rmse : float
        Leave-one-out cross-validated RMSE [N·s/mm] (hat-matrix formula).
    loo_residuals : ndarray
        Leave-one-out residuals [N·s/mm].
    n_tests, dof : int
        M and M - p.
    """

    params: np.ndarray
    params_normal: np.ndarray
    stderr: np.ndarray
    cond_X: float
    cond_G: float
    residuals: np.ndarray
    rmse: float
    loo_rmse: float
    loo_residuals: np.ndarray
    n_tests: int
    dof: int

    def to_dict(self) -> dict[str, Any]:
        def lst(a: np.ndarray) -> list:
            return [None if not math.isfinite(float(v)) else float(v) for v in a]

        return {
            "params": lst(self.params),
            "params_normal_equations": lst(self.params_normal),
            "stderr": lst(self.stderr),
            "cond_X": self.cond_X,
            "cond_G": self.cond_G,
            "residuals": lst(self.residuals),
            "rmse": self.rmse,
            "loo_rmse": None if not math.isfinite(self.loo_rmse) else self.loo_rmse,
            "n_tests": self.n_tests,
            "dof": self.dof,
        }


def leverages(X: np.ndarray) -> np.ndarray:
    """Leverages h_i = diag(X X⁺) of a design matrix (one row per test), in [0, 1].

    Sum of U_ij² over the non-null singular directions of a thin SVD: memory and time linear in the number
    of rows, never the M×M hat matrix; a rank-deficient X is handled.  The leave-one-out residual of a
    least-squares fit is r_i/(1 − h_i).
    """
    U, sv, _ = np.linalg.svd(np.asarray(X, float), full_matrices=False)
    keep = sv > sv.max(initial=0.0) * max(X.shape) * np.finfo(float).eps
    return np.clip(np.sum(U[:, keep] ** 2, axis=1), 0, 1)


def fit_law(law: DampingLaw, omega: Any, A: Any, c_e: Any, x0: Any = None, *, min_tests: int = MIN_TESTS) -> LawFit:
    """Fit a linear-in-parameters damping law by least squares (Eq. 22–24).

    Parameters
    ----------
    law : DampingLaw
    omega : array_like
        [rad/s], one per test.
    A : array_like
        [mm].
    c_e : array_like
        Identified damping [N·s/mm].
    x0 : array_like, optional
        [mm].
    min_tests : int
        Minimum number of tests (default 6, the paper's M > 5); at least
        n_params + 1 in any case.

    Returns
    -------
    LawFit

    Raises
    ------
    ValueError
        Fewer tests than ``max(min_tests, n_params + 1)``, or non-finite input.
    """
    w, a, x = as_arrays(omega, A, x0)
    c = np.asarray(c_e, dtype=float).ravel()
    M = c.size
    if w.size != M:
        raise ValueError(f"omega/A have {w.size} values but c_e has {M}")
    need = max(min_tests, law.n_params + 1)
    if M < need:
        raise ValueError(
            f"{law.name} law: {M} test(s) given; at least {need} are needed "
            f"(the paper's Eq. 22 requires M > 5 tests for the 5 coefficients; LOO needs M > p)"
        )
    if not (np.all(np.isfinite(w)) and np.all(np.isfinite(a)) and np.all(np.isfinite(c))):
        raise ValueError("omega, A and c_e must all be finite")
    if np.any(w <= 0) or np.any(a <= 0):
        raise ValueError("omega [rad/s] and A [mm] must be > 0 for every test")
    X = law.design(w, a, x)
    p = X.shape[1]
    params, *_ = np.linalg.lstsq(X, c, rcond=None)
    G = X.T @ X  # Eq. 24: g_kq = sum x_ki x_qi
    C = X.T @ c  # Eq. 24: c_q = sum c_ei x_qi
    try:
        params_normal = np.linalg.solve(G, C)
    except np.linalg.LinAlgError:
        params_normal = np.full(p, np.nan)
    resid = c - X @ params
    dof = M - p
    rss = float(resid @ resid)
    s2 = rss / dof if dof > 0 else float("nan")
    Ginv = np.linalg.pinv(G)
    stderr = np.sqrt(np.clip(np.diag(Ginv) * s2, 0, None))
    h = leverages(X)
    with np.errstate(divide="ignore", invalid="ignore"):
        loo = resid / (1.0 - h)
    loo_rmse = float(np.sqrt(np.mean(loo**2))) if np.all(h < 1 - 1e-10) else float("inf")
    return LawFit(
        params=params,
        params_normal=params_normal,
        stderr=stderr,
        cond_X=float(np.linalg.cond(X)),
        cond_G=float(np.linalg.cond(G)),
        residuals=resid,
        rmse=float(np.sqrt(rss / M)),
        loo_rmse=loo_rmse,
        loo_residuals=loo,
        n_tests=M,
        dof=dof,
    )


def default_laws(model: StiffnessLike | None = None) -> list[DampingLaw]:
    """The candidate laws: polynomial (Eq. 21), viscous, Coulomb, viscous+Coulomb,
    and, given a model, hysteretic and viscous+hysteretic."""
    laws: list[DampingLaw] = [PolynomialLaw(), ViscousLaw(), CoulombLaw(), CombinedLaw()]
    if model is not None:
        laws += [HystereticLaw(model), CombinedLaw([ViscousLaw(), HystereticLaw(model)])]
    return laws


def rank_laws(
    omega: Any,
    A: Any,
    c_e: Any,
    x0: Any = None,
    laws: Sequence[DampingLaw] | None = None,
    *,
    model: StiffnessLike | None = None,
) -> list[dict[str, Any]]:
    """Fit every law and rank them by leave-one-out RMSE (best first; equal errors: fewer parameters first).

    Errors equal to within :data:`LOO_TIE_REL` (relative), and errors of exact fits (below LOO_TIE_REL times the
    RMS of c_e: round-off), rank as equal, and among equals the law with fewer parameters comes first (the
    simpler law explains the tests as well).

    Parameters
    ----------
    omega, A, c_e, x0 : array_like
        Per test: [rad/s], [mm], [N·s/mm], [mm].
    laws : sequence of DampingLaw, optional
        Default :func:`default_laws` (model).
    model : StiffnessModel, optional
        For the hysteretic law in the default list.

    Returns
    -------
    list of dict
        ``{"law", "formula", "params", "stderr", "rmse", "loo_rmse", "n_params", "fitted": DampingLaw}``;
        laws that cannot be fitted (too few tests) are listed last with an "error".

    Raises
    ------
    ValueError
        Fewer than 6 tests.
    """
    c = np.asarray(c_e, dtype=float).ravel()
    if c.size < MIN_TESTS:
        raise ValueError(f"{c.size} test(s) given; ranking damping laws needs at least {MIN_TESTS} (paper: M > 5)")
    laws = list(laws) if laws is not None else default_laws(model)
    rows = []
    for law in laws:
        try:
            law.fit(omega, A, c, x0)
        except ValueError as exc:
            rows.append({"law": law.name, "formula": law.formula(), "error": str(exc), "loo_rmse": float("inf"),
                         "n_params": law.n_params, "fitted": law})
            continue
        f = law.fit_
        assert f is not None
        rows.append({
            "law": law.name,
            "formula": law.formula(),
            "param_names": list(law.param_names),
            "params": [float(v) for v in f.params],
            "stderr": [float(v) for v in f.stderr],
            "rmse": f.rmse,
            "loo_rmse": f.loo_rmse,
            "n_params": law.n_params,
            "fitted": law,
        })
    return _ranked(rows, c)


#: leave-one-out errors closer than this (relative, or below it times the RMS of c_e) are equal for the ranking
LOO_TIE_REL = 1e-9


def _ranked(rows: list[dict[str, Any]], c: np.ndarray) -> list[dict[str, Any]]:
    """Rows by leave-one-out RMSE, the law with fewer parameters first among equal errors.

    Errors are equal when they lie within :data:`LOO_TIE_REL` (relative) of the smallest error of their group, or
    are all below LOO_TIE_REL·RMS(c_e) (an exact fit up to round-off); groups are formed along the sorted errors,
    so two errors that straddle a rounding boundary are still equal.  Non-finite errors (a failed fit) come last.
    """
    floor = LOO_TIE_REL * float(np.sqrt(np.mean(c * c)))
    order = sorted(rows, key=lambda r: (not math.isfinite(r["loo_rmse"]), r["loo_rmse"], r["n_params"]))
    out: list[dict[str, Any]] = []
    group: list[dict[str, Any]] = []
    for r in order:
        v = max(r["loo_rmse"], floor)
        if group and math.isfinite(v) and v <= max(group[0]["loo_rmse"], floor) * (1 + LOO_TIE_REL):
            group.append(r)
            continue
        out += sorted(group, key=lambda g: g["n_params"])
        group = [r]
    return out + sorted(group, key=lambda g: g["n_params"])


def law_from_dict(d: dict[str, Any], model: StiffnessLike | None = None) -> DampingLaw:
    """Rebuild a law from ``{"name": ..., "params": [...]}`` (names as in :attr:`DampingLaw.name`)."""
    name = d["name"]
    params = d.get("params")
    simple = {"polynomial": PolynomialLaw, "viscous": ViscousLaw, "coulomb": CoulombLaw}
    if name in simple:
        return simple[name](params)
    parts_names = name.split("+")
    parts: list[DampingLaw] = []
    for pn in parts_names:
        if pn == "hysteretic":
            if model is None:
                raise ValueError("hysteretic law needs a stiffness model")
            parts.append(HystereticLaw(model))
        elif pn in simple:
            parts.append(simple[pn]())
        else:
            raise ValueError(f"unknown damping law {pn!r}; valid: polynomial, viscous, coulomb, hysteretic, a+b")
    if len(parts) == 1:  # only "hysteretic" reaches here
        return HystereticLaw(model, params)  # type: ignore[arg-type]
    return CombinedLaw(parts, params)

