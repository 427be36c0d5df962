"""Independent simulations of devices for the recovery tests of the diagnosis.

Everything here is written from the device laws of the effect library's specification (numpy, scipy): closed-form
motions with exact derivatives, hysteresis integrated in displacement by a fine Runge–Kutta step, friction on the
true velocity, a force-driven resonant device in closed form for a sum of lines (``scipy.integrate.solve_ivp``
for any other force).  Nothing comes from ``chainid.model.effects``, ``chainid.model.operators`` or
``chainid.records.simulate``; the only chainid pieces used are :class:`chainid.records.Record` (the container)
and, for a chain base, ``ChainModel().force`` (the base spring the diagnosis is given).

Units: t s, x mm, ẋ mm/s, ẍ mm/s², F N, m kg (m·ẍ·1e-3 = N), c N·s/mm, k N/mm.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from chainid.records import Record

#: a motion: t [s] -> (x [mm], ẋ [mm/s], ẍ [mm/s²]), exact
MotionFn = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]]


# ---------------------------------------------------------------------------------------------------- motions
def sines(freqs: np.ndarray, amps: np.ndarray, phases: np.ndarray, x0: float = 0.0) -> MotionFn:
    """x(t) = x0 + Σ a_k·sin(2π f_k t + φ_k) with its exact derivatives (f Hz, a mm)."""
    w = 2.0 * np.pi * np.asarray(freqs, float)[:, None]
    a = np.asarray(amps, float)[:, None]
    ph = np.asarray(phases, float)[:, None]

    def fn(t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        arg = w * np.asarray(t, float)[None, :] + ph
        s, c = np.sin(arg), np.cos(arg)
        return x0 + (a * s).sum(0), (a * w * c).sum(0), -(a * w**2 * s).sum(0)

    return fn


def multisine_lines(duration: float, f_lo: float, f_hi: float, rms: float, seed: int = 0, periodic: bool = False,
                    n_lines: int | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The lines (f [Hz], a, φ [rad]) of a band-limited random multisine of RMS ``rms`` (a in the unit of ``rms``):
    lines between f_lo and f_hi, equal amplitudes, random phases.  ``periodic``: on the grid k/duration (a record
    is a whole number of periods of every line); otherwise ``n_lines`` frequencies drawn uniformly in the band (off
    the grid)."""
    rng = np.random.default_rng(seed)
    if periodic:
        k = np.arange(max(1, math.ceil(f_lo * duration)), math.floor(f_hi * duration) + 1)
        f = k / duration
    else:
        f = np.sort(rng.uniform(f_lo, f_hi, n_lines or max(8, int((f_hi - f_lo) * duration))))
    ph = rng.uniform(0.0, 2.0 * np.pi, f.size)
    return f, np.full(f.size, rms * math.sqrt(2.0 / f.size)), ph


def multisine(duration: float, f_lo: float, f_hi: float, rms: float, x0: float = 0.0, seed: int = 0,
              periodic: bool = False, n_lines: int | None = None) -> MotionFn:
    """A band-limited random motion of RMS ``rms`` [mm] about ``x0`` (the lines of :func:`multisine_lines`)."""
    return sines(*multisine_lines(duration, f_lo, f_hi, rms, seed, periodic, n_lines), x0)


def smoothstep(t: np.ndarray, t0: float, t1: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The quintic ramp 0 → 1 between t0 and t1 (C², 10u³ − 15u⁴ + 6u⁵) and its first two derivatives [1/s, 1/s²]."""
    d = t1 - t0
    u = np.clip((np.asarray(t, float) - t0) / d, 0.0, 1.0)
    inside = (u > 0) & (u < 1)
    s = 10 * u**3 - 15 * u**4 + 6 * u**5
    s1 = np.where(inside, (30 * u**2 - 60 * u**3 + 30 * u**4) / d, 0.0)
    s2 = np.where(inside, (60 * u - 180 * u**2 + 120 * u**3) / d**2, 0.0)
    return s, s1, s2


def windowed(carrier: MotionFn, window: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]],
             x0: float = 0.0) -> MotionFn:
    """x = x0 + w(t)·(c(t) − c0) with exact derivatives (product rule); c0 the carrier's own offset is not
    removed: give a carrier about 0."""

    def fn(t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        c, c1, c2 = carrier(t)
        w, w1, w2 = window(t)
        return x0 + w * c, w1 * c + w * c1, w2 * c + 2 * w1 * c1 + w * c2

    return fn


def onset(carrier: MotionFn, t_on: float, ramp: float, x0: float = 0.0) -> MotionFn:
    """Rest at x0 until t_on, then the carrier (about 0) faded in over ``ramp`` seconds."""
    return windowed(carrier, lambda t: smoothstep(t, t_on, t_on + ramp), x0)


def between_rests(carrier: MotionFn, t_on: float, t_off: float, ramp: float, x0: float = 0.0) -> MotionFn:
    """Rest at x0 until t_on, the carrier (about 0) faded in over ``ramp`` [s], faded out to end at t_off, rest."""

    def window(t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        a, a1, a2 = smoothstep(t, t_on, t_on + ramp)
        b, b1, b2 = smoothstep(-np.asarray(t, float), -t_off, -t_off + ramp)
        return a * b, a1 * b - a * b1, a2 * b - 2 * a1 * b1 + a * b2

    return windowed(carrier, window, x0)


def chirp(f0: float, f1: float, t_start: float, t_end: float, amp: float, ramp: float, x0: float = 0.0) -> MotionFn:
    """Rest, a linear chirp f0 → f1 [Hz] of amplitude ``amp`` [mm] between t_start and t_end faded in and out over
    ``ramp`` [s], rest again: exact derivatives."""
    k = (f1 - f0) / (t_end - t_start)

    def carrier(t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        tau = np.asarray(t, float) - t_start
        phi = 2 * np.pi * (f0 * tau + 0.5 * k * tau**2)
        p1 = 2 * np.pi * (f0 + k * tau)
        p2 = 2 * np.pi * k
        s, c = np.sin(phi), np.cos(phi)
        return amp * s, amp * p1 * c, amp * (p2 * c - p1**2 * s)

    def window(t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        a, a1, a2 = smoothstep(t, t_start, t_start + ramp)
        b, b1, b2 = smoothstep(-np.asarray(t, float), -t_end, -t_end + ramp)
        return a * b, a1 * b - a * b1, a2 * b - 2 * a1 * b1 + a * b2

    return windowed(carrier, window, x0)


def sine(freq: float, amp: float, x0: float = 0.0, phase: float = 0.0) -> MotionFn:
    """One sine x0 + A·sin(2πft + φ)."""
    return sines(np.array([freq]), np.array([amp]), np.array([phase]), x0)


def sample_times(n: int, fs: float) -> np.ndarray:
    """n sample times at fs [Hz] from 0 [s]."""
    return np.arange(n) / fs


# ---------------------------------------------------------------------------------------------------- device laws
def fine_path(motion: MotionFn, t: np.ndarray, over: int = 8) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The motion on a grid ``over`` times finer than the samples t: (t_fine, x_fine, ẋ_fine); sample i of t is
    fine point i·over."""
    dt = np.diff(t)
    tf = np.concatenate([(t[:-1, None] + dt[:, None] * (np.arange(over)[None, :] / over)).ravel(), t[-1:]])
    x, xd, _ = motion(tf)
    return tf, x, xd


def bouc_wen_z(x_path: np.ndarray, x_y: float, n: float, r: float, z0: float = 0.0) -> np.ndarray:
    """Bouc–Wen state z along a displacement path (the library's form): dz/dx = (1/x_y)·[1 − (r·sgn(ẋ·z) +
    (1 − r))·|z|^n], integrated in x by classical RK4 on each step of the path (the direction sgn(ẋ) is that
    step's sgn(Δx)).  Dahl hysteresis is n = 1, r = 1.  ``x_path`` may be 2-D (rows = records)."""
    X = np.atleast_2d(np.asarray(x_path, float))
    z = np.full(X.shape[0], float(z0))
    out = np.empty_like(X)
    out[:, 0] = z

    def g(z: np.ndarray, s: np.ndarray) -> np.ndarray:
        return (1.0 - (r * np.sign(s * z) + (1.0 - r)) * np.abs(z) ** n) / x_y

    for i in range(1, X.shape[1]):
        h = X[:, i] - X[:, i - 1]
        s = np.sign(h)
        k1 = g(z, s)
        k2 = g(z + 0.5 * h * k1, s)
        k3 = g(z + 0.5 * h * k2, s)
        k4 = g(z + h * k3, s)
        z = z + h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
        out[:, i] = z
    return out if np.ndim(x_path) == 2 else out[0]


def maxwell_force(t_path: np.ndarray, x_path: np.ndarray, k_m: float, tau_m: float) -> np.ndarray:
    """Force of a Maxwell branch (spring k_m [N/mm] in series with a dashpot of time constant tau_m [s]) along a
    path: dF/dt = k_m·ẋ − F/tau_m, exact for x linear between path points, F(0) = 0."""
    F = np.zeros_like(x_path)
    for i in range(1, x_path.size):
        dt = t_path[i] - t_path[i - 1]
        e = math.exp(-dt / tau_m)
        v = (x_path[i] - x_path[i - 1]) / dt
        F[i] = F[i - 1] * e + k_m * tau_m * (1.0 - e) * v
    return F


def deadband_force(x: np.ndarray, k_d: float, g: float, p: float, x_c: float) -> np.ndarray:
    """End stops: k_d·sgn(u)·max(|u| − g, 0)^p, u = x − x_c [N]."""
    u = np.asarray(x, float) - x_c
    return k_d * np.sign(u) * np.maximum(np.abs(u) - g, 0.0) ** p


def stribeck_force(v: np.ndarray, F_c: float, dF_s: float, v_s: float) -> np.ndarray:
    """Velocity-weakening friction sgn(v)·[F_c + dF_s·exp(−(v/v_s)²)] on the true velocity [N].

    The law is set-valued at v = 0 (stiction: any force in [−F_c − dF_s, F_c + dF_s]); a sample that falls on a
    reversal (|v| at round-off, 1e-12 of the largest |v|, as a sine sampled on its grid puts one at each turning
    point) takes the set's midpoint 0, not the sign of the round-off."""
    v = np.asarray(v, float)
    v = np.where(np.abs(v) <= 1e-12 * max(float(np.max(np.abs(v), initial=0.0)), 1e-300), 0.0, v)
    return np.sign(v) * (F_c + dF_s * np.exp(-(v / v_s) ** 2))


@dataclass(frozen=True, eq=False)
class LineForce:
    """A force [N] that is a sum of lines Σ a_k·sin(2π f_k t + φ_k) (f Hz, a N): callable on t [s]."""

    freqs: np.ndarray
    amps: np.ndarray
    phases: np.ndarray

    def __call__(self, t: np.ndarray) -> np.ndarray:
        return sines(self.freqs, self.amps, self.phases)(np.asarray(t, float))[0]


def resonant_response(force: Callable[[np.ndarray], np.ndarray], t: np.ndarray, m: float, c: float, k: float
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A mass–spring–damper m·ẍ·1e-3 + c·ẋ + k·x = F(t) from rest at t[0]: x [mm], ẋ [mm/s], ẍ [mm/s²] at the
    times t.  A :class:`LineForce` is solved in closed form (:func:`resonant_lines`); any other force is
    integrated by ``solve_ivp`` (DOP853, rtol 1e-10)."""
    if isinstance(force, LineForce):
        return resonant_lines(force, t, m, c, k)
    from scipy.integrate import solve_ivp

    def rhs(tt: float, y: np.ndarray) -> list[float]:
        f = float(force(np.array([tt]))[0])
        return [y[1], (f - c * y[1] - k * y[0]) / (m * 1e-3)]

    sol = solve_ivp(rhs, (t[0], t[-1]), [0.0, 0.0], method="DOP853", t_eval=t, rtol=1e-10, atol=1e-12,
                    max_step=0.25 * (t[1] - t[0]) * 8)
    x, v = sol.y
    return x, v, (force(t) - c * v - k * x) / (m * 1e-3)


def resonant_lines(force: LineForce, t: np.ndarray, m: float, c: float, k: float
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The exact response from rest at t[0] to a line force: each line's steady state a·Im[H(ω)·e^{i(ωt+φ)}],
    H = 1/(k − m·1e-3·ω² + i·c·ω) [mm/N], plus the free response A·e^{s₁τ} + B·e^{s₂τ} (s the roots of
    m·1e-3·s² + c·s + k, τ = t − t[0]) that cancels x and ẋ at t[0].  Distinct roots only (not critical damping)."""
    me = m * 1e-3
    w = 2.0 * np.pi * np.asarray(force.freqs, float)
    H = force.amps / (k - me * w**2 + 1j * c * w)
    e = np.exp(1j * (w[:, None] * np.asarray(t, float)[None, :] + force.phases[:, None]))
    xp = np.imag(H @ e)
    vp = np.imag((1j * w * H) @ e)
    disc = np.sqrt(complex(c * c - 4.0 * me * k))
    if abs(disc) <= 1e-9 * abs(c) + 1e-300:
        raise ValueError(f"critical damping (c = {c}, m = {m}, k = {k}): roots not distinct")
    s1, s2 = (-c + disc) / (2.0 * me), (-c - disc) / (2.0 * me)
    x0, v0 = -xp[0], -vp[0]
    A = (v0 - s2 * x0) / (s1 - s2)
    B = x0 - A
    tau = np.asarray(t, float) - t[0]
    e1, e2 = np.exp(s1 * tau), np.exp(s2 * tau)
    x = xp + np.real(A * e1 + B * e2)
    v = vp + np.real(A * s1 * e1 + B * s2 * e2)
    F = np.imag(force.amps @ e)  # the force itself, on the exponentials already formed
    return x, v, (F - c * v - k * x) / me


def force_sines(duration: float, f_lo: float, f_hi: float, rms: float, seed: int = 0) -> LineForce:
    """A random multisine force [N] of RMS ``rms`` with lines on the grid k/duration between f_lo and f_hi [Hz]."""
    return LineForce(*multisine_lines(duration, f_lo, f_hi, rms, seed, periodic=True))


# ---------------------------------------------------------------------------------------------------- records
@dataclass
class Truth:
    """The true motion and noise-free force of a simulated record (for the tests' references)."""

    x: np.ndarray
    xd: np.ndarray
    xdd: np.ndarray
    F: np.ndarray
    extra: dict = field(default_factory=dict)


def noisy(test: str, t: np.ndarray, x: np.ndarray, F: np.ndarray, sigma_x: float, sigma_F: float, seed: int,
          covariates: dict | None = None) -> Record:
    """A Record with white noise of sd sigma_x [mm] on x and sigma_F [N] on F (seeded)."""
    rng = np.random.default_rng(10_000 + seed)
    return Record(test, t, x + rng.normal(0.0, sigma_x, x.size), F + rng.normal(0.0, sigma_F, F.size),
                  covariates=dict(covariates or {}))


def random_motions(n_rec: int, n: int, fs: float, f_lo: float, f_hi: float, rms: float | list[float],
                   x0: float = 0.0, seed: int = 0, periodic: bool = False) -> list[MotionFn]:
    """``n_rec`` band-limited random motions of n samples at fs (RMS per record or one for all)."""
    rr = rms if isinstance(rms, (list, tuple, np.ndarray)) else [rms] * n_rec
    return [multisine(n / fs, f_lo, f_hi, float(rr[i]), x0, seed + 17 * i, periodic) for i in range(n_rec)]
