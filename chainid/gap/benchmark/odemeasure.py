"""Measurement of an ODE-world run (:mod:`chainid.gap.benchmark.odeworld`): from the fine-grid trace to a record.

What a data logger adds, in this order (units s, mm, N):

1. a channel lag τ (``sensor_delay``): τ > 0 the force channel lags, F_meas(t) = F(t − τ); τ < 0 the
   displacement channel lags, x_meas(t) = x(t − |τ|) — the lagged channel is read from a cubic spline through the
   fine grid (the pre-roll holds the times before the record; before the grid the channel holds its first value);
2. a drift of the force channel (outside the library): F += d0 + d1·t;
3. a constant zero offset of the force channel per record (a nuisance the linear base carries as one force offset
   per test);
4. white Gaussian noise, σ_F on the force and σ_x on the displacement;
5. ADC quantisation of the force to steps of q_F (round to the nearest step).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicSpline

from chainid.gap.benchmark.odedevice import Trace
from chainid.gap.benchmark.odeshapes import Shape
from chainid.records.record import Record

__all__ = ["Logger", "measure", "lagged"]


@dataclass(frozen=True)
class Logger:
    """What the logger adds to one record (module docstring).

    Attributes
    ----------
    tau : float
        Channel lag [s] (> 0 force lags, < 0 displacement lags).
    sigma_F, sigma_x : float
        Noise standard deviations [N], [mm] (>= 0).
    q_F : float
        ADC step of the force [N] (0: none).
    offset_F : float
        Zero offset of the force channel [N].
    drift : tuple of float
        (d0 [N], d1 [N/s]) of a force drift d0 + d1·t (outside the library).
    """

    tau: float = 0.0
    sigma_F: float = 0.0
    sigma_x: float = 0.0
    q_F: float = 0.0
    offset_F: float = 0.0
    drift: tuple[float, float] = (0.0, 0.0)

    def __post_init__(self) -> None:
        for name in ("sigma_F", "sigma_x", "q_F"):
            v = getattr(self, name)
            if not (np.isfinite(v) and v >= 0):
                raise ValueError(f"Logger.{name} = {v!r} is invalid; valid range >= 0")


def lagged(t_fine: np.ndarray, y_fine: np.ndarray, t: np.ndarray, lag: float) -> np.ndarray:
    """y(t − lag) from a cubic spline through the fine grid, held at its end values outside it [y's unit]."""
    if lag == 0.0:
        return np.interp(t, t_fine, y_fine)
    return CubicSpline(t_fine, y_fine)(np.clip(t - lag, t_fine[0], t_fine[-1]))  # the spline passes its knots


def measure(test: str, shape: Shape, tr: Trace, log: Logger, rng: np.random.Generator) -> Record:
    """The record ``test`` (t from 0 at the shape's sampling rate) of the trace as the logger reads it."""
    idx = shape.record_index
    t = tr.t[idx]
    x = tr.x[idx] if log.tau >= 0 else lagged(tr.t, tr.x, t, -log.tau)
    F = lagged(tr.t, tr.F, t, log.tau) if log.tau > 0 else tr.F[idx].copy()
    F = F + log.drift[0] + log.drift[1] * t + log.offset_F
    F = F + rng.normal(0.0, log.sigma_F, t.size) if log.sigma_F > 0 else F
    x = x + rng.normal(0.0, log.sigma_x, t.size) if log.sigma_x > 0 else x
    if log.q_F > 0:
        F = log.q_F * np.round(F / log.q_F)
    return Record(test, t, x, F)
