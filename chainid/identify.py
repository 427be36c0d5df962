"""Damping identification from harmonic force–displacement tests (paper Eq. 17–24, 26–27).

Per test (:func:`identify_test`)

* harmonic fit of the force, Eq. 19/26: ``F = F0 + FA sin(psi + phi)`` with
  ``psi = omega t + theta`` the displacement phase, by linear least squares on
  ``[1, sin psi, cos psi]``; gives F0 [N], FA [N], phi [rad] (force lead over the
  displacement; the paper's phi when theta = 0) and R²;
* dissipated force, Eq. 17/20: ``F_c = F - m xddot - F_k(x)`` with the mass
  term in consistent units (:func:`inertia_force_N`) and F_k from a
  :class:`~chainid.models.StiffnessModel`;
* ``F_ac``, the component of F_c in phase with the velocity (``cos psi``), and
  ``c_e = F_ac / (omega A)`` [N·s/mm] (Eq. 20, 27);
* energy dissipated per cycle ``W = ∮ F dx`` [N·mm = mJ] from the loop area,
  and the ratio ``W / (pi c_e omega A²)`` (1 whenever x(t) is harmonic, whatever
  the force law), plus ``r2_c``, the share of F_c explained by its fundamental
  (1 for a viscous loop, 8/π² for Coulomb friction).

Across tests: damping laws c_e(omega, A, x0) with a scikit-learn-like
``fit``/``predict`` interface (:class:`PolynomialLaw` = Eq. 21,
:class:`ViscousLaw`, :class:`HystereticLaw`, :class:`CoulombLaw`,
:class:`CombinedLaw`), fitted by least squares both with the paper's normal
equations ``G A = C`` (Eq. 23–24) and with ``numpy.linalg.lstsq``; condition
numbers, standard errors, residuals and leave-one-out RMSE are reported
(:class:`LawFit`), and :func:`rank_laws` orders laws by LOO error.

Forward prediction, Eq. 1: :func:`predict_force`.

Units: mm, N, s, kg; omega in rad/s.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field
from typing import Any, Callable, Protocol, Sequence

import numpy as np

from .records import HarmonicEstimate, Record, analyse_record

__all__ = [
    "inertia_force_N",
    "HarmonicFit",
    "fit_harmonic",
    "TestResult",
    "loop_energy",
    "identify_test",
    "identify_records",
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
    "predict_force",
    "MIN_TESTS",
]

#: Minimum number of tests for fitting a damping law (paper: M > 5).
MIN_TESTS = 6


class _Model(Protocol):  # the StiffnessModel contract of chainid.models
    name: str
    mass_kg: float

    def force(self, x: np.ndarray) -> np.ndarray: ...

    def stiffness(self, x: np.ndarray) -> np.ndarray: ...


# ----------------------------------------------------------------------------
# Units
# ----------------------------------------------------------------------------
def inertia_force_N(m_kg: float | np.ndarray, xddot_mm_s2: float | np.ndarray) -> float | np.ndarray:
    """Inertial force F_m = m xddot (Eq. 1) in consistent units.

    Parameters
    ----------
    m_kg : float or ndarray
        Mass [kg].
    xddot_mm_s2 : float or ndarray
        Acceleration [mm/s²].

    Returns
    -------
    float or ndarray
        Force [N] = m [kg] · xddot [mm/s²] · 1e-3 [m/mm].
    """
    return np.multiply(m_kg, xddot_mm_s2) * 1e-3


def linear_model_from_records(records: Sequence[Record], mass_kg: float = 0.0,
                               side: dict[str, tuple[float, float, float]] | None = None) -> Any:
    """A linear spring F − m·ẍ = k·(x − x_ref) fitted on the steady cycles of all records.

    For parts that are not chains (``--model linear`` without ``--k``).

    Parameters
    ----------
    records : sequence of Record
        Tests (t s, x mm, F N); compressive force allowed.
    mass_kg : float
        Moving mass m [kg] (default 0); its inertia m·ẍ·1e-3 [N] is removed before the fit.
    side : dict, optional
        test id → (omega rad/s, x0 mm, A mm) instead of the estimates.

    Returns
    -------
    chainid.models.LinearModel
        k [N/mm], x_ref [mm].
    """
    from . import models

    xs, Fs = [], []
    for r in records:
        est = analyse_record(r, side.get(r.test) if side else None, allow_compression=True)
        mwin = (r.t >= est.window.t_start) & (r.t < est.window.t_end)
        xs.append(r.x[mwin])
        Fs.append(r.F[mwin] - inertia_force_N(mass_kg, est.xddot(r.t[mwin])))
    return models.LinearModel.fit(np.concatenate(xs), np.concatenate(Fs), mass=float(mass_kg))


# ----------------------------------------------------------------------------
# Harmonic fit of the force (Eq. 19, 26)
# ----------------------------------------------------------------------------
@dataclass
class HarmonicFit:
    """F = F0 + a sin psi + b cos psi = F0 + FA sin(psi + phi) (Eq. 19).

    Attributes: F0 [N], FA [N] (>= 0), phi [rad], r2 (coefficient of
    determination), a = FA cos phi [N], b = FA sin phi [N].
    """

    F0: float
    FA: float
    phi: float
    r2: float
    a: float
    b: float


def fit_harmonic(psi: np.ndarray, F: np.ndarray) -> HarmonicFit:
    """Linear least-squares fit of F on [1, sin psi, cos psi] (Eq. 19, 26).

    Parameters
    ----------
    psi : ndarray
        Phase omega t + theta [rad].
    F : ndarray
        Force [N] (any signal, e.g. F_c).

    Returns
    -------
    HarmonicFit
        F0, FA, phi, R².
    """
    psi = np.asarray(psi, dtype=float)
    F = np.asarray(F, dtype=float)
    X = np.column_stack([np.ones_like(psi), np.sin(psi), np.cos(psi)])
    sol, *_ = np.linalg.lstsq(X, F, rcond=None)
    resid = F - X @ sol
    ss_tot = float(np.sum((F - F.mean()) ** 2))
    r2 = 1.0 - float(np.sum(resid**2)) / ss_tot if ss_tot > 0 else 1.0
    F0, a, b = (float(v) for v in sol)
    return HarmonicFit(F0=F0, FA=math.hypot(a, b), phi=math.atan2(b, a), r2=r2, a=a, b=b)


# ----------------------------------------------------------------------------
# Per-test identification (Eq. 17, 20, 27)
# ----------------------------------------------------------------------------
@dataclass
class TestResult:
    """Identification of one test.  JSON keys are the field names.

    Attributes
    ----------
    test : str
        Test id.
    omega : float
        Angular frequency [rad/s].
    x0 : float
        Mean elongation [mm].
    A : float
        Displacement amplitude [mm].
    F0, FA, phi, r2 : float
        Harmonic fit of the measured force, Eq. 19: [N], [N], [rad], [-].
    F_ac : float
        Amplitude of F_c in phase with the velocity [N] (Eq. 27).
    c_e : float
        Equivalent viscous damping F_ac/(omega A) [N·s/mm] (Eq. 20, 27).
    W : float
        Energy dissipated per cycle, loop area ∮F dx [N·mm = mJ].
    W_ratio : float
        W / (pi c_e omega A²).  Note: when x(t) is a pure harmonic, ∮F dx picks up
        only the fundamental velocity component of F, so this ratio is 1 for ANY
        force law (viscous, friction, …); it departs from 1 only when x(t) is not
        harmonic.  Use ``r2_c`` to judge whether the loop is viscous.
    r2_c : float
        R² of the one-harmonic fit of F_c: ≈ 1 for a viscous (elliptic) loop,
        ≈ 8/π² ≈ 0.81 for a Coulomb friction (rectangular) loop.
    F_as : float
        Amplitude of F_c in phase with the displacement [N]; ≈ 0 if the
        stiffness model is right (a stiffness-mismatch indicator).
    Fc0 : float
        Mean of F_c [N]; ≈ 0 if the stiffness model is right.
    theta : float
        Phase of x = x0 + A sin(omega t + theta) [rad].
    noise_x : float
        RMS residual of x about the harmonic [mm].
    mass_kg : float
        Mass used in the inertia term [kg].
    t_start, t_end : float
        Steady window used [s].
    n_cycles : int
        Whole cycles used.
    cycles_kept : list of int
        Indices of the kept cycles.
    source : str
        "estimated" or "side file" (origin of omega, x0, A).
    """

    __test__ = False  # not a pytest test class

    test: str
    omega: float
    x0: float
    A: float
    F0: float
    FA: float
    phi: float
    r2: float
    F_ac: float
    c_e: float
    W: float
    W_ratio: float = float("nan")
    r2_c: float = float("nan")
    F_as: float = float("nan")
    Fc0: float = float("nan")
    theta: float = 0.0
    noise_x: float = 0.0
    mass_kg: float = 0.0
    t_start: float = 0.0
    t_end: float = 0.0
    n_cycles: int = 0
    cycles_kept: list[int] = field(default_factory=list)
    source: str = "estimated"

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dict (contract keys test, omega, x0, A, F0, FA, phi, r2, F_ac, c_e, W, + extras)."""
        d = asdict(self)
        return {k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in d.items()}


def loop_energy(x: np.ndarray, F: np.ndarray) -> float:
    """Loop integral ∮ F dx by the trapezoidal rule over the given samples.

    Parameters
    ----------
    x : ndarray
        Elongation [mm]; close the loop by repeating the first sample.
    F : ndarray
        Force [N].

    Returns
    -------
    float
        Energy [N·mm = mJ]; positive for a dissipative loop traversed with the
        force leading the displacement.
    """
    x = np.asarray(x, dtype=float)
    F = np.asarray(F, dtype=float)
    return float(np.sum(0.5 * (F[1:] + F[:-1]) * np.diff(x)))


def identify_test(
    rec: Record,
    model: _Model,
    *,
    estimate: HarmonicEstimate | None = None,
    mass_kg: float | None = None,
    allow_compression: bool = True,
) -> TestResult:
    """Identify F0, FA, phi, F_ac, c_e and W of one harmonic test (Eq. 17–20, 26–27).

    Parameters
    ----------
    rec : Record
        The test: t [s], x [mm], F [N].
    model : StiffnessModel
        Provides ``force(x)`` F_k [N] and ``mass_kg`` [kg].
    estimate : HarmonicEstimate, optional
        omega, x0, A, theta and the steady window; estimated from x(t) if None.
    mass_kg : float, optional
        Mass m [kg]; default ``model.mass_kg``.
    allow_compression : bool
        Passed to validation when ``estimate`` is None.

    Returns
    -------
    TestResult

    Notes
    -----
    The acceleration is that of the fitted harmonic, xddot = -omega² A sin psi
    (as in Eq. 20), so that sensor noise is not differentiated.  F_k is
    evaluated at the measured x, so the nonlinearity of F_k(x) (its higher
    harmonics) is removed sample by sample, as the paper recommends.
    """
    est = estimate if estimate is not None else analyse_record(rec, allow_compression=allow_compression)
    win = est.window
    if win is None or win.n_cycles < 1:
        raise ValueError(f"test {rec.test!r}: no steady whole cycle to identify from")
    m = (rec.t >= win.t_start) & (rec.t < win.t_end)
    t, x, F = rec.t[m], rec.x[m], rec.F[m]
    psi = est.phase(t)
    mass = float(model.mass_kg if mass_kg is None else mass_kg)
    hf = fit_harmonic(psi, F)
    Fk = np.asarray(model.force(x), dtype=float)
    Fc = F - inertia_force_N(mass, est.xddot(t)) - Fk
    hc = fit_harmonic(psi, Fc)
    F_ac = hc.b  # coefficient of cos psi: in phase with the velocity
    c_e = F_ac / (est.omega * est.A)
    # loop area over whole cycles: close the polygon on the kept samples
    xs = np.append(x, x[0])
    Fs = np.append(F, F[0])
    W = loop_energy(xs, Fs) / win.n_cycles
    W_visc = math.pi * c_e * est.omega * est.A**2
    return TestResult(
        test=rec.test,
        omega=est.omega,
        x0=est.x0,
        A=est.A,
        F0=hf.F0,
        FA=hf.FA,
        phi=hf.phi,
        r2=hf.r2,
        F_ac=F_ac,
        c_e=c_e,
        W=W,
        W_ratio=W / W_visc if W_visc != 0 else float("nan"),
        r2_c=hc.r2,
        F_as=hc.a,
        Fc0=hc.F0,
        theta=est.theta,
        noise_x=est.noise,
        mass_kg=mass,
        t_start=win.t_start,
        t_end=win.t_end,
        n_cycles=win.n_cycles,
        cycles_kept=list(win.cycles_kept),
        source=est.source,
    )


def identify_records(
    records: Sequence[Record],
    model: _Model,
    *,
    side: dict[str, tuple[float, float, float]] | None = None,
    mass_kg: float | None = None,
    allow_compression: bool = True,
    progress: Callable[[int, int, str], None] | None = None,
) -> list[TestResult]:
    """Run :func:`identify_test` on every record.

    Parameters
    ----------
    records : sequence of Record
    model : StiffnessModel
    side : dict, optional
        test id -> (omega rad/s, x0 mm, A mm) from a side file.
    mass_kg : float, optional
        Mass [kg]; default ``model.mass_kg``.
    allow_compression : bool
        Accept F < 0 [N] (validation).
    progress : callable, optional
        Called as ``progress(i, n, test)`` before each test.

    Returns
    -------
    list of TestResult
    """
    out = []
    n = len(records)
    for i, rec in enumerate(records):
        if progress is not None:
            progress(i, n, rec.test)
        s = side.get(rec.test) if side else None
        est = analyse_record(rec, s, allow_compression=allow_compression)
        out.append(identify_test(rec, model, estimate=est, mass_kg=mass_kg))
    return out


# ----------------------------------------------------------------------------
# Damping laws (Eq. 21 and alternatives)
# ----------------------------------------------------------------------------
def _as_arrays(omega: Any, A: Any, x0: Any = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
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
        self.params: np.ndarray | None = None if params is None else np.asarray(params, dtype=float)
        self.fit_: LawFit | None = None
        if self.params is not None and self.params.size != len(self.param_names):
            raise ValueError(
                f"{self.name}: params has {self.params.size} values; expected {len(self.param_names)} "
                f"({', '.join(self.param_names)})"
            )

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
        w, a, x = _as_arrays(omega, A, x0)
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

    def __init__(self, model: _Model, params: Sequence[float] | None = None) -> None:
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
    w, a, x = _as_arrays(omega, A, x0)
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
    H = X @ np.linalg.pinv(X)
    h = np.clip(np.diag(H), 0, 1)
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


def default_laws(model: _Model | None = None) -> list[DampingLaw]:
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
    model: _Model | None = None,
) -> list[dict[str, Any]]:
    """Fit every law and rank them by leave-one-out RMSE (best first).

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
    rows.sort(key=lambda r: (r["loo_rmse"], r["n_params"]))
    return rows


def law_from_dict(d: dict[str, Any], model: _Model | None = None) -> DampingLaw:
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


# ----------------------------------------------------------------------------
# Forward prediction (Eq. 1)
# ----------------------------------------------------------------------------
def predict_force(
    t: Any,
    x: Any,
    model: _Model,
    law_or_ce: DampingLaw | float,
    *,
    omega: float | None = None,
    A: float | None = None,
    x0: float | None = None,
    xdot: Any = None,
    xddot: Any = None,
    mass_kg: float | None = None,
) -> np.ndarray:
    """Force response F = m xddot + F_k(x) + c_e xdot (Eq. 1).

    Parameters
    ----------
    t : array_like
        Time [s].
    x : array_like
        Elongation [mm].
    model : StiffnessModel
        F_k(x) [N] and mass [kg].
    law_or_ce : DampingLaw or float
        A fitted law evaluated at (omega, A, x0), or a constant c_e [N·s/mm].
    omega, A, x0 : float, optional
        Test parameters [rad/s, mm, mm] for the law; estimated from x(t) if omitted.
    xdot, xddot : array_like, optional
        Velocity [mm/s] and acceleration [mm/s²]; by default ``numpy.gradient`` of x.
    mass_kg : float, optional
        Default ``model.mass_kg``.

    Returns
    -------
    ndarray
        F [N], same shape as x.
    """
    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float)
    v = np.gradient(x, t) if xdot is None else np.asarray(xdot, dtype=float)
    acc = np.gradient(v, t) if xddot is None else np.asarray(xddot, dtype=float)
    if isinstance(law_or_ce, DampingLaw):
        if omega is None or A is None or (x0 is None and isinstance(law_or_ce, (HystereticLaw, CombinedLaw))):
            from .records import estimate_harmonic

            est = estimate_harmonic(t, x)
            omega = est.omega if omega is None else omega
            A = est.A if A is None else A
            x0 = est.x0 if x0 is None else x0
        c = float(law_or_ce.predict(omega, A, x0)[0])
    else:
        c = float(law_or_ce)
    m = float(model.mass_kg if mass_kg is None else mass_kg)
    return inertia_force_N(m, acc) + np.asarray(model.force(x), dtype=float) + c * v
