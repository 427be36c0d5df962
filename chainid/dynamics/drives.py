"""Prescribed motion of the drive node: start-up ramp, sinusoid, sprocket polygon effect.

Units: t s, u mm, v mm/s, a mm/s², ω rad/s, pitch mm.

Laws
----
``"none"``     u = 0 (the drive end held; free vibration about the pre-tensioned state).
``"ramp"``     start-up to speed v over ``t_ramp`` with a cosine (finite-jerk) profile
               v(t) = v·(1 − cos(π t/t_ramp))/2 for t < t_ramp, then v; ``t_ramp = 0`` is a speed step.
``"sine"``     u = A·sin(ω t) (the paper's harmonic test, Eq. 18, about the pretension).
``"polygon"``  the ramp's mean speed, delivered by a sprocket of z teeth (the chordal or polygon effect).

Polygon effect (derivation).  A sprocket of z teeth and chain pitch p has the pitch radius
R = p / (2 sin(π/z)) (the chain wraps it as a z-sided polygon of side p).  At sprocket angle θ the engaged
link's joint sits at angle φ = θ − 2πk/z ∈ [−π/z, π/z) from the perpendicular to the strand (k = the number
of teeth passed, rounded), so the strand position is u = k·p + R·sin φ (continuous: R·sin(π/z) = p/2) and

    v = R·cos φ · θ̇,        a = R·cos φ · θ̈ − R·sin φ · θ̇².

The speed varies between R θ̇ and R θ̇ cos(π/z) (ratio 1/cos(π/z)) with the period of one pitch,
p/v̄; the mean speed over a pitch is R θ̇ · sin(π/z)/(π/z) = p z θ̇/(2π), so a prescribed mean speed v̄ gives
θ̇ = 2π v̄/(z p), i.e. v = v̄ · (π/z)/sin(π/z) · cos φ.  The acceleration jumps by 2 R θ̇² sin(π/z) when a
tooth engages (the polygon impact).  This is the classical chordal-action result for roller chains
(R. C. Binder, *Mechanics of the Roller Chain Drive*, Prentice-Hall 1956, ch. 9; ISO 10823:2004, Annex on
the polygon effect; G. Niemann, H. Winter, *Maschinenelemente* III, Springer 1983, §22).  For round link
chains on a pocket wheel with z pockets the chain wraps a polygon of 2z sides whose side is the link pitch
(horizontal and vertical links alternate), so use ``z = 2 × pockets`` (first-order model: it neglects the
different lengths of the flat and standing link chords).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

__all__ = ["Drive", "DRIVE_LAWS", "drive_state", "drive_motion"]

DRIVE_LAWS: dict[str, int] = {"none": 0, "ramp": 1, "sine": 2, "polygon": 3}


@dataclass(frozen=True)
class Drive:
    """A drive law for node 0.

    Parameters
    ----------
    law : str
        One of ``"none"``, ``"ramp"``, ``"sine"``, ``"polygon"``.
    v : float
        Target (mean) chain speed [mm/s] for ``ramp``/``polygon``, >= 0.
    t_ramp : float
        Start-up time [s], >= 0 (0: a speed step at t = 0).
    A : float
        Amplitude [mm] for ``sine``, >= 0.
    omega : float
        Circular frequency [rad/s] for ``sine``, > 0.
    z : int
        Sprocket teeth (polygon sides) for ``polygon``, >= 3.
    pitch : float, optional
        Chain pitch [mm] for ``polygon``; default the chain's pitch.
    """

    law: str = "ramp"
    v: float = 0.0
    t_ramp: float = 0.0
    A: float = 0.0
    omega: float = 1.0
    z: int = 8
    pitch: float | None = None

    def __post_init__(self) -> None:
        if self.law not in DRIVE_LAWS:
            raise ValueError(f"drive law = {self.law!r} is invalid: valid laws are {list(DRIVE_LAWS)}")
        checks = (("v", self.v, self.v >= 0, ">= 0 mm/s"), ("t_ramp", self.t_ramp, self.t_ramp >= 0, ">= 0 s"),
                  ("A", self.A, self.A >= 0, ">= 0 mm"), ("omega", self.omega, self.omega > 0, "> 0 rad/s"))
        for name, val, ok, valid in checks:
            if not (math.isfinite(val) and ok):
                raise ValueError(f"drive {name} = {val!r} is invalid: valid range {valid}")
        if int(self.z) != self.z or self.z < 3:
            raise ValueError(f"drive z = {self.z!r} is invalid: valid range an int >= 3 teeth")
        if self.pitch is not None and not (math.isfinite(self.pitch) and self.pitch > 0):
            raise ValueError(f"drive pitch = {self.pitch!r} is invalid: valid range > 0 mm")

    def params(self, pitch: float) -> tuple[int, np.ndarray]:
        """(law code, parameter vector [v, t_ramp, A, omega, z, pitch]) for the numba integrators."""
        p = self.pitch if self.pitch is not None else pitch
        return DRIVE_LAWS[self.law], np.array([self.v, self.t_ramp, self.A, self.omega, float(self.z), p])

    def max_speed(self, pitch: float) -> float:
        """Largest drive speed [mm/s]."""
        if self.law == "sine":
            return self.A * self.omega
        if self.law == "polygon":
            z = float(self.z)
            return self.v * (math.pi / z) / math.sin(math.pi / z)
        return self.v if self.law == "ramp" else 0.0

    def period(self, pitch: float) -> float:
        """Period of the drive's excitation [s]: 2π/ω of a sine with A > 0, p/v̄ of the polygon effect; inf for
        a ramp, a held end or a sine of zero amplitude (no periodic excitation)."""
        if self.law == "sine" and self.A > 0:
            return 2.0 * math.pi / self.omega
        if self.law == "polygon":
            return self.polygon_period(pitch)
        return math.inf

    def polygon_period(self, pitch: float) -> float:
        """Period of the polygon excitation p/v̄ [s] (inf when v = 0)."""
        p = self.pitch if self.pitch is not None else pitch
        return p / self.v if self.v > 0 else math.inf


@njit(cache=True)
def _ramp(t, v, tr):
    if t <= 0.0:
        return 0.0, 0.0, 0.0
    if tr <= 0.0:
        return v * t, v, 0.0
    if t < tr:
        w = math.pi / tr
        return 0.5 * v * (t - math.sin(w * t) / w), 0.5 * v * (1.0 - math.cos(w * t)), 0.5 * v * w * math.sin(w * t)
    return v * (t - 0.5 * tr), v, 0.0


@njit(cache=True)
def drive_state(t, code, p):
    """(u [mm], v [mm/s], a [mm/s²]) of the drive node at time t [s] for a law code and parameters."""
    if code == 0:
        return 0.0, 0.0, 0.0
    if code == 2:
        s, c = math.sin(p[3] * t), math.cos(p[3] * t)
        return p[2] * s, p[2] * p[3] * c, -p[2] * p[3] * p[3] * s
    ur, vr, ar = _ramp(t, p[0], p[1])
    if code == 1:
        return ur, vr, ar
    z, pitch = p[4], p[5]
    R = pitch / (2.0 * math.sin(math.pi / z))
    k_th = 2.0 * math.pi / (z * pitch)  # θ per mm of mean travel
    th, thd, thdd = k_th * ur, k_th * vr, k_th * ar
    k = math.floor(th * z / (2.0 * math.pi) + 0.5)
    phi = th - 2.0 * math.pi * k / z
    sp, cp = math.sin(phi), math.cos(phi)
    return k * pitch + R * sp, R * cp * thd, R * cp * thdd - R * sp * thd * thd


def drive_motion(drive: Drive, t: np.ndarray, pitch: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Drive displacement [mm], speed [mm/s], acceleration [mm/s²] at times t [s] (numpy arrays)."""
    code, p = drive.params(pitch)
    t = np.asarray(t, dtype=float)
    out = np.array([drive_state(float(ti), code, p) for ti in t.reshape(-1)]).reshape(t.shape + (3,))
    return out[..., 0], out[..., 1], out[..., 2]
