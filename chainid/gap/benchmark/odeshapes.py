"""Excitation shapes of the ODE world (:mod:`chainid.gap.benchmark.odeworld`), written apart from the project's
motion programs.

A :class:`Shape` is a normalised signal y(t) [-] with its exact first and second derivatives ẏ [1/s], ÿ [1/s²]
on a fine internal grid of ``over`` points per record sample (rate fs·over), starting ``n_pre`` samples before
the record (a pre-roll: whole periods of a periodic shape, so the device is in its periodic state when the record
starts, or a rest).  The drive of a record is ``mean + amp·y``: a displacement [mm] of a servo-hydraulic machine
or a force [N] of a shaker.

Shapes (frequencies Hz, times s):

* :func:`harmonic` — y = sin(2π f t) after a raised-cosine ramp-in over the first of the pre-roll cycles;
* :func:`multisine` — random-phase multisine, flat amplitude on every line k/T_p inside [f_lo, f_hi] (every m-th
  line when there are more than :data:`MAX_LINES`), periodic with period T_p; the record holds ``n_periods``
  periods (an integer, or not) after one or more pre-roll periods; unit RMS;
* :func:`filtered_noise` — Gaussian noise through a Butterworth band-pass magnitude |H(f)| of the given order
  (synthesised in the frequency domain on the fine grid, derivatives spectral), unit RMS, then a cosine taper
  over ``taper`` seconds at both ends (y = ẏ = 0 at the ends); a rest before the record;
* :func:`chirp` — sine sweeps f0 → f1 (linear or exponential in frequency; down when f0 > f1), each under a
  Tukey window (cosine ends of ``taper`` of the sweep), with the device at rest for ``rest`` s before, between and
  after the sweeps.

Units: t s, f Hz; y dimensionless.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = ["Shape", "harmonic", "multisine", "filtered_noise", "chirp", "check_rate"]

#: sampling rates a record may have [Hz]
FS_RANGE = (200.0, 10_000.0)
#: samples a record may have
N_RANGE = (2_000, 40_000)
#: most lines of a multisine (a denser band takes every m-th line k/T_p)
MAX_LINES = 200


@dataclass(frozen=True)
class Shape:
    """A normalised excitation on the fine grid (see the module docstring).

    Attributes
    ----------
    kind : str
        ``harmonic``, ``multisine``, ``noise`` or ``chirp``.
    t, y, yd, ydd : ndarray
        Fine grid [s] (from −n_pre/fs) and y [-], ẏ [1/s], ÿ [1/s²] on it.
    fs : float
        Sampling rate of the record [Hz].
    over : int
        Fine points per record sample.
    n : int
        Samples of the record.
    n_pre : int
        Samples (of the record's rate) before t = 0 on the fine grid.
    f_lo, f_hi : float
        Band of the excitation [Hz] (f_lo = f_hi = f for a harmonic test).
    info : dict
        Shape details (period, phases, rests, taper), for the truth.
    """

    kind: str
    t: np.ndarray
    y: np.ndarray
    yd: np.ndarray
    ydd: np.ndarray
    fs: float
    over: int
    n: int
    n_pre: int
    f_lo: float
    f_hi: float
    info: dict[str, Any] = field(default_factory=dict)

    @property
    def f_centre(self) -> float:
        """Band centre [Hz]: the frequency of a harmonic test, the mean of the band edges otherwise."""
        return 0.5 * (self.f_lo + self.f_hi)

    @property
    def record_index(self) -> np.ndarray:
        """Indices of the record's samples (t = 0, 1/fs, …) in the fine grid."""
        return self.n_pre * self.over + self.over * np.arange(self.n)


def check_rate(fs: float, n: int) -> None:
    """Refuse a sampling rate or length outside the world's ranges.

    Raises
    ------
    ValueError
        Naming ``fs`` [Hz] or ``n`` and the valid range.
    """
    if not (FS_RANGE[0] <= fs <= FS_RANGE[1]):
        raise ValueError(f"fs = {fs!r} Hz is out of range; valid range {FS_RANGE[0]:g} to {FS_RANGE[1]:g} Hz")
    if not (N_RANGE[0] <= int(n) <= N_RANGE[1]):
        raise ValueError(f"n = {n!r} samples is out of range; valid range {N_RANGE[0]} to {N_RANGE[1]}")


def _grid(fs: float, n: int, n_pre: int, over: int) -> np.ndarray:
    return np.arange(-n_pre * over, n * over, dtype=float) / (fs * over)


def _ramp(t: np.ndarray, t0: float, T: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Raised-cosine ramp from 0 at t0 to 1 at t0 + T and its two derivatives."""
    s = np.clip((t - t0) / T, 0.0, 1.0)
    inside = (s > 0) & (s < 1)
    w = 0.5 * (1 - np.cos(np.pi * s))
    wd = np.where(inside, 0.5 * np.pi / T * np.sin(np.pi * s), 0.0)
    wdd = np.where(inside, 0.5 * (np.pi / T) ** 2 * np.cos(np.pi * s), 0.0)
    return w, wd, wdd


def _window(t: np.ndarray, t_a: float, t_b: float, taper: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Tukey window: 0 before t_a, cosine up over ``taper`` s, 1, cosine down to 0 at t_b, 0 after."""
    u, ud, udd = _ramp(t, t_a, taper)
    d, dd_, ddd = _ramp(-t, -t_b, taper)  # the mirror image: 1 before t_b − taper, 0 at t_b
    return u * d, ud * d - u * dd_, udd * d - 2 * ud * dd_ + u * ddd


def _product(w: tuple[np.ndarray, ...], y: tuple[np.ndarray, ...]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    return w[0] * y[0], w[1] * y[0] + w[0] * y[1], w[2] * y[0] + 2 * w[1] * y[1] + w[0] * y[2]


def harmonic(fs: float, n: int, f: float, pre_cycles: int = 3, over: int = 4) -> Shape:
    """A harmonic test y = sin(2π f t) [-] (see the module docstring); ``pre_cycles`` >= 2 cycles of pre-roll."""
    check_rate(fs, n)
    if not (0 < f <= fs / 10):
        raise ValueError(f"f = {f!r} Hz is out of range; valid range 0 < f <= fs/10 = {fs / 10:g} Hz")
    pre_cycles = max(2, int(pre_cycles))
    n_pre = int(math.ceil(pre_cycles * fs / f))
    t = _grid(fs, n, n_pre, over)
    w = 2 * np.pi * f
    s = (np.sin(w * t), w * np.cos(w * t), -w * w * np.sin(w * t))
    env = _ramp(t, t[0], 1.0 / f)
    y, yd, ydd = _product(env, s)
    return Shape("harmonic", t, y, yd, ydd, fs, over, n, n_pre, f, f, {"f": f, "cycles": n * f / fs})


def multisine(fs: float, n: int, f_lo: float, f_hi: float, n_periods: float, rng: np.random.Generator,
              over: int = 4, pre_periods: int = 1) -> Shape:
    """A random-phase multisine of unit RMS, period T_p = n/(fs·n_periods) [s] (see the module docstring).

    Raises
    ------
    ValueError
        A band with fewer than 3 lines k/T_p, or above fs/10.
    """
    check_rate(fs, n)
    T_p = n / fs / float(n_periods)
    k = np.arange(max(1, math.ceil(f_lo * T_p)), math.floor(f_hi * T_p) + 1)
    if k.size > MAX_LINES:  # every m-th line: a sparse multisine, still periodic in T_p
        k = k[::math.ceil(k.size / MAX_LINES)]
    if k.size < 3 or f_hi > fs / 10:
        raise ValueError(f"multisine band {f_lo:g}-{f_hi:g} Hz holds {k.size} lines of 1/T_p = {1 / T_p:.4g} Hz "
                         f"(valid: >= 3 lines, f_hi <= fs/10 = {fs / 10:g} Hz)")
    n_pre = int(round(pre_periods * T_p * fs))
    t = _grid(fs, n, n_pre, over)
    f = k / T_p
    ph = rng.uniform(0, 2 * np.pi, k.size)
    a = math.sqrt(2.0 / k.size)  # unit RMS over a period
    y, yd, ydd = (np.zeros_like(t) for _ in range(3))
    for fk, pk in zip(f, ph):  # line by line: an outer product of 10^5 times by 10^3 lines would not fit
        w = 2 * np.pi * fk
        s, c = np.sin(w * t + pk), np.cos(w * t + pk)
        y += a * s
        yd += a * w * c
        ydd -= a * w * w * s
    return Shape("multisine", t, y, yd, ydd, fs, over, n, n_pre, float(f[0]), float(f[-1]),
                 {"period_s": T_p, "n_periods": float(n_periods), "lines_hz": f.tolist(), "phases": ph.tolist(),
                  "line_amplitude": a})


def filtered_noise(fs: float, n: int, f_lo: float, f_hi: float, taper: float, rng: np.random.Generator,
                   order: int = 4, over: int = 4, rest: float = 0.0) -> Shape:
    """Band-limited filtered noise of unit RMS (before the taper) with a cosine taper of ``taper`` s at both ends
    and a rest of ``rest`` s before t = 0 (see the module docstring)."""
    check_rate(fs, n)
    T = n / fs
    if not (0 < f_lo < f_hi <= fs / 10) or not (0 < taper <= 0.25 * T):
        raise ValueError(f"noise band {f_lo:g}-{f_hi:g} Hz, taper {taper:g} s: valid 0 < f_lo < f_hi <= fs/10 = "
                         f"{fs / 10:g} Hz and 0 < taper <= T/4 = {T / 4:g} s")
    n_pre = int(round(rest * fs))
    t = _grid(fs, n, n_pre, over)
    m = n * over
    f = np.fft.rfftfreq(m, d=1.0 / (fs * over))
    with np.errstate(divide="ignore"):
        H = np.where(f > 0, 1.0 / np.sqrt((1 + (f_lo / np.where(f > 0, f, 1.0)) ** (2 * order))
                                           * (1 + (f / f_hi) ** (2 * order))), 0.0)
    Z = (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)) * H
    Z[-1] = Z[-1].real if m % 2 == 0 else Z[-1]
    iw = 2j * np.pi * f
    s = [np.fft.irfft(Z * iw ** p, m) for p in range(3)]
    scale = 1.0 / float(np.sqrt(np.mean(s[0] ** 2)))
    body = tuple(np.concatenate([np.zeros(n_pre * over), v * scale]) for v in s)
    win = _window(t, 0.0, T, taper)
    y, yd, ydd = _product(win, body)
    return Shape("noise", t, y, yd, ydd, fs, over, n, n_pre, f_lo, f_hi,
                 {"taper_s": taper, "order": order, "rest_s": rest})


def chirp(fs: float, n: int, f0: float, f1: float, n_sweeps: int, rest: float, log: bool = False,
          taper: float = 0.1, over: int = 4) -> Shape:
    """Sine sweeps f0 → f1 [Hz] of unit amplitude under Tukey windows, with rests of ``rest`` s before, between and
    after them (see the module docstring); ``taper`` is the fraction of a sweep in each cosine end."""
    check_rate(fs, n)
    T = n / fs
    T_s = (T - (n_sweeps + 1) * rest) / n_sweeps
    fmin, fmax = min(f0, f1), max(f0, f1)
    if n_sweeps < 1 or T_s * fmin < 3 or fmax > fs / 10 or rest < 0 or not (0 < taper <= 0.5):
        raise ValueError(f"chirp {f0:g}->{f1:g} Hz, {n_sweeps} sweep(s) of {T_s:.4g} s, rest {rest:g} s: valid "
                         f"n_sweeps >= 1, >= 3 periods of the lowest frequency per sweep, f <= fs/10 = {fs / 10:g} "
                         "Hz, rest >= 0, 0 < taper <= 0.5")
    n_pre = int(round(rest * fs)) if rest > 0 else int(round(0.5 * fs / fmin))
    t = _grid(fs, n, n_pre, over)
    y, yd, ydd = (np.zeros_like(t) for _ in range(3))
    starts = [rest + i * (T_s + rest) for i in range(n_sweeps)]
    for a in starts:
        tau = np.clip(t - a, 0.0, T_s)
        if log:
            r = math.log(f1 / f0) / T_s
            fi = f0 * np.exp(r * tau)
            ph = 2 * np.pi * f0 * (np.exp(r * tau) - 1) / r
            fd = r * fi
        else:
            fi = f0 + (f1 - f0) * tau / T_s
            ph = 2 * np.pi * (f0 * tau + 0.5 * (f1 - f0) * tau * tau / T_s)
            fd = np.full_like(tau, (f1 - f0) / T_s)
        w, wd = 2 * np.pi * fi, 2 * np.pi * fd
        s = (np.sin(ph), w * np.cos(ph), wd * np.cos(ph) - w * w * np.sin(ph))
        win = _window(t, a, a + T_s, taper * T_s)
        p = _product(win, s)
        y += p[0]
        yd += p[1]
        ydd += p[2]
    return Shape("chirp", t, y, yd, ydd, fs, over, n, n_pre, fmin, fmax,
                 {"f0": f0, "f1": f1, "n_sweeps": n_sweeps, "sweep_s": T_s, "rest_s": rest, "log": log,
                  "starts_s": starts, "taper": taper, "down": f1 < f0})
