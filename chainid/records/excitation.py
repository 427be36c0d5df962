"""Non-harmonic displacement programs for simulated records, with exact derivatives.

Four families of the excitations machines meet in service, each a :class:`Motion`
(t s, x mm, ẋ mm/s, ẍ mm/s²) whose derivatives are exact (analytic forms or the
derivatives of a finite Fourier series), so a simulated force F = m·ẍ + F_k(x) + c·ẋ + effects
has no discretisation error of its own:

* :func:`band_random` — band-limited random displacement (flat spectrum in [f_lo, f_hi], random
  phases) about a mean, optionally with a slow wander of the mean;
* :func:`sweep` — a linear or exponential sine sweep (chirp) f0 → f1 at constant amplitude;
* :func:`startup_steps` — a start-up ramp of the mean load with load steps (smooth quintic steps),
  and the machine's running vibration whose frequency runs up from rest during the ramp;
* :func:`earthquake` — ground-motion-like displacement: Kanai–Tajimi filtered noise with a
  Clough–Penzien high-pass, modulated by a rise / strong phase / exponential decay envelope, plus an
  optional near-fault pulse and a permanent offset after it.

Every program can start with a rest lead-in (a trigger delay) and taper in and out
(:func:`with_envelope`).  :func:`simulate_motion` turns a motion into a noisy :class:`Record`.

Units: t s, x mm, ẋ mm/s, ẍ mm/s², f Hz, F N.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from chainid.records.files import Record

__all__ = ["Motion", "band_random", "sweep", "startup_steps", "earthquake", "with_envelope", "simulate_motion",
           "smoothstep"]


@dataclass(frozen=True)
class Motion:
    """A displacement program with exact derivatives.

    Attributes
    ----------
    t : ndarray  time [s], uniform
    x, xd, xdd : ndarray  displacement [mm], velocity [mm/s], acceleration [mm/s²]
    f_max : float  highest frequency of the program [Hz] (band edge)
    A : float  dynamic amplitude scale [mm]: √2 × RMS of the oscillating part
    kind : str  family name
    f_dom : float  dominant frequency [Hz] (where most of the motion is; default f_max)
    """

    t: np.ndarray
    x: np.ndarray
    xd: np.ndarray
    xdd: np.ndarray
    f_max: float
    A: float
    kind: str
    f_dom: float = 0.0

    def __post_init__(self) -> None:
        if not self.f_dom > 0:
            object.__setattr__(self, "f_dom", self.f_max)

    def __add__(self, other: "Motion") -> "Motion":
        return Motion(self.t, self.x + other.x, self.xd + other.xd, self.xdd + other.xdd,
                      max(self.f_max, other.f_max), self.A, self.kind, max(self.f_dom, other.f_dom))


def smoothstep(u: np.ndarray, T: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Quintic step s(u) = 10u³ − 15u⁴ + 6u⁵ of u = (t − t_i)/T clipped to [0, 1], with ds/dt and d²s/dt²
    (continuous acceleration: no jerk spike in the simulated force)."""
    u = np.clip(np.asarray(u, float), 0.0, 1.0)
    s = u**3 * (10 - 15 * u + 6 * u * u)
    ds = 30 * u * u * (1 - u) ** 2 / T
    dds = 60 * u * (1 - u) * (1 - 2 * u) / T**2
    return s, ds, dds


def _check(n: int, fs: float) -> np.ndarray:
    if not (isinstance(n, (int, np.integer)) and n >= 64):
        raise ValueError(f"n = {n!r} samples is invalid: valid range integer >= 64")
    if not (math.isfinite(fs) and fs > 0):
        raise ValueError(f"fs = {fs!r} Hz is invalid: valid range > 0")
    return np.arange(int(n)) / float(fs)


def _fourier(t: np.ndarray, f: np.ndarray, amp: np.ndarray, ph: np.ndarray) -> tuple[np.ndarray, ...]:
    """Σ amp·sin(2πf t + ph) and its first two time derivatives (exact)."""
    x = np.zeros_like(t)
    xd = np.zeros_like(t)
    xdd = np.zeros_like(t)
    for k0 in range(0, f.size, 64):  # chunks: memory n × 64
        w = 2 * np.pi * f[k0:k0 + 64, None]
        arg = w * t[None, :] + ph[k0:k0 + 64, None]
        s, c = np.sin(arg), np.cos(arg)
        a = amp[k0:k0 + 64, None]
        x += (a * s).sum(0)
        xd += (a * w * c).sum(0)
        xdd -= (a * w * w * s).sum(0)
    return x, xd, xdd


def band_random(n: int, fs: float, f_lo: float, f_hi: float, rms: float, x0: float,
                rng: np.random.Generator, wander: float = 0.0) -> Motion:
    """Band-limited random displacement: flat amplitude spectrum on [f_lo, f_hi] Hz (lines at 1/T), random
    phases, scaled to ``rms`` [mm] about ``x0`` [mm]; ``wander`` [mm]: RMS of a slow random wander of the
    mean (lines below f_lo/4)."""
    t = _check(n, fs)
    T = n / fs
    if not (0 < f_lo < f_hi < fs / 2):
        raise ValueError(f"band [{f_lo}, {f_hi}] Hz is invalid: valid range 0 < f_lo < f_hi < fs/2 = {fs / 2:g}")
    f = np.arange(max(1, math.ceil(f_lo * T)), math.floor(f_hi * T) + 1) / T
    if f.size < 2:
        raise ValueError(f"band [{f_lo}, {f_hi}] Hz holds {f.size} line(s) over {T:g} s: valid range >= 2 lines")
    x, xd, xdd = _fourier(t, f, np.ones(f.size), rng.uniform(0, 2 * np.pi, f.size))
    s = rms / float(np.std(x))
    x, xd, xdd = x0 + s * x, s * xd, s * xdd
    if wander > 0:
        fw = np.arange(1, max(2, math.floor(0.25 * f_lo * T)) + 1) / T
        a = 1.0 / fw  # a red spectrum: the slowest lines carry most
        w1, w2, w3 = _fourier(t, fw, a, rng.uniform(0, 2 * np.pi, fw.size))
        sw = wander / max(float(np.std(w1)), 1e-300)
        x, xd, xdd = x + sw * w1, xd + sw * w2, xdd + sw * w3
    return Motion(t, x, xd, xdd, float(f_hi), math.sqrt(2) * rms, "random")


def sweep(n: int, fs: float, f0: float, f1: float, A: float, x0: float, log: bool = False) -> Motion:
    """Sine sweep x = x0 + A sin φ(t), instantaneous frequency from f0 to f1 [Hz] over the record, linear or
    exponential (``log``); A [mm]."""
    t = _check(n, fs)
    T = t[-1] + 1 / fs
    if not (0 < f0 and 0 < f1 < fs / 2 and f0 != f1):
        raise ValueError(f"sweep f0 = {f0}, f1 = {f1} Hz is invalid: valid range 0 < f0 != f1 < fs/2 = {fs / 2:g}")
    if log:
        r = math.log(f1 / f0) / T
        e = np.exp(r * t)
        ph = 2 * np.pi * f0 * (e - 1) / r
        w = 2 * np.pi * f0 * e
        dw = w * r
    else:
        k = (f1 - f0) / T
        ph = 2 * np.pi * (f0 * t + 0.5 * k * t * t)
        w = 2 * np.pi * (f0 + k * t)
        dw = np.full_like(t, 2 * np.pi * k)
    s, c = np.sin(ph), np.cos(ph)
    return Motion(t, x0 + A * s, A * w * c, A * (dw * c - w * w * s), float(max(f0, f1)), float(A), "sweep")


def startup_steps(n: int, fs: float, levels: list[float], t_ramp: float, t_step: float, f_run: float, A: float,
                  x_start: float = 0.0) -> Motion:
    """Start-up with load steps: the mean displacement runs from ``x_start`` up to ``levels[0]`` over ``t_ramp``
    [s] (quintic), then steps to each further level (equally spaced in the rest of the record, each step
    taking ``t_step`` s); the running vibration A·s(t)·sin φ(t) [mm] runs up in frequency from 0 to ``f_run``
    [Hz] (and in amplitude from 0 to A) over the same ramp."""
    t = _check(n, fs)
    T = t[-1] + 1 / fs
    if not (0 < t_ramp < T and t_step > 0 and f_run > 0 and levels):
        raise ValueError(f"start-up: t_ramp = {t_ramp} s, t_step = {t_step} s, f_run = {f_run} Hz, {len(levels)} "
                         f"level(s) invalid: valid range 0 < t_ramp < record length {T:g} s, t_step > 0, f_run > 0, "
                         ">= 1 level")
    s, ds, dds = smoothstep(t / t_ramp, t_ramp)
    m, dm, ddm = x_start + (levels[0] - x_start) * s, (levels[0] - x_start) * ds, (levels[0] - x_start) * dds
    k = len(levels) - 1
    for i in range(k):
        ti = t_ramp + (i + 1) * (T - t_ramp) / (k + 1)
        a, b, c = smoothstep((t - ti) / t_step, t_step)
        h = levels[i + 1] - levels[i]
        m, dm, ddm = m + h * a, dm + h * b, ddm + h * c
    u = np.clip(t / t_ramp, 0.0, 1.0)
    integ = np.where(t < t_ramp, t_ramp * u**4 * (2.5 - 3 * u + u * u), 0.5 * t_ramp + (t - t_ramp))
    ph = 2 * np.pi * f_run * integ
    w, dw = 2 * np.pi * f_run * s, 2 * np.pi * f_run * ds
    sn, cs = np.sin(ph), np.cos(ph)
    x = m + A * s * sn
    xd = dm + A * (ds * sn + s * w * cs)
    xdd = ddm + A * (dds * sn + 2 * ds * w * cs + s * (dw * cs - w * w * sn))
    return Motion(t, x, xd, xdd, float(f_run), float(A), "startup")


def earthquake(n: int, fs: float, peak: float, x0: float, rng: np.random.Generator, f_g: float = 2.0,
               zeta_g: float = 0.5, f_c: float = 0.2, f_hi: float | None = None, t_rise: float | None = None,
               decay: float | None = None, pulse: float = 0.0, offset: float = 0.0) -> Motion:
    """Earthquake-like displacement about ``x0`` [mm] scaled to a peak |x − x0| of ``peak`` [mm].

    Ground acceleration: Kanai–Tajimi spectrum (ground frequency f_g [Hz], damping zeta_g) with a
    Clough–Penzien high-pass at f_c [Hz], cut at f_hi (default 5·f_g); displacement = acceleration/ω²
    (random phases), modulated by e(t) = u^b·exp(b(1 − u)), u = t/t_rise, b = max(2, decay·t_rise): a rise to
    the strong phase at t_rise [s] and a decay at about ``decay`` [1/s] after it (default 6/record length).  ``pulse`` [× peak]: a near-fault
    displacement pulse (a Gabor wavelet at f_g/2 at the envelope's peak); ``offset`` [× peak]: a permanent
    displacement after the pulse (a quintic step over a period of f_g)."""
    t = _check(n, fs)
    T = t[-1] + 1 / fs
    f_hi = 5 * f_g if f_hi is None else f_hi
    if not (0 < f_c < f_g < f_hi < fs / 2):
        raise ValueError(f"earthquake: f_c = {f_c}, f_g = {f_g}, f_hi = {f_hi} Hz invalid: valid range "
                         f"0 < f_c < f_g < f_hi < fs/2 = {fs / 2:g}")
    f = np.arange(1, math.floor(f_hi * T) + 1) / T
    r = (f / f_g) ** 2
    kt = (1 + 4 * zeta_g**2 * r) / ((1 - r) ** 2 + 4 * zeta_g**2 * r)  # Kanai–Tajimi |H|² of acceleration
    rc = (f / f_c) ** 2
    cp = rc**2 / ((1 - rc) ** 2 + 4 * 0.7**2 * rc)  # Clough–Penzien high-pass |H|²
    amp = np.sqrt(kt * cp) / (2 * np.pi * f) ** 2
    g, gd, gdd = _fourier(t, f, amp, rng.uniform(0, 2 * np.pi, f.size))
    t_rise = 0.15 * T if t_rise is None else t_rise
    decay = 6.0 / T if decay is None else decay
    # e = u^b·exp(b(1 − u)), u = t/t_rise: rises to 1 at t_rise, then falls at the rate ≈ b/t_rise = decay
    b = max(2.0, decay * t_rise)
    u = np.maximum(t / t_rise, 1e-12)
    e = np.exp(b * np.log(u) + b * (1 - u))
    q = b * (1 / u - 1)
    ed = e * q / t_rise
    edd = e * (q * q - b / (u * u)) / t_rise**2
    e, ed, edd = (np.where(t > 0, v, 0.0) for v in (e, ed, edd))
    x, xd, xdd = e * g, ed * g + e * gd, edd * g + 2 * ed * gd + e * gdd
    if pulse:
        fp = 0.5 * f_g
        sig = 0.6 / fp
        z = (t - t_rise) / sig
        gau = np.exp(-0.5 * z * z)
        dgau = -z / sig * gau
        ddgau = (z * z - 1) / sig**2 * gau
        wp = 2 * np.pi * fp
        sn, cs = np.sin(wp * (t - t_rise)), np.cos(wp * (t - t_rise))
        pk = float(np.max(np.abs(x))) or 1.0
        P = pulse * pk
        x = x + P * gau * sn
        xd = xd + P * (dgau * sn + gau * wp * cs)
        xdd = xdd + P * (ddgau * sn + 2 * dgau * wp * cs - gau * wp * wp * sn)
    xo = x.copy()  # the oscillating part (before the permanent offset)
    if offset:
        pk = float(np.max(np.abs(x))) or 1.0
        s, ds, dds = smoothstep((t - t_rise) * f_g, 1.0 / f_g)
        x, xd, xdd = x + offset * pk * s, xd + offset * pk * ds, xdd + offset * pk * dds
    sc = peak / max(float(np.max(np.abs(x))), 1e-300)
    return Motion(t, x0 + sc * x, sc * xd, sc * xdd, float(f_hi), math.sqrt(2) * float(np.std(sc * xo)), "quake",
                  float(f_g))


def with_envelope(m: Motion, lead: float = 0.0, taper: float = 0.0) -> Motion:
    """The motion's oscillation about its first value delayed by a rest lead-in of ``lead`` [s] (a trigger
    delay: the record starts at rest) and tapered in and out over ``taper`` [s] (quintic); same length."""
    t = m.t
    x0 = float(m.x[0])
    if lead > 0:
        x = np.interp(t - lead, t, m.x, left=x0)
        xd = np.interp(t - lead, t, m.xd, left=0.0)
        xdd = np.interp(t - lead, t, m.xdd, left=0.0)
        ramp = smoothstep((t - lead) / max(0.25 * lead, 1e-9), max(0.25 * lead, 1e-9))
        # start from rest: the delayed program fades in over a quarter of the lead
        y, yd, ydd = x - x0, xd, xdd
        x = x0 + ramp[0] * y
        xd = ramp[1] * y + ramp[0] * yd
        xdd = ramp[2] * y + 2 * ramp[1] * yd + ramp[0] * ydd
        m = Motion(t, x, xd, xdd, m.f_max, m.A, m.kind, m.f_dom)
    if taper > 0:
        T = t[-1]
        a = smoothstep(t / taper, taper)
        b = smoothstep((T - t) / taper, taper)
        e, ed, edd = a[0] * b[0], a[1] * b[0] - a[0] * b[1], a[2] * b[0] - 2 * a[1] * b[1] + a[0] * b[2]
        xm = float(np.mean(m.x))
        y = m.x - xm
        m = Motion(t, xm + e * y, ed * y + e * m.xd, edd * y + 2 * ed * m.xd + e * m.xdd, m.f_max, m.A, m.kind,
                   m.f_dom)
    return m


def simulate_motion(test: str, m: Motion, model: Any, c: float, *, force_fn: Callable[..., np.ndarray] | None = None,
                    noise_F: float = 0.0, noise_x: float = 0.0, quantum_F: float = 0.0,
                    rng: np.random.Generator | None = None) -> Record:
    """A record of ``model`` driven through the motion ``m``: F = m·ẍ + F_k(x) + c·ẋ [N] (c N·s/mm), through an
    optional hook ``force_fn(t, x, ẋ, ẍ, F) -> F`` (unmodelled effects, as :func:`chainid.records.simulate.
    simulate_test`), plus Gaussian noise on F [N] and x [mm] and a force quantisation step ``quantum_F`` [N].

    Raises
    ------
    ValueError
        A non-finite simulated force (naming the sample).
    """
    from chainid.records.simulate import model_force

    rng = rng if rng is not None else np.random.default_rng(0)
    F = model_force(m.x, m.xd, m.xdd, model, c)
    if force_fn is not None:
        F = np.asarray(force_fn(m.t, m.x, m.xd, m.xdd, F), float)
    bad = ~np.isfinite(F)
    if bad.any():
        i = int(np.argmax(bad))
        raise ValueError(f"test {test!r}: the simulated force is {float(F[i])!r} N at t = {m.t[i]:.6g} s: "
                         "valid range finite")
    Fm = F + (rng.normal(0.0, noise_F, F.size) if noise_F > 0 else 0.0)
    if quantum_F > 0:
        Fm = quantum_F * np.round(Fm / quantum_F)
    xm = m.x + (rng.normal(0.0, noise_x, F.size) if noise_x > 0 else 0.0)
    return Record(test, m.t.copy(), xm, Fm)
