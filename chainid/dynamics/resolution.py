"""Whether a run of the lumped chain resolves its drive: the time step and the output interval [s] against the
drive's period [s] (:func:`resolution_warnings`, one of :func:`chainid.dynamics.simulation.simulate`'s checks).

Units s (mm/s and rad/s in the messages).
"""
from __future__ import annotations

import math

from chainid.dynamics.drives import Drive

__all__ = ["MIN_STEPS_PER_PERIOD", "resolution_warnings"]

#: a periodic drive needs at least this many time steps per period to be followed (the Verlet/Newmark phase
#: error per period is about (2π/N)²/12: 0.8 % at N = 20), and its output at least 2 samples per period
MIN_STEPS_PER_PERIOD = 20


def _short(count: float) -> str:
    """A count below its threshold as text, cut (not rounded) to two decimals: 19.998 reads 19.99, never 20."""
    return f"{math.floor(100.0 * count) / 100.0:.4g}"


def resolution_warnings(drive: Drive, pitch: float, dt: float, dt_out: float) -> list[str]:
    """Warnings when the drive's period (:meth:`Drive.period` [s]) is not resolved by the time step ``dt`` [s]
    (fewer than :data:`MIN_STEPS_PER_PERIOD` steps) or by the output interval ``dt_out`` [s] (fewer than 2 samples:
    the stored series alias the drive)."""
    T = drive.period(pitch)
    if not math.isfinite(T):
        return []
    what = (f"the drive ({drive.law}, ω = {drive.omega:.4g} rad/s" if drive.law == "sine"
            else f"the drive ({drive.law}, v = {drive.v:.4g} mm/s, one pitch") + f": period {T:.3g} s)"
    out = []
    if dt > T / MIN_STEPS_PER_PERIOD:
        out.append(f"{what} is not resolved by the time step dt = {dt:.3g} s ({_short(T / dt)} steps per period; "
                   f"valid >= {MIN_STEPS_PER_PERIOD}): the chain does not follow the drive and the result is "
                   f"meaningless; give dt <= {T / MIN_STEPS_PER_PERIOD:.3g} s (--dt) or a slower drive")
    elif dt_out > T / 2:
        out.append(f"{what} is sampled every {dt_out:.3g} s by the outputs ({_short(T / dt_out)} per period; valid "
                   ">= 2): the stored tension series alias the drive (the peak and the energies are computed at "
                   "every step and are not affected); use a shorter t_end for a resolved series")
    return out
