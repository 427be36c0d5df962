"""Damping identification from harmonic force–displacement tests (paper Eq. 17–24, 26–27).

Per test (:func:`identify_test`)

* harmonic fit of the force, Eq. 19/26: ``F = F0 + FA sin(psi + phi)`` with
  ``psi = omega t + theta`` the displacement phase, by linear least squares on
  ``[1, sin psi, cos psi]``; gives F0 [N], FA [N], phi [rad] (force lead over the
  displacement; the paper's phi when theta = 0) and R²;
* dissipated force, Eq. 17/20: ``F_c = F - m xddot - F_k(x)`` with the mass
  term in consistent units (:func:`inertia_force_N`) and F_k from a
  :class:`~chainid.model.base.StiffnessModel`;
* ``F_ac``, the component of F_c in phase with the velocity (``cos psi``), and
  ``c_e = F_ac / (omega A)`` [N·s/mm] (Eq. 20, 27);
* energy dissipated per cycle ``W = ∮ F dx`` [N·mm = mJ] from the loop area,
  and the ratio ``W / (pi c_e omega A²)`` (1 whenever x(t) is harmonic, whatever
  the force law), plus ``r2_c``, the share of F_c explained by its fundamental
  (1 for a viscous loop, 8/π² for Coulomb friction).

Across tests: the damping laws c_e(omega, A, x0) and their fit (Eq. 21–24,
:class:`PolynomialLaw`, ..., :func:`fit_law`, :func:`rank_laws`) live in
:mod:`chainid.model.laws` and are re-exported here.  :func:`identify_records` leaves
out a test whose steady cycles, harmonic fit or damping estimate cannot be
obtained and lists it with its reason (:class:`Identification`).

Forward prediction, Eq. 1: :func:`predict_force` (in :mod:`chainid.model.predict`, re-exported).

Units: mm, N, s, kg; omega in rad/s.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field
from typing import Any, Callable, Sequence

import numpy as np

from chainid.model.laws import StiffnessLike
from chainid.model.predict import inertia_force_N
from chainid.records.files import HarmonicEstimate, Record, analyse_record, try_analyse

__all__ = [
    "HarmonicFit",
    "fit_harmonic",
    "TestResult",
    "loop_energy",
    "identify_test",
    "identify_records",
    "Identification",
]

def linear_model_from_records(records: Sequence[Record], mass_kg: float = 0.0,
                               side: dict[str, tuple[float, float, float]] | None = None,
                               steady_tol: float | None = None) -> Any:
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
    steady_tol : float or None
        Steady-cycle tolerance (fraction); None = adaptive.  Tests that cannot be
        analysed are skipped.

    Returns
    -------
    chainid.model.base.LinearModel
        k [N/mm], x_ref [mm].
    """
    from chainid.model import base as models

    xs, Fs = [], []
    for r in records:
        est, _ = try_analyse(r, side=side.get(r.test) if side else None, allow_compression=True,
                             steady_tol=steady_tol)
        if est is None or est.window is None:  # left out (identify_records says why)
            continue
        mwin = (r.t >= est.window.t_start) & (r.t < est.window.t_end)
        xs.append(r.x[mwin])
        Fs.append(r.F[mwin] - inertia_force_N(mass_kg, est.xddot(r.t[mwin])))
    if not xs:
        raise ValueError("no test has steady cycles: cannot fit the linear spring (--model linear without --k)")
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
        Phase of x = x0 + A sin(omega (t - t_origin) + theta) [rad] (:meth:`to_dict` gives it for t itself).
    t_origin : float
        Time origin of ``theta`` [s]: the record's first sample (any time stamp, e.g. Unix time); not in
        the JSON.
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
    steady : str
        What was kept and why (window, cycles, tolerance), from
        :meth:`chainid.signal.steady.SteadyWindow.statement`.
    steady_tol : float
        Steady-cycle tolerance used (fraction of the plateau amplitude).
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
    steady: str = ""
    steady_tol: float = float("nan")
    t_origin: float = 0.0

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dict (contract keys test, omega, x0, A, F0, FA, phi, r2, F_ac, c_e, W, + extras).

        ``theta`` is given in the record's own time, x = x0 + A sin(omega t + theta) (the computations use it
        from ``t_origin``; the shift by omega·t_origin is made here only, so the contract is unchanged).
        """
        d = asdict(self)
        t0 = d.pop("t_origin")
        if t0:
            th = self.theta - self.omega * t0
            d["theta"] = math.atan2(math.sin(th), math.cos(th))
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
    model: StiffnessLike,
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
        t_origin=float(getattr(est, "t_origin", 0.0)),
        noise_x=est.noise,
        mass_kg=mass,
        t_start=win.t_start,
        t_end=win.t_end,
        n_cycles=win.n_cycles,
        cycles_kept=list(win.cycles_kept),
        source=est.source,
    )


class Identification(list):
    """The :class:`TestResult` of every identified test (a list), plus the tests left out.

    Attributes
    ----------
    excluded : list of dict
        ``{"test": id, "reason": str}`` for every test whose steady cycles,
        harmonic fit or damping estimate could not be obtained, in record order.
    """

    def __init__(self, results: Sequence[TestResult] = (), excluded: Sequence[dict[str, str]] = ()) -> None:
        super().__init__(results)
        self.excluded: list[dict[str, str]] = list(excluded)


def identify_records(
    records: Sequence[Record],
    model: StiffnessLike,
    *,
    side: dict[str, tuple[float, float, float]] | None = None,
    mass_kg: float | None = None,
    allow_compression: bool = True,
    progress: Callable[[int, int, str], None] | None = None,
    steady_tol: float | None = None,
    strict: bool = False,
) -> Identification:
    """Run :func:`identify_test` on every record; leave out (with the reason) those that cannot be identified.

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
    steady_tol : float or None
        Steady-cycle tolerance (fraction, 0.03 = 3 %); None = adaptive
        (:func:`chainid.signal.steady.select_steady`).
    strict : bool
        Raise on the first test that cannot be identified instead of leaving it out.

    Returns
    -------
    Identification
        A list of :class:`TestResult` (identified tests, record order) with
        ``.excluded = [{"test", "reason"}, ...]``.

    Raises
    ------
    ValueError
        Data errors (NaN, t not increasing, compression without
        ``allow_compression``: :func:`chainid.records.check_data`), and with
        ``strict`` any test that cannot be identified; ``mass_kg`` not a finite number >= 0.
    """
    if mass_kg is not None and (isinstance(mass_kg, bool) or not (math.isfinite(mass_kg) and mass_kg >= 0)):
        raise ValueError(f"mass_kg = {mass_kg!r} is invalid: valid range >= 0 kg (finite)")
    out = Identification()
    n = len(records)
    for i, rec in enumerate(records):
        if progress is not None:
            progress(i, n, rec.test)
        s = side.get(rec.test) if side else None
        est, why = try_analyse(rec, allow_compression=allow_compression, steady_tol=steady_tol, side=s)
        res = None
        if est is not None:
            try:
                res = identify_test(rec, model, estimate=est, mass_kg=mass_kg)
                res.steady = why
                res.steady_tol = est.window.rel_tol if est.window is not None else float("nan")
                if not (math.isfinite(res.c_e) and math.isfinite(res.F_ac)):
                    why = f"damping estimate is not finite (c_e = {res.c_e!r} N.s/mm)"
                    res = None
            except (ValueError, np.linalg.LinAlgError) as exc:
                why = f"damping estimate failed: {exc}"
        if res is None:
            if strict:
                raise ValueError(f"test {rec.test!r}: {why}")
            out.excluded.append({"test": rec.test, "reason": why})
        else:
            out.append(res)
    return out
