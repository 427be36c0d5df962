"""The filter estimator of smooth kinematics, and its predicted error at the ends of a record.

A record that is not periodic is smoothed by a zero-phase 4th-order Butterworth low-pass (run forward and backward:
gain |H(f)|² = 1/(1 + (tan(πf/fs)/tan(πf_c/fs))⁸), the bilinear transform of the analog prototype) and
differentiated by five-point differences (gain D(f) = fs·(8·sin θ − sin 2θ)/6, θ = 2πf/fs).  Away from the ends
the error of the k-th derivative is stationary: the signal's |(2πf)^k − |H|²·D^k|² and the white noise of x through
|H|⁴·D^{2k} (:func:`chainid.gap.core.kinematics.error_budget`).

**The ends.**  The filter needs samples beyond the record; they are made by :func:`pad_odd`: the odd reflection
about the even part of a cubic fitted over the k samples at each end (a quarter of the band edge's period), so x,
ẋ, ẍ and x⃛ continue unbroken (a plain odd reflection flips ẍ at the end, and its error spreads over the filter's
length).  The differences run on the padded series, so no one-sided difference is taken at an end.

The padding, the filter and the differences are each linear in x, so the estimate of the k-th derivative at sample
j is a fixed row L_j of weights on the samples near its end, and its error is known in closed form for a stationary
signal of one-sided power S(f) per bin plus white noise σ_x (:func:`end_profile`):

    E[e_j²] = Σ_f S(f)·|Σ_i L_ji·e^{i2πf·t_i} − (i2πf)^k·e^{i2πf·t_j}|² + σ_x²·Σ_i L_ji²

(a line a·cos(2πft + φ) of random phase has S = a²/2).  Inside the record the row is the stationary one and the
expression is the stationary budget; within a filter length of an end it is larger (the cubic's extrapolation and
its noise).  It is the error expected over records of the same spectrum: one record's error at its first few
samples varies with the phase of its motion there.

Units: t s, x mm, ẋ mm/s, ẍ mm/s², f and fs Hz, σ_x mm.
"""
from __future__ import annotations

import math

import numpy as np

from chainid.gap.core.noise import sample_rate

__all__ = ["pad_lengths", "curvature_weight", "pad_odd", "derivative", "filtered", "filtered_columns", "stencil_gain",
           "butter_gain2",
           "end_profile"]

#: the filter runs below this fraction of the sampling rate (at or above it: no smoothing)
MAX_CUT = 0.45


def pad_lengths(n: int, fs: float, f_cut: float, f_band: float | None) -> tuple[int, int]:
    """(m, k): the samples added at each end, three periods of the cut (at least 8, at most n − 1), and the samples
    the end cubic is fitted over, a quarter of the band edge's period f_band [Hz] (default f_cut/4; at least 5, at
    most n)."""
    m = int(min(n - 1, max(8, math.ceil(3.0 * fs / f_cut))))
    k = int(math.ceil(fs / (4.0 * (f_band if f_band else 0.25 * f_cut))))
    return max(1, m), max(5, min(k, n))


def curvature_weight(f: np.ndarray, S: np.ndarray, fs: float, k: int, sigma_x: float) -> float:
    """ρ ∈ [0, 1], the weight of the end cubic's curvature in :func:`pad_odd`: the Wiener weight
    E[a₂²]/(E[a₂²] + var(â₂)) of the curvature a₂ = ẍ·h²/2 (h = 1/fs) fitted over k samples, with E[ẍ²] = Σ S·(2πf)⁴
    from the signal's one-sided power S [mm² per bin] at f [Hz] and var(â₂) = σ_x²·[(VᵀV)⁻¹]₂₂ for the cubic's
    Vandermonde V.  On a smooth record it is 1; where x's noise swamps the end's curvature (a noisy record at
    rest at its ends) it is near 0 and the padding is the plain odd reflection."""
    u = np.arange(max(5, int(k)), dtype=float)
    V = np.vander(u, 4)
    var_noise = sigma_x ** 2 * float(np.linalg.inv(V.T @ V)[1, 1])
    acc2 = float(np.sum(np.asarray(S, float) * (2.0 * np.pi * np.asarray(f, float)) ** 4))
    sig = acc2 * (0.5 / fs ** 2) ** 2
    return sig / (sig + var_noise) if sig + var_noise > 0 else 1.0


def pad_odd(x: np.ndarray, m: int, k: int, rho: float = 1.0) -> np.ndarray:
    """x [mm] (samples along axis 0) extended at each end by m samples: u samples beyond an end, 2·(a₀ + ρ·a₂u²) −
    x(u) (with ρ = 1: q(−u) + q(u) − x(u)), where q = a₀ + a₁u + a₂u² + a₃u³ is the cubic fitted over the k samples
    at that end (u = 0 at the end sample) and ρ the curvature's weight (:func:`curvature_weight`).  With ρ = 1, x,
    ẋ, ẍ and x⃛ continue across the end as far as the cubic follows x there; with ρ = 0 it is the odd reflection
    about the cubic's end value (x and ẋ continue, ẍ flips)."""
    x = np.asarray(x, float)
    n = x.shape[0]
    m = max(1, min(m, n - 1))
    k = max(5, min(k, n))
    u = np.arange(k, dtype=float)
    j = np.arange(1, m + 1, dtype=float).reshape((m,) + (1,) * (x.ndim - 1))
    a = np.polyfit(u, x[:k], 3)  # about the first sample
    b = np.polyfit(-u[::-1], x[n - k:], 3)  # about the last sample
    left = 2.0 * (a[3] + rho * a[1] * j ** 2) - x[1:m + 1]
    back = x[n - 2:n - m - 2:-1] if n - m - 2 >= 0 else x[n - 2::-1]
    right = 2.0 * (b[3] + rho * b[1] * j ** 2) - back
    return np.concatenate([left[::-1], x, right])


def derivative(y: np.ndarray, t: np.ndarray) -> np.ndarray:
    """dy/dt along axis 0 by five-point differences on a uniform grid (second-order one-sided differences at the two
    samples at each end); ``np.gradient`` on the time stamps t [s] when the sampling is not uniform (a step off the
    median by more than 1 %)."""
    y = np.asarray(y, float)
    t = np.asarray(t, float)
    dt = np.diff(t)
    h = float(np.median(dt))
    if y.shape[0] < 5 or np.max(np.abs(dt - h)) > 0.01 * h:
        return np.gradient(y, t, axis=0)
    d = np.empty_like(y)
    d[2:-2] = (y[:-4] - 8.0 * y[1:-3] + 8.0 * y[3:-1] - y[4:]) / (12.0 * h)
    # np.gradient's own formulas (edge_order=2) at the two samples of each end, without its pass over the rest
    d[1] = (y[2] - y[0]) / (2.0 * h)
    d[-2] = (y[-1] - y[-3]) / (2.0 * h)
    d[0] = -1.5 / h * y[0] + 2.0 / h * y[1] - 0.5 / h * y[2]
    d[-1] = 0.5 / h * y[-3] - 2.0 / h * y[-2] + 1.5 / h * y[-1]
    return d


def filtered_columns(t: np.ndarray, X: np.ndarray, f_cut: float, f_band: float | None = None, rho: float = 1.0
                     ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`filtered` on every column of X (samples along axis 0): smooth X, its first and second derivative."""
    t = np.asarray(t, float)
    X = np.asarray(X, float)
    n = X.shape[0]
    fs = sample_rate(t)
    if not (f_cut < MAX_CUT * fs and n >= 30):
        Xd = derivative(X, t)
        return X.copy(), Xd, derivative(Xd, t)
    from scipy.signal import butter, sosfiltfilt

    sos = butter(4, f_cut / (0.5 * fs), output="sos")
    m, k = pad_lengths(n, fs, f_cut, f_band)
    Xs = sosfiltfilt(sos, pad_odd(X, m, k, rho), axis=0, padtype=None)
    h = 1.0 / fs
    tp = np.concatenate([t[0] - h * np.arange(m, 0, -1), t, t[-1] + h * np.arange(1, m + 1)])
    Xd = derivative(Xs, tp)
    return Xs[m:m + n], Xd[m:m + n], derivative(Xd, tp)[m:m + n]


def filtered(t: np.ndarray, x: np.ndarray, f_cut: float, f_band: float | None = None, rho: float = 1.0
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Zero-phase Butterworth (4th order, forward-backward) at f_cut [Hz] on x [mm] padded at each end
    (:func:`pad_odd`; the cubic over a quarter of the band edge's period, f_band [Hz], default f_cut/4; its
    curvature weighed by ρ), then five-point differences on the padded series, cut back to the record: x, ẋ, ẍ [mm,
    mm/s, mm/s²] (no smoothing at or above 0.45·fs)."""
    xs, xd, xdd = filtered_columns(t, np.asarray(x, float)[:, None], f_cut, f_band, rho)
    return xs[:, 0], xd[:, 0], xdd[:, 0]


def stencil_gain(w: np.ndarray, fs: float) -> np.ndarray:
    """The five-point difference's gain at angular frequency w [rad/s] (true: w)."""
    th = w / fs
    return fs * (8.0 * np.sin(th) - np.sin(2.0 * th)) / 6.0


def butter_gain2(f: np.ndarray, f_cut: float, fs: float) -> np.ndarray:
    """|H(f)|² of the digital 4th-order Butterworth at f_cut [Hz] (bilinear transform of the analog prototype):
    1/(1 + (tan(πf/fs)/tan(πf_cut/fs))^8) — the forward-backward gain (1 at or above 0.45·fs)."""
    if f_cut >= MAX_CUT * fs:
        return np.ones_like(np.asarray(f, float))
    ratio = np.tan(np.pi * np.minimum(np.asarray(f, float), 0.4999999 * fs) / fs) / math.tan(math.pi * f_cut / fs)
    return 1.0 / (1.0 + ratio ** 8)


#: an end whose weights span more samples than this is probed with random signs instead of every unit impulse
EXACT_SPAN = 600
#: random-sign probes of the noise term past EXACT_SPAN (a row's sum of squares to ±12 % (1 sd), its root ±6 %;
#: the worst of a profile's rows about 20 % off the exact sum)
PROBES = 128
#: the signal's bins are merged into at most this many (power-weighted centre frequency, summed power)
MAX_LINES = 64


def _lines(f: np.ndarray, S: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The bins that hold signal, merged into at most :data:`MAX_LINES` groups of neighbours."""
    keep = np.asarray(S, float) > 0
    fk, Sk = np.asarray(f, float)[keep], np.asarray(S, float)[keep]
    if fk.size <= MAX_LINES:
        return fk, Sk
    groups = np.array_split(np.arange(fk.size), MAX_LINES)
    Sg = np.array([Sk[g].sum() for g in groups])
    return np.array([fk[g] @ Sk[g] for g in groups]) / Sg, Sg


def end_profile(f: np.ndarray, S: np.ndarray, fs: float, f_cut: float, f_band: float | None, sigma_x: float,
                n: int, rho: float = 1.0) -> np.ndarray:
    """The predicted RMS error of x, ẋ and ẍ [mm, mm/s, mm/s²] near the ends of a record of n samples: shape
    (2, 3, R), [0] the first R samples, [1] the last R counted from the end (the forward-backward filter starts
    each pass from its steady state at that pass's first value, so the ends differ), R = the padding's m
    (:func:`pad_lengths`, at most n // 2).  ``S`` is the signal's one-sided power per bin [mm²] at ``f`` [Hz], σ_x
    [mm] the white noise of x, ρ the padding's curvature weight: the module docstring's expression, its signal term
    on the estimator applied to cos and sin of every line, its noise term on the unit impulses (or, past
    :data:`EXACT_SPAN` samples, on :data:`PROBES` seeded random-sign vectors, whose mean square response is
    Σ_i L_ji² in expectation)."""
    m, k = pad_lengths(n, fs, f_cut, f_band)
    R = max(1, min(m, n // 2))
    L = min(n, 2 * R + m + k + 8)
    t = np.arange(L) / fs
    fl, Sl = _lines(f, S)
    w = 2.0 * np.pi * fl
    ph = np.outer(t, w)
    Z = np.eye(L) if L <= EXACT_SPAN else np.random.default_rng(0).choice([-1.0, 1.0], size=(L, PROBES))
    est = filtered_columns(t, np.hstack([np.cos(ph), np.sin(ph), Z]), f_cut, f_band, rho)
    nw = w.size
    true = ((np.cos(ph), np.sin(ph)), (-w * np.sin(ph), w * np.cos(ph)), (-w * w * np.cos(ph), -w * w * np.sin(ph)))
    out = np.empty((2, 3, R))
    for side, rows in enumerate((np.arange(R), L - 1 - np.arange(R))):
        for order, E in enumerate(est):
            e_c = E[rows, :nw] - true[order][0][rows]
            e_s = E[rows, nw:2 * nw] - true[order][1][rows]
            probe = E[rows, 2 * nw:] ** 2
            noise = probe.sum(axis=1) if L <= EXACT_SPAN else probe.mean(axis=1)
            out[side, order] = np.sqrt((e_c ** 2 + e_s ** 2) @ Sl + sigma_x ** 2 * noise)
    return out
