"""Causal state operators (memory effects) that run forward over any sampled x(t).

Every operator here is *rate independent*: its output at a sample depends only on the sequence of
displacement values, never on the time stamps, so uniform and non-uniform sampling of the same path give
the same result.  Each has

* a scalar one-step function (numba) ``*_step(state, x_new, ...)`` a time-stepping loop (e.g. a
  dynamics integrator) calls once per step, returning the new state, the force and the energy dissipated
  over the step;
* an array runner over a whole series with a stated initial state, returning the force and the
  per-sample dissipated-energy increments (``dE[0] = 0``, ``dE[i]`` over the step i−1 → i).

Operators (units: x mm, force N, energy N·mm = 1e-3 J):

* :func:`play` — play/backlash of half-width b [mm]: y follows x with a dead band ±b (no force, no
  dissipation; it maps a displacement);
* :func:`jenkins` — Jenkins element: a Coulomb slider of slip force F_c [N] in series with an elastic
  stick spring of stiffness F_c/x_s (stick travel x_s [mm]); force = F_c·(x − y)/x_s with y = play(x, x_s),
  dissipation F_c·|Δy|.  x_s → 0 is Coulomb friction with stick (see :func:`coulomb_sign`);
  loop area of a cycle of amplitude A > x_s: 4·F_c·(A − x_s);
* :func:`stribeck_step` — velocity-weakening (Stribeck) friction for a time-stepper: a Jenkins element whose slip
  force F_c + dF_s·exp(−(v/v_s)²) ± dF follows the speed v at the end of the step (rate dependent: a step function
  only, the speed comes from the stepper);
* :func:`dahl` — Dahl hysteresis: dz/dx = (F_h/x_h)(1 − sgn(ẋ)·z/F_h), solved exactly between samples
  (x piecewise linear); stored energy z²/(2k₀), k₀ = F_h/x_h, so the dissipation rate is z²|ẋ|/F_h ≥ 0;
  loop area of a symmetric cycle of amplitude A: 4·F_h·(A − x_h·tanh(A/x_h));
* :func:`bouc_wen` — Bouc–Wen hysteresis with shape, in normalised form: z ∈ [−1, 1] with
  dz/dx = (1/x_y)·[1 − (r·sgn(ẋ·z) + (1 − r))·|z|^n], force F_y·z.  x_y [mm] is the yield travel (the initial
  stiffness is F_y/x_y), n > 0 the sharpness of the yield knee, r ∈ [0, 1] the unloading shape (r = 1:
  unloading stiffer than the initial slope, r = ½: unloading at the initial slope).  Dahl is n = 1, r = 1.
  The classical form F = α·z_c, ż_c = A·ẋ − β|ẋ||z_c|^(n−1)z_c − γẋ|z_c|^n maps to it by
  z_c = z·z_m with z_m = (A/(β + γ))^(1/n), α·z_m = F_y, x_y = z_m/A, r = β/(β + γ);
  stepped exactly on a travel table of the autonomous law (:func:`bouc_wen_table`: the travel between two states
  is a difference of a tabulated integral), so a sample step of any size costs two table look-ups;
* :func:`iwan` — Masing/Iwan model: Jenkins elements (F_c,i, x_s,i) in parallel, a rate-independent
  hysteretic damping; :func:`iwan_for_loss` builds the distribution whose loop area is π·η·k·A² (the
  structural-damping energy) for every A up to its largest stick travel.

Initial states (stated): play y₀ = x₀ (centred in the dead band); Jenkins and Iwan sliders y₀ = x₀
(unstressed); Dahl and Bouc–Wen z₀ = 0.  ``periodic=True`` runs the series twice and returns the second pass (the
periodic steady state of a series that is one period).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

try:  # numba with a cache that never crashes chainid; plain Python if numba is absent
    from chainid.infra.numba_cache import njit_cached as njit
except Exception:  # pragma: no cover
    def njit(*a: Any, **k: Any) -> Any:  # type: ignore
        def deco(f: Any) -> Any:
            return f
        return deco if not (a and callable(a[0])) else a[0]

__all__ = ["play_step", "jenkins_step", "stribeck_step", "dahl_step", "bouc_wen_step", "bouc_wen_table", "iwan_step",
           "play",
           "jenkins", "dahl", "bouc_wen", "iwan",
           "iwan_for_loss", "coulomb_sign", "dahl_cycle_energy", "jenkins_cycle_energy"]


# ------------------------------------------------------------------ one-step functions (numba)
@njit()
def play_step(y: float, x: float, b: float) -> float:  # pragma: no cover - numba
    """Play output [mm] after x moves to ``x`` [mm], from output ``y`` [mm], half-width ``b`` [mm] (≥ 0)."""
    if x - b > y:
        return x - b
    if x + b < y:
        return x + b
    return y


@njit()
def jenkins_step(y: float, x: float, F_c: float, x_s: float) -> tuple[float, float, float]:  # pragma: no cover
    """One step of a Jenkins element (slip force F_c [N], stick travel x_s [mm] > 0).

    Returns (slider position y [mm], force [N], dissipated energy over the step [N·mm]).
    """
    yn = play_step(y, x, x_s)
    return yn, F_c * (x - yn) / x_s, F_c * abs(yn - y)


@njit()
def stribeck_step(y: float, x: float, v: float, k: float, F_c: float, dF_s: float, v_s: float,
                  dF: float) -> tuple[float, float, float]:  # pragma: no cover - numba
    """One step of Stribeck friction regularised by an elastic stick (a Jenkins element whose slip force weakens
    with the sliding speed), for a time-stepper.

    The slider at ``y`` [mm] is joined to ``x`` [mm] by a stick spring ``k`` [N/mm] (> 0); it slips when the spring
    force k·(x − y) leaves the band [−(f − dF), f + dF] with f = F_c + dF_s·exp(−(v/v_s)²) at the speed ``v``
    [mm/s] of x at the end of the step: the static force F_s = F_c + dF_s at rest, the kinetic F_c when fast
    (v_s [mm/s] > 0), and a direction asymmetry dF [N] (|dF| ≤ F_c: slip force F_c + dF moving +x).  While the
    band holds the spring, nothing slips (no sign of v is ever taken: the force near v = 0 is the stick spring's,
    continuous, so a time-stepper neither chatters nor drifts).  Sliding, the force is ±(band edge), the library's
    sgn(ẋ)·[F_c + dF_s·exp(−(ẋ/v_s)²)] + dF.

    Returns (slider position [mm], force [N], dissipated energy over the step [N·mm] = force·Δy ≥ 0).
    """
    w = math.exp(-(v / v_s) * (v / v_s))
    f = F_c + dF_s * w
    z = k * (x - y)
    yn = y
    if z > f + dF:
        yn = x - (f + dF) / k
    elif z < -(f - dF):
        yn = x + (f - dF) / k
    zn = k * (x - yn)
    return yn, zn, zn * (yn - y)


@njit()
def dahl_step(z: float, x_prev: float, x: float, F_h: float, x_h: float) -> tuple[float, float]:  # pragma: no cover
    """One exact step of the Dahl model from (z [N] at x_prev [mm]) to x [mm].

    Returns (z [N] at x, dissipated energy over the step [N·mm]): the work ∫z dx of the exact exponential
    branch minus the change of the stored energy z²/(2F_h/x_h).
    """
    dx = x - x_prev
    if dx == 0.0 or F_h == 0.0:
        return z, 0.0
    s = 1.0 if dx > 0 else -1.0
    e = math.exp(-abs(dx) / x_h)
    zn = s * F_h + (z - s * F_h) * e
    work = s * (s * F_h * abs(dx) + (z - s * F_h) * x_h * (1.0 - e))
    stored = (zn * zn - z * z) * x_h / (2.0 * F_h)
    return zn, work - stored


#: points of the Bouc–Wen travel table (uniform in u, z = tanh u, over |u| <= BW_U)
BW_POINTS = 4001
BW_U = 9.0


def bouc_wen_table(n: float, r: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The travel table of the normalised Bouc–Wen law for a step in +x (any x_y: travel scales with it).

    Moving in +x, dz/dξ = h(z) = 1 − (r·sgn(z) + 1 − r)·|z|^n with ξ = x/x_y, an autonomous law, so the travel
    from one state to another is ξ(z₁) − ξ(z₀) with ξ(z) = ∫ dz/h(z).  Tabulated on z = tanh(u) (the integrand
    (1 − z²)/h(z) stays finite as z → ±1, where h vanishes linearly) by the trapezoid rule over :data:`BW_POINTS`
    points: returns (z, ξ, Z) with Z = ∫ z dξ (the work per unit F_y·x_y).  A step in −x is the same map of −z.
    """
    u = np.linspace(-BW_U, BW_U, BW_POINTS)
    z = np.tanh(u)
    az = np.abs(z)
    h = 1.0 - (r * np.sign(z) + (1.0 - r)) * az ** n
    g = (1.0 - z * z) / np.maximum(h, 1e-300)
    du = u[1] - u[0]
    xi = np.concatenate([[0.0], np.cumsum(0.5 * (g[1:] + g[:-1]) * du)])
    zg = z * g
    Z = np.concatenate([[0.0], np.cumsum(0.5 * (zg[1:] + zg[:-1]) * du)])
    return z, xi, Z


@njit()
def bouc_wen_step(z: float, x_prev: float, x: float, F_y: float, x_y: float, txi: np.ndarray,
                  tZ: np.ndarray) -> tuple[float, float]:  # pragma: no cover - numba
    """One exact step of the normalised Bouc–Wen model from (z at x_prev [mm]) to x [mm] on the travel table
    (txi, tZ) of :func:`bouc_wen_table` (its n, r; uniform in u = atanh z over ±BW_U).

    Returns (z at x, dissipated energy over the step [N·mm]): F_y·∫z dx minus the change of the stored energy
    F_y·x_y·z²/2 of the initial stiffness (exact for Dahl, n = 1, r = 1).
    """
    dx = x - x_prev
    if dx == 0.0:
        return z, 0.0
    s = 1.0 if dx > 0 else -1.0
    m = txi.size
    du = 2.0 * BW_U / (m - 1)
    zs = min(max(s * z, -0.9999999999), 0.9999999999)  # the step in +x of the mirrored state
    q = (math.atanh(zs) + BW_U) / du
    q = min(max(q, 0.0), m - 1.0)
    k0 = min(int(q), m - 2)
    a0 = q - k0
    xi0 = txi[k0] + a0 * (txi[k0 + 1] - txi[k0])
    Z0 = tZ[k0] + a0 * (tZ[k0 + 1] - tZ[k0])
    xi1 = xi0 + abs(dx) / x_y
    k1 = np.searchsorted(txi, xi1)
    if k1 >= m:
        u1 = BW_U
        Z1 = tZ[m - 1] + (xi1 - txi[m - 1])  # saturated: z = 1 over the rest of the travel
    else:
        k1 = max(k1, 1)
        a1 = (xi1 - txi[k1 - 1]) / (txi[k1] - txi[k1 - 1])
        u1 = -BW_U + (k1 - 1 + a1) * du
        Z1 = tZ[k1 - 1] + a1 * (tZ[k1] - tZ[k1 - 1])
    zn = s * math.tanh(u1)
    work = x_y * (Z1 - Z0)  # ∫ z dx of the true state (mirrored: z·dx = z̃·dξ·x_y)
    return zn, F_y * work - 0.5 * F_y * x_y * (zn * zn - z * z)


@njit()
def iwan_step(y: np.ndarray, x: float, F_c: np.ndarray, x_s: np.ndarray) -> tuple[float, float]:  # pragma: no cover
    """One step of parallel Jenkins elements; ``y`` (slider positions [mm]) is updated in place.

    Returns (force [N], dissipated energy over the step [N·mm]).
    """
    F = 0.0
    dE = 0.0
    for i in range(y.size):
        yn, f, d = jenkins_step(y[i], x, F_c[i], x_s[i])
        y[i] = yn
        F += f
        dE += d
    return F, dE


# ------------------------------------------------------------------ array loops (numba)
@njit()
def _play_run(x: np.ndarray, b: float, y0: float) -> np.ndarray:  # pragma: no cover - numba
    y = np.empty_like(x)
    yi = y0
    for i in range(x.size):
        yi = play_step(yi, x[i], b)
        y[i] = yi
    return y


@njit()
def _dahl_run(x: np.ndarray, F_h: float, x_h: float, z0: float) -> tuple[np.ndarray, np.ndarray]:  # pragma: no cover
    z = np.empty_like(x)
    dE = np.zeros_like(x)
    zi = z0
    z[0] = zi
    for i in range(1, x.size):
        zi, d = dahl_step(zi, x[i - 1], x[i], F_h, x_h)
        z[i] = zi
        dE[i] = d
    return z, dE


@njit()
def _bouc_wen_run(x: np.ndarray, F_y: float, x_y: float, txi: np.ndarray, tZ: np.ndarray,
                  z0: float) -> tuple[np.ndarray, np.ndarray]:  # pragma: no cover - numba
    z = np.empty_like(x)
    dE = np.zeros_like(x)
    zi = z0
    z[0] = zi
    for i in range(1, x.size):
        zi, d = bouc_wen_step(zi, x[i - 1], x[i], F_y, x_y, txi, tZ)
        z[i] = zi
        dE[i] = d
    return z, dE


@njit()
def _iwan_run(x: np.ndarray, F_c: np.ndarray, x_s: np.ndarray, y0: np.ndarray) -> tuple[np.ndarray, np.ndarray]:  # pragma: no cover
    y = y0.copy()
    F = np.empty_like(x)
    dE = np.zeros_like(x)
    for i in range(x.size):
        F[i], dE[i] = iwan_step(y, x[i], F_c, x_s)
    return F, dE


# ------------------------------------------------------------------ array runners (public)
def _series(x: Any, periodic: bool) -> tuple[np.ndarray, int]:
    x = np.ascontiguousarray(x, dtype=np.float64)
    if x.ndim != 1 or x.size == 0:
        raise ValueError(f"x must be a non-empty 1-D series of displacements [mm]; got shape {x.shape}")
    if not np.all(np.isfinite(x)):
        raise ValueError("x contains NaN or infinite values; the operators need finite displacements [mm]")
    return (np.concatenate([x, x]) if periodic else x), (x.size if periodic else 0)


def _nonneg(name: str, v: float) -> float:
    v = float(v)
    if not (math.isfinite(v) and v >= 0):
        raise ValueError(f"{name} = {v!r} is out of range; valid range >= 0")
    return v


def play(x: Any, b: float, y0: float | None = None, periodic: bool = False) -> np.ndarray:
    """Play (backlash) output y [mm] of x [mm] with half-width b [mm]; initial output y0 (default x[0])."""
    b = _nonneg("b (play half-width, mm)", b)
    xs, k = _series(x, periodic)
    if b == 0:
        return xs[k:].copy()
    return _play_run(xs, b, float(xs[0] if y0 is None else y0))[k:]


#: |ẋ| at or below this fraction of the largest |ẋ| is an instant on a turning point (round-off)
ROUND_OFF = 1e-12


def coulomb_sign(xd: Any, periodic: bool = True) -> np.ndarray:
    """sgn(ẋ) of Coulomb sliding (the x_s → 0 limit of :func:`jenkins`), 0 for an instant on a turning point.

    The force of sliding friction at an instant is F_c·sgn(ẋ), however near a reversal the instant falls: a record
    samples the force at instants, and the harmonic route evaluates its model at the samples' phases (exact for
    commensurate sampling).  Only an instant on the turning point (|ẋ| at round-off, ``ROUND_OFF`` of the largest
    |ẋ|, as a sine sampled on its grid puts one at each turning point) takes the set-valued force at its midpoint,
    0 (stick).  ``periodic`` (the series is one cycle) is accepted for symmetry with the operators; the rule does
    not depend on it.

    An earlier rule zeroed every sample within a third of a step of a reversal (speed under half its neighbours'):
    a full F_c wrong on two reversals in three of sampled data, and a 0.1 % bias of F_c that only a Richardson
    extrapolation in Δt could remove.
    """
    xd = np.asarray(xd, dtype=float)
    s = np.sign(xd)
    a = np.abs(xd)
    s[a <= ROUND_OFF * float(np.max(a, initial=0.0))] = 0.0
    return s


def jenkins(x: Any, F_c: float, x_s: float, y0: float | None = None,
            periodic: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Force [N] and dissipated-energy increments [N·mm] of a Jenkins element over x [mm].

    F_c [N] ≥ 0 slip force, x_s [mm] > 0 stick travel (for x_s = 0 use :func:`coulomb_sign` with the
    velocity: the set-valued Coulomb limit needs ẋ), y0 the initial slider position (default x[0]:
    unstressed).
    """
    F_c = _nonneg("F_c (slip force, N)", F_c)
    x_s = _nonneg("x_s (stick travel, mm)", x_s)
    if x_s == 0:
        raise ValueError("x_s = 0 (Coulomb with rigid stick) needs the velocity: use coulomb_sign(xdot)·F_c")
    xs, k = _series(x, periodic)
    F, dE = _iwan_run(xs, np.array([F_c]), np.array([x_s]), np.array([float(xs[0] if y0 is None else y0)]))
    return F[k:], dE[k:]


def dahl(x: Any, F_h: float, x_h: float, z0: float = 0.0,
         periodic: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Dahl force z [N] and dissipated-energy increments [N·mm] over x [mm].

    F_h [N] the saturation force, x_h [mm] > 0 the travel over which z approaches ±F_h, z0 [N] the
    initial force (|z0| ≤ F_h).
    """
    F_h = float(F_h)
    if not math.isfinite(F_h):
        raise ValueError(f"F_h = {F_h!r} must be finite [N]")
    x_h = float(x_h)
    if not (math.isfinite(x_h) and x_h > 0):
        raise ValueError(f"x_h = {x_h!r} is out of range; valid range > 0 [mm]")
    xs, k = _series(x, periodic)
    z, dE = _dahl_run(xs, F_h, x_h, float(z0))
    return z[k:], dE[k:]


def bouc_wen(x: Any, F_y: float, x_y: float, n: float, r: float, z0: float = 0.0,
             periodic: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Bouc–Wen force F_y·z [N] and dissipated-energy increments [N·mm] over x [mm] (see the module docstring).

    F_y [N] the saturation force, x_y [mm] > 0 the yield travel, n > 0 the knee sharpness, r ∈ [0, 1] the
    unloading shape, z0 ∈ [−1, 1] the initial normalised state.
    """
    F_y = float(F_y)
    if not math.isfinite(F_y):
        raise ValueError(f"F_y = {F_y!r} must be finite [N]")
    for name, v, lo, hi in (("x_y", x_y, 0.0, math.inf), ("n", n, 0.0, 50.0), ("r", r, 0.0, 1.0)):
        v = float(v)
        if not (math.isfinite(v) and (lo < v if name != "r" else lo <= v) and v <= hi):
            raise ValueError(f"{name} = {v!r} is out of range; valid range {lo:g} to {hi:g}"
                             + (" (exclusive)" if name != "r" else ""))
    if not -1.0 <= float(z0) <= 1.0:
        raise ValueError(f"z0 = {z0!r} is out of range; valid range -1 to 1")
    xs, k = _series(x, periodic)
    _, txi, tZ = _table(float(n), float(r))
    z, dE = _bouc_wen_run(xs, F_y, float(x_y), txi, tZ, float(z0))
    return F_y * z[k:], dE[k:]


_TABLES: dict[tuple[float, float], tuple[np.ndarray, np.ndarray, np.ndarray]] = {}


def _table(n: float, r: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`bouc_wen_table` of (n, r), kept for the last 64 shapes."""
    key = (n, r)
    if key not in _TABLES:
        if len(_TABLES) >= 64:
            _TABLES.pop(next(iter(_TABLES)))
        _TABLES[key] = bouc_wen_table(n, r)
    return _TABLES[key]


def iwan(x: Any, F_c: Any, x_s: Any, y0: Any = None, periodic: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Force [N] and dissipated-energy increments [N·mm] of parallel Jenkins elements (Masing/Iwan).

    F_c, x_s : arrays of slip forces [N] (≥ 0) and stick travels [mm] (> 0), one per element.
    y0 : initial slider positions [mm] (default x[0] for every element: unstressed).
    """
    Fc = np.ascontiguousarray(F_c, dtype=np.float64).ravel()
    xs_ = np.ascontiguousarray(x_s, dtype=np.float64).ravel()
    if Fc.size != xs_.size or Fc.size == 0:
        raise ValueError(f"iwan: F_c ({Fc.size}) and x_s ({xs_.size}) need the same number (>= 1) of elements")
    if np.any(~np.isfinite(Fc)) or np.any(Fc < 0) or np.any(~np.isfinite(xs_)) or np.any(xs_ <= 0):
        raise ValueError("iwan: every F_c must be >= 0 [N] and every x_s > 0 [mm]")
    xx, k = _series(x, periodic)
    y = np.full(Fc.size, float(xx[0])) if y0 is None else np.ascontiguousarray(y0, dtype=np.float64).copy()
    F, dE = _iwan_run(xx, Fc, xs_, y)
    return F[k:], dE[k:]


def iwan_for_loss(eta_k: float, x_max: float, n: int = 32) -> tuple[np.ndarray, np.ndarray]:
    """Iwan elements whose loop area is π·η·k·A² [N·mm] for every amplitude A ≤ x_max [mm].

    A uniform density φ = π·η·k/2 [N/mm] of slip force over the stick travel s ∈ (0, x_max] gives
    W(A) = ∫₀ᴬ 4φ(A − s) ds = 2φA² = πηkA² (structural damping).  Midpoint discretisation with ``n``
    elements: s_i = (i − ½)·x_max/n, F_c,i = φ·x_max/n (exact at A = j·x_max/n).

    Parameters
    ----------
    eta_k : float
        Loss factor times stiffness, η·k [N/mm] (≥ 0).
    x_max : float
        Largest amplitude the distribution covers [mm] (> 0); beyond it the loop area grows only linearly.
    """
    eta_k = _nonneg("eta_k (N/mm)", eta_k)
    if not (math.isfinite(x_max) and x_max > 0):
        raise ValueError(f"x_max = {x_max!r} is out of range; valid range > 0 [mm]")
    if n < 1:
        raise ValueError(f"n = {n!r} is out of range; valid range >= 1")
    d = x_max / n
    return np.full(n, 0.5 * math.pi * eta_k * d), (np.arange(n) + 0.5) * d


def jenkins_cycle_energy(F_c: float, x_s: float, A: float) -> float:
    """Closed-form loop area [N·mm] of a Jenkins element over a symmetric cycle ±A [mm]: 4F_c(A − x_s)⁺."""
    return 4.0 * F_c * max(A - x_s, 0.0)


def dahl_cycle_energy(F_h: float, x_h: float, A: float) -> float:
    """Closed-form loop area [N·mm] of the Dahl model over a symmetric cycle ±A [mm]: 4F_h(A − x_h·tanh(A/x_h))."""
    return 4.0 * F_h * (A - x_h * math.tanh(A / x_h))
