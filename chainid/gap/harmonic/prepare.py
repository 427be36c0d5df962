"""Prepare one record for the diagnosis: steady window, phase bins, noise, cycle statistics.

Each test's steady window (:mod:`chainid.records`) is folded into ``B`` phase
bins of ψ = ωt + θ (x = x0 + A sin ψ).  The cycle-averaged force per bin is the
"measured" force used for all errors (noise averaged over the cycles); the
noise σ [N] is the cycle-to-cycle scatter at the same phase, within the model
grid's cells (:mod:`chainid.gap.harmonic.cyclenoise`), so the noise floor of a
bin mean is σ/√n_bin.

Per whole cycle the mean force and the force's first harmonic (in phase with x
and with ẋ) are kept: a displacement-controlled test whose x is periodic must
give a periodic force under any static effect, so a trend of these over the
cycles is a non-stationarity that no static library member explains
(:mod:`chainid.gap.core.stationarity`).

Units: t s, x mm, F N, ω rad/s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from chainid.gap.harmonic.cyclenoise import cycle_noise, grid_cells
from chainid.signal.cycles import segment_lstsq


@dataclass
class TestData:
    """Steady window of one test prepared for the diagnosis (units mm, N, s; ``t`` from the record's first sample)."""

    __test__ = False
    test: str
    omega: float
    A: float
    x0: float
    theta: float
    t: np.ndarray
    F: np.ndarray
    x: np.ndarray
    xd: np.ndarray
    xdd: np.ndarray
    xfun: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]]
    bins: np.ndarray
    counts: np.ndarray
    Fbar: np.ndarray
    sigma: float
    x_meas: np.ndarray
    window: str = ""
    #: per whole cycle: mid time [s], mean force [N], in-phase (sin ψ) and quadrature (cos ψ) force amplitude [N]
    cycles: dict[str, np.ndarray] = field(default_factory=dict)
    #: one model cycle at the distinct sample phases (see :func:`phase_grid`): t [s], x [mm], ẋ, ẍ per point;
    #: map (cell → point), bin and weight per cell
    grid: dict[str, np.ndarray] = field(default_factory=dict)
    #: time origin [s] of ``t`` (the record's first sample): the record's own time is ``t + t_origin``
    t_origin: float = 0.0

    def binmean(self, y: np.ndarray) -> np.ndarray:
        """Bin means of a per-sample quantity ``y`` over the phase bins."""
        return np.bincount(self.bins, weights=y, minlength=self.counts.size) / np.maximum(self.counts, 1)

    def gridmean(self, y: np.ndarray) -> np.ndarray:
        """Bin means of a quantity evaluated on the phase grid (weighted as the samples are)."""
        g = self.grid
        return np.bincount(g["bin"], weights=g["w"] * np.asarray(y)[g["map"]],
                           minlength=self.counts.size) / np.maximum(self.counts, 1)


#: phase quanta per bin of the model grid (the samples' phases are rounded to 1/Q of a bin)
Q = 16


def phase_grid(psi: np.ndarray, B: int, theta: float, omega: float, xfun: Callable,
               bins: np.ndarray | None = None, v_sd: float = 0.0) -> dict[str, np.ndarray]:
    """One cycle of the (periodic) model inputs at the distinct sample phases.

    In the steady window x(t) is periodic in ψ = ωt + θ, so every model force
    (static, memory operators in their periodic steady state, a delay) is a
    function of ψ alone: it is evaluated once per distinct phase, rounded to
    1/Q of a bin (each cell at the mean phase of its samples), weighted by how
    many samples fall there.  Exact for commensurate sampling, and the cost no
    longer grows with the record length.  A point on a reversal within the
    smooth ẋ's standard error ``v_sd`` [mm/s] has ẋ = 0 (:func:`on_reversal`).
    """
    if bins is None:
        bins = np.minimum((psi / (2 * math.pi) * B * Q).astype(np.int64), B * Q - 1) // Q
    ukey, inv, w = grid_cells(psi, bins, B, Q)  # a cell: the sample's own phase bin and its 1/Q of the bin
    # the mean sample phase of each cell (exact when the sampling is commensurate with the cycle: a switch
    # of sgn(ẋ) then falls between the same samples as in the record)
    pg = np.bincount(inv, weights=psi, minlength=ukey.size) / w
    order = np.argsort(pg, kind="stable")  # cells in phase order (the key orders by bin first)
    ukey, w, pg = ukey[order], w[order], pg[order]
    # one sample phase split over two cells by round-off (time stamps written with finite digits) is evaluated
    # once: twins closer than 1e-3 of the typical spacing of distinct phases are one point.  The model runs on
    # the distinct points; each cell (with its own bin and weight) maps to its point
    dp = np.diff(pg)
    tol = max(1e-9, 1e-3 * float(np.median(dp[dp > 1e-9]))) if np.any(dp > 1e-9) else 1e-9
    grp = np.concatenate([[0], np.cumsum(dp > tol)]).astype(np.int64)
    pts = np.bincount(grp, weights=pg * w) / np.bincount(grp, weights=w.astype(float))
    tg = (pts - theta) / omega
    xg, xdg, xddg = xfun(tg)
    return {"t": tg, "x": xg, "xd": on_reversal(xdg, v_sd), "xdd": xddg, "map": grp,
            "bin": (ukey // (B * Q)).astype(np.int64), "w": w.astype(float)}


#: a grid point is on a reversal when its |ẋ| is within this many standard errors of the smooth ẋ of zero
REVERSAL_SIGMAS = 3.0
#: harmonics of the smooth periodic displacement (:func:`fourier_x`)
FOURIER_H = 5


def velocity_sd(resid: np.ndarray, omega: float, H: int = FOURIER_H) -> float:
    """Standard error [mm/s] of the smooth ẋ of :func:`fourier_x` at a phase: least squares over N samples with
    white residual σ (``resid``, the record's x less the fit [mm]; σ² = Σr²/(N − 2H − 1)) gives each harmonic's
    cosine and sine coefficients a variance 2σ²/N, and the k-th harmonic's derivative scales them by kω, so
    var ẋ = (2σ²ω²/N)·Σ_{k=1..H} k²."""
    n = int(np.size(resid))
    dof = n - (2 * H + 1)
    if dof <= 0:
        return 0.0
    sigma2 = float(np.sum(np.square(resid))) / dof
    return omega * math.sqrt(2.0 * sigma2 / n * sum(k * k for k in range(1, H + 1)))


def on_reversal(xd: np.ndarray, v_sd: float) -> np.ndarray:
    """ẋ on one cycle of phase points with 0 at a point that sits on a reversal.

    A record sampled commensurately with its cycle (64 samples a cycle, say) can put a sample exactly on the turning
    point, where a sliding contact's force is set-valued (its midpoint, 0 for a symmetric friction).  The grid's ẋ
    there is the estimate's error, so its sign is that error's, and a friction force evaluated on it is a full ±F
    wrong.  The point where ẋ changes sign (its neighbours of opposite signs, its |ẋ| the least of the three) is
    on the reversal when its |ẋ| is within ``REVERSAL_SIGMAS`` standard errors ``v_sd`` [mm/s] of zero
    (:func:`velocity_sd`): the record cannot tell it from one, and its ẋ is set to 0
    (:func:`chainid.model.operators.coulomb_sign` then gives the midpoint).  A point the record resolves as near
    a reversal, not on it, keeps its ẋ.  [mm/s]"""
    xd = np.asarray(xd, float)
    if xd.size < 3 or not v_sd > 0.0:
        return xd
    prev, nxt = np.roll(xd, 1), np.roll(xd, -1)
    a = np.abs(xd)
    on = (prev * nxt < 0.0) & (a <= np.minimum(np.abs(prev), np.abs(nxt))) & (a <= REVERSAL_SIGMAS * v_sd)
    return np.where(on, 0.0, xd)


def fourier_x(t: np.ndarray, x: np.ndarray, omega: float, theta: float, H: int = FOURIER_H) -> Callable:
    """A smooth periodic displacement model x(t), ẋ(t), ẍ(t) (H harmonics of ω, least squares) [mm, mm/s, mm/s²]."""
    psi = omega * t + theta
    cols = [np.ones_like(t)]
    for k in range(1, H + 1):
        cols += [np.cos(k * psi), np.sin(k * psi)]
    coef, *_ = np.linalg.lstsq(np.column_stack(cols), x, rcond=None)

    def f(ts: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        ps = omega * np.asarray(ts, float) + theta
        xv = np.full_like(ps, coef[0])
        xd = np.zeros_like(ps)
        xdd = np.zeros_like(ps)
        for k in range(1, H + 1):
            a, b = coef[2 * k - 1], coef[2 * k]
            c, s = np.cos(k * ps), np.sin(k * ps)
            xv += a * c + b * s
            w = k * omega
            xd += w * (-a * s + b * c)
            xdd += -w * w * (a * c + b * s)
        return xv, xd, xdd

    return f


class Unusable(ValueError):
    """A test that cannot be analysed (no steady cycle, no harmonic fit): left out with this reason.

    Data errors (NaN, t not increasing, compressive force not allowed) are plain ValueErrors and stop the run.
    """


def _estimate(rec: Any, allow_compression: bool, steady_tol: float | None) -> Any:
    """The record's harmonic estimate with its steady window; :class:`Unusable` with the reason if none."""
    from chainid.records.files import try_analyse

    est, reason = try_analyse(rec, allow_compression=allow_compression, steady_tol=steady_tol)
    if est is None:
        raise Unusable(reason)
    return est


def cycle_stats(t: np.ndarray, F: np.ndarray, omega: float, theta: float,
                x: np.ndarray | None = None) -> dict[str, np.ndarray]:
    """Per whole cycle of ψ = ωt + θ (cycles counted from ψ = 0, only those fully inside the window):
    mid time [s], mean force and its sin ψ / cos ψ amplitudes [N] (least squares per cycle); with ``x`` also
    the cycle's mean displacement ``xm`` and amplitude ``xa`` [mm] (covariates of the trend test), and the
    number of samples ``n``."""
    z = np.zeros(0)
    empty = {"t": z, "mean": z, "a": z, "b": z, "xm": z, "xa": z, "n": z}
    psi = omega * t + theta
    k = np.floor(psi / (2 * math.pi)).astype(np.int64)
    k -= k[0]
    n = int(k[-1]) + 1
    if n < 3:
        return empty
    cnt = np.bincount(k, minlength=n).astype(float)
    # whole cycles only: not the first or last (partial unless the window is phase-aligned), full sample count
    full = np.zeros(n, bool)
    full[1:-1] = True
    full &= cnt >= 0.9 * np.median(cnt[1:-1])
    if not np.any(full):
        return empty
    xx = x if x is not None else np.zeros_like(t)
    beta, _ = segment_lstsq(k, n, (np.ones_like(t), np.sin(psi), np.cos(psi)), (F, xx), full)
    cf, cx = beta[full, :, 0], beta[full, :, 1]
    t_mid = np.bincount(k, weights=t, minlength=n)[full] / cnt[full]
    return {"t": t_mid, "mean": cf[:, 0], "a": cf[:, 1], "b": cf[:, 2], "xm": cx[:, 0], "xa": np.hypot(cx[:, 1], cx[:, 2]), "n": cnt[full]}


def prepare_test(rec: Any, n_bins: int = 64, allow_compression: bool = True,
                 steady_tol: float | None = None) -> TestData:
    """Fold one record's steady window into phase bins; estimate the noise σ [N].

    Parameters
    ----------
    rec : Record
        One test (t s, x mm, F N).
    n_bins : int
        Largest number of phase bins per cycle (fewer when a cycle has few samples).
    allow_compression : bool
        Accept records whose force goes negative.
    steady_tol : float, optional
        Relative tolerance of the steady-cycle selection (None: adaptive, set from the record).

    Raises
    ------
    Unusable
        No steady cycle, or the harmonic estimate fails (the message says why).
    ValueError
        A data error in the record (NaN, t not increasing, compressive force not allowed).
    """
    est = _estimate(rec, allow_compression, steady_tol)
    win = est.window
    if win is None or win.n_cycles < 1:
        raise Unusable("no steady cycles found")
    other = other_plateau(win)
    if other:
        raise Unusable(other)
    m = (rec.t >= win.t_start) & (rec.t < win.t_end)
    # time from the record's first sample (est.t_origin): the phase omega t + theta of a Unix time stamp
    # (~1.7e9 s) would be rounded; TestData.t is this relative time, TestData.t_origin the shift [s]
    t, x, F = rec.t[m] - getattr(est, "t_origin", 0.0), rec.x[m], rec.F[m]
    if t.size < 16:
        raise Unusable(f"only {t.size} samples in the steady window (need >= 16)")
    bad = not_a_sine(t, x, est.omega, est.theta, est.x0, est.A)
    if bad:
        raise Unusable(bad)
    spc = t.size / max(win.n_cycles, 1)
    B = int(max(8, min(n_bins, 4 * (int(spc) // 8))))
    xfun = fourier_x(t, x, est.omega, est.theta)
    xs, xd, xdd = xfun(t)
    psi = np.mod(est.omega * t + est.theta, 2 * math.pi)
    bins = np.minimum((psi / (2 * math.pi) * B).astype(np.int64), B - 1)
    counts = np.bincount(bins, minlength=B).astype(float)
    sigma = cycle_noise(t, F, psi, bins, B, Q)
    sigma = max(sigma, 1e-6 * float(np.std(F)) + 1e-9)
    Fbar = np.bincount(bins, weights=F, minlength=B) / np.maximum(counts, 1)
    describe = getattr(win, "describe", None)
    return TestData(rec.test, est.omega, est.A, est.x0, est.theta, t, F, xs, xd, xdd, xfun, bins, counts, Fbar,
                    sigma, x, describe() if callable(describe) else "", cycle_stats(t, F, est.omega, est.theta, x),
                    phase_grid(psi, B, est.theta, est.omega, xfun, bins, velocity_sd(x - xs, est.omega)),
                    float(getattr(est, "t_origin", 0.0)))


#: a steady harmonic test's displacement departs from its fitted sine by at most this fraction of the amplitude
#: (RMS); a triangle wave departs by 8.5 %, a sine with 2 % harmonic distortion by 2 %
SINE_DISTORTION_MAX = 0.03


def not_a_sine(t: np.ndarray, x: np.ndarray, omega: float, theta: float, x0: float, A: float) -> str:
    """Why a steady window is not a sine test, or "": the RMS departure of x [mm] from the least-squares sine at
    its frequency ω [rad/s] above ``SINE_DISTORTION_MAX``·A beyond what the displacement noise explains (a
    triangular stroke, a clipped or square drive).  Such a record goes to the time-domain route: the phase bins
    of Eq. 17–27 assume x = x0 + A·sin(ωt + θ)."""
    if not A > 0 or t.size < 16:
        return ""
    X = np.column_stack([np.ones_like(t), np.sin(omega * t), np.cos(omega * t)])
    coef, *_ = np.linalg.lstsq(X, x, rcond=None)
    r = x - X @ coef
    amp = float(np.hypot(coef[1], coef[2])) or A
    noise = 1.4826 * float(np.median(np.abs(np.diff(x, 2) - np.median(np.diff(x, 2))))) / math.sqrt(6.0)
    dist = math.sqrt(max(float(np.mean(r**2)) - noise**2, 0.0)) / amp
    if dist > SINE_DISTORTION_MAX:
        return (f"not a sine test: the displacement departs from its fitted sine by {100 * dist:.1f} % of the "
                f"amplitude (RMS; a sine test departs by at most {100 * SINE_DISTORTION_MAX:.0f} %, a triangle by "
                "8.6 %): time-domain route")
    return ""


def other_plateau(win: Any) -> str:
    """Why the record is not *one* steady harmonic test, or "": a whole cycle outside the steady window
    oscillates at the plateau's amplitude (within 25 %) about a mean more than half that amplitude away — a
    second steady state (a load step, a start-up plateau).  Ramp-in and ramp-out cycles (smaller amplitude)
    do not count.  Such a record goes to the time-domain route, which uses all of it."""
    A = np.asarray(getattr(win, "cycle_amplitudes", []) or [], float)
    m = np.asarray(getattr(win, "cycle_means", []) or [], float)
    kept = [k for k in getattr(win, "cycles_kept", []) if 0 <= k < min(A.size, m.size)]
    if not kept or A.size != m.size or not win.plateau_A > 0:
        return ""
    pl_A, pl_m = float(win.plateau_A), float(np.median(m[kept]))
    out = np.ones(A.size, bool)
    out[kept] = False
    other = out & (np.abs(A / pl_A - 1) <= 0.25) & (np.abs(m - pl_m) > 0.5 * pl_A)
    if not other.any():
        return ""
    i = int(np.flatnonzero(other)[0])
    return (f"not one steady harmonic test: cycle {i} oscillates at the plateau amplitude ({A[i]:.3g} mm) about "
            f"x = {m[i]:.4g} mm, {abs(m[i] - pl_m):.3g} mm from the steady window's mean (a load step or another "
            f"plateau)")
