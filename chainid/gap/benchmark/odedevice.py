"""Devices of the ODE world: a base with effects carried by internal states, integrated in time with LSODA.

Written from the equations of the effect library (names and parameters of ``effects_spec``), apart from the
project's effect operators: every memory effect is an ordinary differential equation in time, integrated with
``scipy.integrate.odeint`` (LSODA, stiff/non-stiff switching) on a fine grid, never the exact rate-independent
stepping of :mod:`chainid.model.operators`.  The chain spring F_k(x) comes from :class:`chainid.model.base.ChainModel`
(the base physics, shared on purpose).

Device force (units mm, N, s, kg; m·ẍ·1e-3 = N)::

    F = (m + m_f)·ẍ·1e-3 + F_spring(u) + c·ẋ + z_f + F_str(ẋ) + F_h·z_h + F_y·z_b + F_dead(x) + F_hard(x)
        [+ q (Maxwell branch) + k_s·(x − y_s) + c_s·(ẋ − ẏ_s) (stick-slip slider)]

* F_spring: the chain's F_k (ChainModel with ``ea_scale``, ``hertz_scale``, ``contact_exponent``, ``slack``) or
  k·(u − x_ref); u = x, or the play output u = x − h·w (``backlash``, h = b/2);
* ``friction`` — Jenkins slider, smoothed: ż_f = k_t·ẋ·(1 − [ẋ·z_f > 0]·|z_f/F_±|^N), k_t = F_c/x_s, slip force
  F_+ = F_c + dF moving +x, F_− = F_c − dF moving −x, N = :data:`N_SLIP`;
* ``stribeck`` — tanh(ẋ/v_e)·[F_c + (F_s − F_c)·exp(−(ẋ/v_s)²)] + dF·|tanh(ẋ/v_e)| (v_e the regularisation speed);
* ``hysteresis`` — Dahl: ż_h = (ẋ − |ẋ|·z_h)/x_h;
* ``bouc_wen`` — ż_b = (ẋ − r·|ẋ|·sgn(z_b)·|z_b|^n − (1 − r)·ẋ·|z_b|^n)/x_y (Dahl for n = r = 1);
* ``backlash`` — play state w ∈ [−1, 1]: ẇ = (ẋ/h)·(1 − [ẋ·w > 0]·|w|^N);
* ``deadband`` — k_d·sgn(x − x_c)·max(|x − x_c| − g, 0)^p;  ``hardening`` — k3·(x − x_m)³ + k2·(x − x_m)²;
* ``fixture_mass`` — m_f [kg];
* outside the library: ``relaxation`` (Maxwell branch q̇ = k_m·ẋ − q/τ_m) and ``chatter`` (a slider of mass m_s on
  a spring k_s and dashpot c_s from the drive, rubbing with velocity-weakening friction: stick-slip at the
  structural frequency √(k_s/m_s)).

Two drive modes: :func:`run_displacement` (x(t) prescribed: a servo-hydraulic machine; the states are integrated,
the force evaluated) and :func:`run_force` (F(t) prescribed on a linear-base device: (m + m_f)·ẍ·1e-3 = F −
F_internal(x, ẋ, states), a shaker or an analog mass–spring–damper).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numba import njit
from scipy.integrate import odeint
from scipy.optimize import brentq

__all__ = ["Device", "Trace", "run_displacement", "run_force", "N_SLIP", "STATE_EFFECTS"]

#: exponent of the smoothed slip and play switches (the larger, the sharper the corner)
N_SLIP = 25.0
#: effects and outside mechanisms that carry internal states, in state order
STATE_EFFECTS = ("friction", "hysteresis", "bouc_wen", "backlash", "relaxation", "chatter")

# parameter vector layout (numba reads the module-level ints as constants)
K, XREF, C = 0, 1, 2
FR_ON, FR_KT, FR_FP, FR_FM = 3, 4, 5, 6
ST_ON, ST_FC, ST_FS, ST_DF, ST_VS, ST_VE = 7, 8, 9, 10, 11, 12
DA_ON, DA_FH, DA_XH = 13, 14, 15
BW_ON, BW_FY, BW_XY, BW_N, BW_R = 16, 17, 18, 19, 20
PL_ON, PL_H = 21, 22
DB_ON, DB_KD, DB_G, DB_P, DB_XC = 23, 24, 25, 26, 27
HA_ON, HA_K3, HA_K2, HA_XM = 28, 29, 30, 31
MX_ON, MX_KM, MX_TAU = 32, 33, 34
CH_ON, CH_KS, CH_CS, CH_MS, CH_FC, CH_FS, CH_VS, CH_VE = 35, 36, 37, 38, 39, 40, 41, 42
I_ZF, I_ZH, I_ZB, I_W, I_Q, I_YS = 43, 44, 45, 46, 47, 48
MASS, LINEAR = 49, 50
N_P = 51


@dataclass
class Device:
    """One device: base, viscous damping, effects and outside mechanisms (parameters in the spec's units).

    Parameters
    ----------
    base : str
        ``chain`` or ``linear``.
    chain : ChainSpec, optional
        The chain of a chain base.
    chain_kw : dict
        The true chain's :class:`~chainid.model.base.ChainModel` parameters (``ea_scale``, ``hertz_scale``,
        ``contact_exponent``, ``slack``).
    k, x_ref : float
        Linear spring [N/mm] and its zero-force elongation [mm] (linear base).
    m : float
        Moving mass [kg] (a chain base: the links' mass when None).
    c : float
        Viscous damping [N·s/mm] >= 0.
    effects, outside : dict
        Library effects / outside mechanisms by name, each a dict of parameters (module docstring).
    """

    base: str
    chain: Any = None
    chain_kw: dict[str, float] = field(default_factory=dict)
    k: float = 0.0
    x_ref: float = 0.0
    m: float | None = None
    c: float = 0.0
    effects: dict[str, dict[str, float]] = field(default_factory=dict)
    outside: dict[str, dict[str, float]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.base not in ("chain", "linear"):
            raise ValueError(f"Device.base = {self.base!r} is invalid; valid: chain, linear")
        if not (math.isfinite(self.c) and self.c >= 0):
            raise ValueError(f"Device.c = {self.c!r} N·s/mm is invalid; valid range >= 0")
        self.model = None
        if self.base == "chain":
            from chainid.model.base import ChainModel

            self.model = ChainModel(self.chain, **self.chain_kw)
            if self.m is None:
                self.m = self.model.mass_kg
        self.m = float(self.m or 0.0)
        self.P = self._params()

    def spring(self, u: np.ndarray) -> np.ndarray:
        """F_spring(u) [N] at the spring's elongation u [mm] (vectorised)."""
        if self.model is not None:
            return np.asarray(self.model.force(u), dtype=float)
        return self.k * (np.asarray(u, dtype=float) - self.x_ref)

    @property
    def n_states(self) -> int:
        """Internal states (the chatter slider has two)."""
        return sum(n in self.effects or n in self.outside for n in STATE_EFFECTS) + ("chatter" in self.outside)

    def _check(self) -> None:
        """Refuse parameters the ODEs cannot run with, naming the effect, the field, the value and the range."""
        rules = {"stribeck": {"F_c": (0, None), "v_s": (0, None, True), "v_e": (0, None, True)},
                 "hysteresis": {"F_h": (0, None), "x_h": (0, None, True)},
                 "bouc_wen": {"F_y": (0, None), "x_y": (0, None, True), "n": (0.5, 8), "r": (0, 1)},
                 "backlash": {"b": (0, None, True)}, "deadband": {"k_d": (0, None), "g": (0, None), "p": (1, 4)},
                 "fixture_mass": {"m_f": (0, None)}, "relaxation": {"k_m": (0, None), "tau_m": (0, None, True)},
                 "chatter": {"k_s": (0, None, True), "m_s": (0, None, True), "c_s": (0, None), "F_c": (0, None),
                             "v_s": (0, None, True), "v_e": (0, None, True)}}
        for name, p in {**self.effects, **self.outside}.items():
            for key, (lo, hi, *strict) in rules.get(name, {}).items():
                v = p.get(key)
                ok = v is not None and math.isfinite(v) and (v > lo if strict else v >= lo) and (hi is None or v <= hi)
                if not ok:
                    rng = f"{'>' if strict else '>='} {lo:g}" + (f" and <= {hi:g}" if hi is not None else "")
                    raise ValueError(f"{name}.{key} = {v!r} is out of range; valid range {rng}")
        if "stribeck" in self.effects and self.effects["stribeck"]["F_s"] < self.effects["stribeck"]["F_c"]:
            raise ValueError(f"stribeck.F_s = {self.effects['stribeck']['F_s']!r} is out of range; valid range "
                             f">= F_c = {self.effects['stribeck']['F_c']!r} N (static above kinetic)")

    def _params(self) -> np.ndarray:
        self._check()
        P = np.zeros(N_P)
        P[K], P[XREF], P[C], P[LINEAR] = self.k, self.x_ref, self.c, float(self.base == "linear")
        e, o = self.effects, self.outside
        P[MASS] = self.m + e.get("fixture_mass", {}).get("m_f", 0.0)
        idx = 0
        for name, slot in zip(STATE_EFFECTS, (I_ZF, I_ZH, I_ZB, I_W, I_Q, I_YS)):
            if name in e or name in o:
                P[slot] = idx
                idx += 2 if name == "chatter" else 1
            else:
                P[slot] = -1
        if "friction" in e:
            p = e["friction"]
            Fc, dF, xs = p["F_c"], p.get("dF", 0.0), p["x_s"]
            if not (Fc > 0 and xs > 0 and abs(dF) < Fc):
                raise ValueError(f"friction {p}: valid F_c > 0 N, x_s > 0 mm (the ODE world's stick), |dF| < F_c")
            P[[FR_ON, FR_KT, FR_FP, FR_FM]] = 1, Fc / xs, Fc + dF, Fc - dF
        if "stribeck" in e:
            p = e["stribeck"]
            P[[ST_ON, ST_FC, ST_FS, ST_DF, ST_VS, ST_VE]] = 1, p["F_c"], p["F_s"], p.get("dF", 0.0), p["v_s"], p["v_e"]
        if "hysteresis" in e:
            P[[DA_ON, DA_FH, DA_XH]] = 1, e["hysteresis"]["F_h"], e["hysteresis"]["x_h"]
        if "bouc_wen" in e:
            p = e["bouc_wen"]
            P[[BW_ON, BW_FY, BW_XY, BW_N, BW_R]] = 1, p["F_y"], p["x_y"], p["n"], p["r"]
        if "backlash" in e:
            P[[PL_ON, PL_H]] = 1, 0.5 * e["backlash"]["b"]
        if "deadband" in e:
            p = e["deadband"]
            P[[DB_ON, DB_KD, DB_G, DB_P, DB_XC]] = 1, p["k_d"], p["g"], p["p"], p["x_c"]
        if "hardening" in e:
            p = e["hardening"]
            P[[HA_ON, HA_K3, HA_K2, HA_XM]] = 1, p["k3"], p.get("k2", 0.0), p["x_m"]
        if "relaxation" in o:
            P[[MX_ON, MX_KM, MX_TAU]] = 1, o["relaxation"]["k_m"], o["relaxation"]["tau_m"]
        if "chatter" in o:
            p = o["chatter"]
            P[[CH_ON, CH_KS, CH_CS, CH_MS, CH_FC, CH_FS, CH_VS, CH_VE]] = (1, p["k_s"], p["c_s"], p["m_s"], p["F_c"],
                                                                           p["F_s"], p["v_s"], p["v_e"])
        return P

    def initial_states(self, x_start: float) -> np.ndarray:
        """Relaxed states at rest at x_start [mm]: z = 0, the play centred, q = 0, the slider unloaded."""
        s = np.zeros(self.n_states)
        if self.P[I_YS] >= 0:
            s[int(self.P[I_YS])] = x_start
        return s


@njit(cache=True)
def _hermite(t: float, t0: float, h: float, y: np.ndarray, yd: np.ndarray) -> float:  # pragma: no cover - numba
    """Cubic Hermite interpolant of (y, ẏ) on the uniform grid t0 + i·h at t (clamped at the ends)."""
    u = (t - t0) / h
    i = int(math.floor(u))
    if i < 0:
        return y[0]
    if i >= y.size - 1:
        return y[y.size - 1]
    s = u - i
    s2, s3 = s * s, s * s * s
    return ((2 * s3 - 3 * s2 + 1) * y[i] + (s3 - 2 * s2 + s) * h * yd[i] + (-2 * s3 + 3 * s2) * y[i + 1]
            + (s3 - s2) * h * yd[i + 1])


@njit(cache=True)
def _friction_law(v: float, Fc: float, Fs: float, vs: float, ve: float) -> float:  # pragma: no cover - numba
    return math.tanh(v / ve) * (Fc + (Fs - Fc) * math.exp(-(v / vs) ** 2))


@njit(cache=True)
def _rates(x: float, v: float, s: np.ndarray, off: int, P: np.ndarray, out: np.ndarray) -> None:  # pragma: no cover
    """Time derivatives of the effect states s[off:] at (x [mm], ẋ [mm/s]) into out[off:]."""
    if P[FR_ON] > 0:
        i = off + int(P[I_ZF])
        z = s[i]
        r = 1.0
        if v * z > 0:
            r = 1.0 - (abs(z) / (P[FR_FP] if v > 0 else P[FR_FM])) ** N_SLIP
        out[i] = P[FR_KT] * v * r
    if P[DA_ON] > 0:
        i = off + int(P[I_ZH])
        out[i] = (v - abs(v) * s[i]) / P[DA_XH]
    if P[BW_ON] > 0:
        i = off + int(P[I_ZB])
        z = s[i]
        zn = abs(z) ** P[BW_N]
        sg = 1.0 if z > 0 else (-1.0 if z < 0 else 0.0)
        out[i] = (v - P[BW_R] * abs(v) * sg * zn - (1.0 - P[BW_R]) * v * zn) / P[BW_XY]
    if P[PL_ON] > 0:
        i = off + int(P[I_W])
        w = s[i]
        r = 1.0
        if v * w > 0:
            r = 1.0 - abs(w) ** N_SLIP
        out[i] = v / P[PL_H] * r
    if P[MX_ON] > 0:
        i = off + int(P[I_Q])
        out[i] = P[MX_KM] * v - s[i] / P[MX_TAU]
    if P[CH_ON] > 0:
        i = off + int(P[I_YS])
        ys, vs = s[i], s[i + 1]
        Ft = P[CH_KS] * (x - ys) + P[CH_CS] * (v - vs)
        out[i] = vs
        out[i + 1] = (Ft - _friction_law(vs, P[CH_FC], P[CH_FS], P[CH_VS], P[CH_VE])) / (P[CH_MS] * 1e-3)


@njit(cache=True)
def _internal(x: float, v: float, s: np.ndarray, off: int, P: np.ndarray) -> float:  # pragma: no cover - numba
    """The force of damping, effects and outside mechanisms [N] (no spring, no inertia)."""
    F = P[C] * v
    if P[FR_ON] > 0:
        F += s[off + int(P[I_ZF])]
    if P[ST_ON] > 0:
        th = math.tanh(v / P[ST_VE])
        F += _friction_law(v, P[ST_FC], P[ST_FS], P[ST_VS], P[ST_VE]) + P[ST_DF] * abs(th)
    if P[DA_ON] > 0:
        F += P[DA_FH] * s[off + int(P[I_ZH])]
    if P[BW_ON] > 0:
        F += P[BW_FY] * s[off + int(P[I_ZB])]
    if P[DB_ON] > 0:
        u = x - P[DB_XC]
        d = abs(u) - P[DB_G]
        if d > 0:
            F += P[DB_KD] * (1.0 if u > 0 else -1.0) * d ** P[DB_P]
    if P[HA_ON] > 0:
        u = x - P[HA_XM]
        F += P[HA_K3] * u * u * u + P[HA_K2] * u * u
    if P[MX_ON] > 0:
        F += s[off + int(P[I_Q])]
    if P[CH_ON] > 0:
        i = off + int(P[I_YS])
        F += P[CH_KS] * (x - s[i]) + P[CH_CS] * (v - s[i + 1])
    return F


@njit(cache=True)
def _spring_input(x: float, s: np.ndarray, off: int, P: np.ndarray) -> float:  # pragma: no cover - numba
    """The spring's elongation u [mm]: x, or the play output x − h·w."""
    if P[PL_ON] > 0:
        return x - P[PL_H] * s[off + int(P[I_W])]
    return x


@njit(cache=True)
def _rhs_displacement(s: np.ndarray, t: float, t0: float, h: float, x: np.ndarray, v: np.ndarray,
                      a: np.ndarray, P: np.ndarray) -> np.ndarray:  # pragma: no cover - numba
    out = np.zeros(s.size)
    _rates(_hermite(t, t0, h, x, v), _hermite(t, t0, h, v, a), s, 0, P, out)
    return out


@njit(cache=True)
def _rhs_force(s: np.ndarray, t: float, t0: float, h: float, Fd: np.ndarray, Fdd: np.ndarray,
               P: np.ndarray) -> np.ndarray:  # pragma: no cover - numba
    out = np.zeros(s.size)
    x, v = s[0], s[1]
    u = _spring_input(x, s, 2, P)
    Fint = P[K] * (u - P[XREF]) + _internal(x, v, s, 2, P)
    out[0] = v
    out[1] = (_hermite(t, t0, h, Fd, Fdd) - Fint) / (P[MASS] * 1e-3)
    _rates(x, v, s, 2, P, out)
    return out


@njit(cache=True)
def _forces(x: np.ndarray, v: np.ndarray, S: np.ndarray, off: int, P: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Internal force (no spring, no inertia) [N] and spring input u [mm] at every point."""  # pragma: no cover
    F = np.empty(x.size)
    u = np.empty(x.size)
    for j in range(x.size):
        F[j] = _internal(x[j], v[j], S[j], off, P)
        u[j] = _spring_input(x[j], S[j], off, P)
    return F, u


@dataclass(frozen=True)
class Trace:
    """A device run on the fine grid: t [s], x [mm], ẋ [mm/s], ẍ [mm/s²], F [N] and the states."""

    t: np.ndarray
    x: np.ndarray
    v: np.ndarray
    a: np.ndarray
    F: np.ndarray
    states: np.ndarray


def _atol(dev: Device, F_scale: float, x_scale: float) -> np.ndarray:
    """Absolute tolerances per state: 1e-7 of the force scale for forces, 1e-8 for z and w, 1e-9 of x for y_s."""
    tol = np.full(dev.n_states, 1e-8)
    P = dev.P
    for slot, val in ((I_ZF, 1e-7 * F_scale), (I_Q, 1e-7 * F_scale), (I_YS, 1e-9 * x_scale)):
        if P[slot] >= 0:
            tol[int(P[slot])] = val
    if P[I_YS] >= 0:
        tol[int(P[I_YS]) + 1] = 1e-9 * x_scale * 1e3
    return tol


def _solve(rhs: Any, s0: np.ndarray, t: np.ndarray, args: tuple, atol: np.ndarray, hmax: float) -> np.ndarray:
    """LSODA on the grid t − t[0] (the fine grid starts before the record, at t < 0, and LSODA's interpolation test
    misjudges its last step at negative times); ``args`` start with the grid's origin, which becomes 0."""
    S, info = odeint(rhs, s0, t - t[0], args=(0.0,) + tuple(args[1:]), rtol=1e-8, atol=atol, hmax=hmax, mxstep=200_000, full_output=True)
    if info["message"] != "Integration successful.":
        raise RuntimeError(f"the ODE world's LSODA integration failed: {info['message']}")
    return S


def run_displacement(dev: Device, t: np.ndarray, x: np.ndarray, v: np.ndarray, a: np.ndarray,
                     hmax: float) -> Trace:
    """The device under a prescribed displacement x(t) [mm] (with ẋ [mm/s], ẍ [mm/s²]) on the uniform fine grid t
    [s]; the states start relaxed at x[0]; LSODA steps are at most ``hmax`` [s]."""
    h = float(t[1] - t[0])
    if dev.n_states:
        atol = _atol(dev, 1.0 + float(np.ptp(dev.spring(x))), 1.0 + float(np.ptp(x)))
        S = _solve(_rhs_displacement, dev.initial_states(float(x[0])), t, (float(t[0]), h, x, v, a, dev.P), atol,
                   hmax)
    else:
        S = np.zeros((t.size, 0))
    Fi, u = _forces(x, v, S, 0, dev.P)
    F = dev.P[MASS] * a * 1e-3 + dev.spring(u) + Fi
    return Trace(t, x, v, a, F, S)


def equilibrium(dev: Device, F: float) -> float:
    """Static elongation x [mm] of a linear-base device at rest under force F [N] (states relaxed)."""
    s = dev.initial_states(0.0)

    def g(xx: float) -> float:
        return dev.k * (xx - dev.x_ref) + _internal(xx, 0.0, s, 0, dev.P) - F
    lo, hi = dev.x_ref - 1.0, dev.x_ref + 1.0
    while g(lo) > 0:
        lo = dev.x_ref - 2 * (dev.x_ref - lo)
    while g(hi) < 0:
        hi = dev.x_ref + 2 * (hi - dev.x_ref)
    return float(brentq(g, lo, hi, xtol=1e-13))


def run_force(dev: Device, t: np.ndarray, Fd: np.ndarray, Fdd: np.ndarray, hmax: float) -> Trace:
    """A linear-base device under a prescribed force F(t) [N] (with Ḟ [N/s]) on the uniform fine grid t [s],
    starting at rest in static equilibrium under F[0]; F of the trace is the drive force (what the load cell
    between drive and device reads)."""
    if dev.base != "linear" or dev.P[MASS] <= 0:
        raise ValueError(f"run_force needs a linear base with a moving mass > 0 kg (got base {dev.base!r}, "
                         f"mass {dev.P[MASS]:g} kg)")
    if dev.P[CH_ON] > 0:
        raise ValueError("run_force: the chatter slider is a displacement-driven mechanism")
    h = float(t[1] - t[0])
    x0 = equilibrium(dev, float(Fd[0]))
    s0 = np.concatenate([[x0, 0.0], dev.initial_states(x0)])
    xs = 1.0 + abs(x0)
    atol = np.concatenate([[1e-10 * xs, 1e-8 * xs], _atol(dev, 1.0 + float(np.ptp(Fd)), xs)])
    S = _solve(_rhs_force, s0, t, (float(t[0]), h, Fd, Fdd, dev.P), atol, hmax)
    x, v, St = S[:, 0].copy(), S[:, 1].copy(), S[:, 2:]
    Fi, u = _forces(x, v, np.ascontiguousarray(St), 0, dev.P)
    a = (Fd - dev.spring(u) - Fi) / (dev.P[MASS] * 1e-3)
    return Trace(t, x, v, a, Fd.copy(), St)
