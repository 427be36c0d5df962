"""Harmonic estimate x(t) = x0 + A sin(omega t + theta) of a displacement record (paper Eq. 18, 25).

``omega`` [rad/s] from the FFT peak of the velocity, refined by nonlinear least
squares (``scipy.optimize.least_squares``) on candidate segments; the steady
window from :func:`chainid.signal.steady.select_steady`.  Cost O(N log N) in the number
of samples (long records: the candidate search runs on a decimated copy).

Units: t [s], x [mm], omega [rad/s], theta [rad].
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from chainid.signal.steady import SteadyWindow, select_steady

__all__ = ["HarmonicEstimate", "estimate_harmonic", "refines", "shift_window"]


@dataclass
class HarmonicEstimate:
    """Harmonic model of the displacement, x = x0 + A sin(omega t + theta) (Eq. 18).

    Attributes
    ----------
    omega : float
        Angular frequency [rad/s].
    x0 : float
        Mean elongation [mm].
    A : float
        Amplitude [mm], > 0.
    theta : float
        Phase [rad] in (-pi, pi] at ``t = t_origin``; the paper's Eq. 18 has theta = 0.
    noise : float
        RMS residual of x about the harmonic over the kept window [mm].
    window : SteadyWindow or None
        The steady window used (None if estimated over the whole record).
    source : str
        "estimated" or "side file".
    t_origin : float
        Time origin of the phase [s]: the record's first sample.  Every phase is computed from
        ``t - t_origin``, so a record stamped in Unix time (~1.7e9 s) gives the same phases, cycles and
        windows as the same record from t = 0.

    Notes
    -----
    The window's ``t_start`` and ``t_end`` are in the record's own time [s] (not shifted).
    """

    omega: float
    x0: float
    A: float
    theta: float
    noise: float
    window: SteadyWindow | None = None
    source: str = "estimated"
    t_origin: float = 0.0

    def phase(self, t: np.ndarray) -> np.ndarray:
        """psi = omega (t - t_origin) + theta [rad] (t in the record's time [s])."""
        return self.omega * (np.asarray(t, dtype=float) - self.t_origin) + self.theta

    def x(self, t: np.ndarray) -> np.ndarray:
        """Harmonic displacement [mm]."""
        return self.x0 + self.A * np.sin(self.phase(t))

    def xdot(self, t: np.ndarray) -> np.ndarray:
        """Velocity [mm/s]."""
        return self.omega * self.A * np.cos(self.phase(t))

    def xddot(self, t: np.ndarray) -> np.ndarray:
        """Acceleration [mm/s^2]."""
        return -self.omega**2 * self.A * np.sin(self.phase(t))

    @property
    def period(self) -> float:
        """Period 2 pi / omega [s]."""
        return 2.0 * math.pi / self.omega


# ----------------------------------------------------------------------------
# FFT peak, linear and nonlinear harmonic fits
# ----------------------------------------------------------------------------
def _fft_peak_omega(t: np.ndarray, x: np.ndarray) -> float:
    """Angular frequency [rad/s] of the largest FFT peak of x(t) (linear trend removed).

    Non-uniform sampling is handled by interpolating onto a uniform grid first.
    The peak is refined by parabolic interpolation of the log-magnitude.
    """
    n = t.size
    tu = np.linspace(t[0], t[-1], n)
    xu = np.interp(tu, t, x)
    # remove a linear trend (ramp) and taper with a Hann window
    u = tu - 0.5 * (tu[0] + tu[-1])  # closed-form least-squares line (uniform grid)
    xu = xu - xu.mean() - (u @ xu) / (u @ u) * u
    xu = xu * np.hanning(n)
    # zero padding 4x for ordinary records; long records (> 2^16 samples) already resolve the
    # peak finely (bin = 1/span) and the NLS refinement follows, so no padding there
    nfft = 1 << int(math.ceil(math.log2(max((4 if n <= 65536 else 1) * n, 1024))))
    spec = np.abs(np.fft.rfft(xu, nfft))
    freqs = np.fft.rfftfreq(nfft, d=(tu[1] - tu[0]))
    # ignore the lowest bins: at least ~1.5 cycles in the record
    fmin = 1.5 / (tu[-1] - tu[0])
    spec[freqs < fmin] = 0.0
    k = int(np.argmax(spec))
    if 0 < k < spec.size - 1 and spec[k - 1] > 0 and spec[k + 1] > 0:
        a, b, c = np.log(spec[k - 1]), np.log(spec[k]), np.log(spec[k + 1])
        den = a - 2 * b + c
        delta = 0.5 * (a - c) / den if den != 0 else 0.0
    else:
        delta = 0.0
    return 2.0 * math.pi * (freqs[k] + delta * (freqs[1] - freqs[0]))


def linear_harmonic(t: np.ndarray, x: np.ndarray, omega: float) -> tuple[float, float, float]:
    """Least-squares [1, sin, cos] fit at fixed omega; returns (x0, a, b)."""
    X = np.column_stack([np.ones_like(t), np.sin(omega * t), np.cos(omega * t)])
    sol, *_ = np.linalg.lstsq(X, x, rcond=None)
    return float(sol[0]), float(sol[1]), float(sol[2])


def _nls_harmonic(t: np.ndarray, x: np.ndarray, omega0: float) -> tuple[float, float, float, float, float]:
    """Nonlinear LS refinement of x = x0 + a sin(omega t') + b cos(omega t'), t' = t - mean(t).

    Returns (omega, x0, A, theta, rms) with theta referred to the absolute time t.
    """
    tc = float(np.mean(t))
    tt = t - tc
    x0, a, b = linear_harmonic(tt, x, omega0)

    def resid(p: np.ndarray) -> np.ndarray:
        w, c0, aa, bb = p
        return c0 + aa * np.sin(w * tt) + bb * np.cos(w * tt) - x

    def jac(p: np.ndarray) -> np.ndarray:
        w, _, aa, bb = p
        s, c = np.sin(w * tt), np.cos(w * tt)
        return np.column_stack([tt * (aa * c - bb * s), np.ones_like(tt), s, c])

    sol = least_squares(resid, np.array([omega0, x0, a, b]), jac=jac, method="lm", x_scale="jac")
    w, c0, aa, bb = sol.x
    if w < 0:  # sin(-wt) = -sin(wt): normalise to w > 0
        w, aa = -w, -aa
    A = math.hypot(aa, bb)
    theta_c = math.atan2(bb, aa)  # phase at t' = 0
    theta = theta_c - w * tc
    theta = math.atan2(math.sin(theta), math.cos(theta))
    rms = float(np.sqrt(np.mean(resid(np.array([w, c0, aa, bb])) ** 2)))
    return float(w), float(c0), float(A), float(theta), rms


#: Candidate search of :func:`estimate_harmonic` on long records: at least this many
#: samples per period and in total are kept when decimating (records shorter than
#: ``2 * _SEARCH_N`` samples are never decimated).
_SEARCH_SPC = 16
_SEARCH_N = 20_000


def _search_stride(t: np.ndarray, omega: float) -> int:
    """Decimation step for the candidate search (1 = every sample)."""
    n = t.size
    if n < 2 * _SEARCH_N:
        return 1
    dt = (t[-1] - t[0]) / (n - 1)
    spc = 2 * math.pi / (omega * dt)
    return max(1, min(n // _SEARCH_N, int(spc // _SEARCH_SPC)))


def estimate_harmonic(
    t: np.ndarray,
    x: np.ndarray,
    *,
    rel_tol: float | None = None,
    drop_first: bool = True,
    test: str = "?",
) -> HarmonicEstimate:
    """Estimate omega, x0, A (Eq. 18) and the steady window of a displacement record.

    1. FFT peak of the velocity (``numpy.gradient`` of x; a ramp becomes a
       near-constant and does not mask the oscillation), Hann window, zero
       padding and parabolic peak interpolation; over the whole record and its
       last half and third (distinct peaks are all tried).
    2. Nonlinear least-squares refinement of x = x0 + A sin(omega t + theta)
       (``scipy.optimize.least_squares``) on candidate segments: provisional
       whole cycles at that frequency (lenient :func:`select_steady`), the
       second half, the last third, the last fifth and the whole record; the
       candidate whose steady window has the most cycles wins (ties: smallest
       residual), then one more refinement on that window.
    3. Final steady window aligned with the fitted phase, first cycle dropped,
       and a linear least-squares fit of x0, A, theta on it.

    Parameters
    ----------
    t : ndarray
        Time [s], strictly increasing.
    x : ndarray
        Elongation [mm].
    rel_tol : float or None
        Steady-cycle tolerance (fraction, e.g. 0.03 = 3 %); None (default) =
        adaptive, set from the record's own cycle-to-cycle scatter (see
        :func:`chainid.signal.steady.select_steady`).
    drop_first : bool
        Drop the first steady cycle.
    test : str
        Test id, used in error messages.

    Returns
    -------
    HarmonicEstimate
        omega [rad/s], x0 [mm], A [mm], theta [rad], noise [mm] and window.

    Raises
    ------
    ValueError
        If no oscillation is found.
    """
    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float)
    if t.size < 16:
        raise ValueError(f"test {test!r}: only {t.size} samples; need at least 16")
    # every phase from the record's first sample: omega * 1.7e9 s would round the cycle boundaries
    t_origin = float(t[0])
    t = t - t_origin
    w0s = _start_omegas(t, x, test)
    # long records: the candidate search (step 2) runs on every k-th sample, keeping
    # >= _SEARCH_SPC samples per period and >= _SEARCH_N samples, so its cost does not grow
    # with N; the final window, refinement and fit (step 3) use every sample
    stride = _search_stride(t, min(w0s))
    fit = _best_candidate(t[::stride], x[::stride], w0s, float(t[-1] - t[0]), rel_tol, drop_first, test)
    w, x0, A, theta, rms, win = _final_fit(t, x, fit, stride, rel_tol, drop_first)
    return HarmonicEstimate(omega=w, x0=x0, A=A, theta=theta, noise=rms, window=shift_window(win, t_origin),
                            t_origin=t_origin)


def _start_omegas(t: np.ndarray, x: np.ndarray, test: str) -> list[float]:
    """Step 1 of :func:`estimate_harmonic`: the FFT peaks [rad/s] of the velocity (a ramp becomes a near constant,
    the oscillation dominates) over the whole record and its last half and third (where a slow ramp that outweighs
    a small oscillation has ended), distinct by more than 1 %."""
    span = t[-1] - t[0]
    v = np.gradient(x, t)
    w0s: list[float] = []
    for f in (0.0, 0.5, 0.67):
        seg = t >= t[0] + f * span
        if seg.sum() < 16:
            continue
        w0 = _fft_peak_omega(t[seg], v[seg])
        if w0 > 0 and math.isfinite(w0) and all(abs(w0 - u) > 0.01 * u for u in w0s):
            w0s.append(w0)
    if not w0s:
        raise ValueError(f"test {test!r}: no harmonic oscillation found in x(t)")
    return w0s


def _best_candidate(t: np.ndarray, x: np.ndarray, w0s: list[float], span: float, rel_tol: float | None,
                    drop_first: bool, test: str) -> tuple[float, float, float, float, float]:
    """Step 2 of :func:`estimate_harmonic`: the NLS refinement (ω, x0, A, θ, rms) on candidate segments
    (provisional steady cycles at each start ω, the second half, the last third and fifth, the whole record) whose
    steady window has the most cycles (ties: smallest residual); ``span`` [s] the whole record's."""
    best = None
    for w0 in w0s:
        # (lenient provisional selection: w0 may be off by a fraction of a per cent,
        #  which shows up as drift and amplitude wobble in the per-cycle fits)
        win0 = select_steady(t, x, w0, 0.0, rel_tol=max(rel_tol or 0.0, 0.1), drop_first=False,
                            drift_tol=math.inf)
        segments = []
        if win0.n_cycles >= 1:
            segments.append((t >= win0.t_start) & (t < win0.t_end))
        segments += [t >= t[0] + f * span for f in (0.5, 0.67, 0.8)] + [np.ones(t.size, dtype=bool)]
        for seg in segments:
            if seg.sum() < 16:
                continue
            try:
                w, x0, A, theta, rms = _nls_harmonic(t[seg], x[seg], w0)
            except (ValueError, np.linalg.LinAlgError):
                continue
            if not refines(w, w0, t):
                continue
            win_c = select_steady(t, x, w, theta, rel_tol=rel_tol, drop_first=drop_first)
            # compare at the starting tolerance first (widening is for the final window only)
            score = (win_c.n_cycles_start, win_c.n_cycles, -rms)
            if best is None or score > best[0]:
                best = (score, (w, x0, A, theta, rms))
    if best is None:
        raise ValueError(f"test {test!r}: no harmonic oscillation found in x(t)")
    return best[1]


def _final_fit(t: np.ndarray, x: np.ndarray, fit: tuple[float, float, float, float, float], stride: int,
               rel_tol: float | None, drop_first: bool) -> tuple[float, float, float, float, float, SteadyWindow]:
    """Step 3 of :func:`estimate_harmonic` on every sample: one more NLS refinement on the steady cycles of the
    candidate ``fit`` (every ``stride``-th sample), then the steady window aligned with the phase and the linear
    fit of x0, A, θ at the refined ω.  Returns (ω, x0, A, θ, rms, window)."""
    w, x0, A, theta, rms = fit
    win = select_steady(t, x, w, theta, rel_tol=rel_tol, drop_first=drop_first)
    if win.n_cycles >= 1:  # one more refinement on the steady cycles themselves
        i0, i1 = np.searchsorted(t, [win.t_start, win.t_end], side="left")
        again = _nls_harmonic(t[i0:i1:stride], x[i0:i1:stride], w)
        if refines(again[0], w, t):
            w, x0, A, theta, rms = again
    win = select_steady(t, x, w, theta, rel_tol=rel_tol, drop_first=drop_first)
    if win.n_cycles >= 1:
        m = (t >= win.t_start) & (t < win.t_end)
        x0, a, b = linear_harmonic(t[m], x[m], w)
        A = math.hypot(a, b)
        theta = math.atan2(b, a)
        rms = float(np.sqrt(np.mean((x[m] - x0 - a * np.sin(w * t[m]) - b * np.cos(w * t[m])) ** 2)))
    return w, x0, A, theta, rms, win


def refines(w: float, w0: float, t: np.ndarray) -> bool:
    """Whether a least-squares ω [rad/s] refines its start w0: finite, positive, below the sampling's Nyquist
    frequency and within half of w0 (a fit that ran further converged on something else: from 1.25 rad/s on 1.3
    cycles of a clean 1 rad/s sine, 1.2e11 rad/s, whose cycle boundaries would number in the hundreds of
    billions)."""
    dt = float(np.median(np.diff(t))) if t.size > 1 else math.inf
    return bool(w > 0 and math.isfinite(w) and w < math.pi / dt and abs(w - w0) <= 0.5 * w0)


def shift_window(win: SteadyWindow, t_origin: float) -> SteadyWindow:
    """``win`` (found on ``t - t_origin``) in the record's own time: ``t_start``, ``t_end`` + ``t_origin`` [s]."""
    if t_origin == 0.0:
        return win
    return dataclasses.replace(win, t_start=win.t_start + t_origin, t_end=win.t_end + t_origin)

