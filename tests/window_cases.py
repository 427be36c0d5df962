"""A steady harmonic record whose identification window is set on sample times exactly, for the tests that pin
the half-open window [t_start, t_end) (a sample exactly on t_end is not used).

A 2 Hz sine of 0.4 mm about 2 mm, 64 samples per period, 10 periods and one sample (t[640] = 5 s); the window is
t_start = t[I0] = t[128], t_end = t[I1] = t[384]: four whole cycles.  Units: s, mm, N.
"""
from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from chainid.records.record import Record

F_HZ, X0, AMP = 2.0, 2.0, 0.4
W = 2 * math.pi * F_HZ
SPC = 64
DT = 1.0 / (F_HZ * SPC)
I0, I1 = 2 * SPC, 6 * SPC
#: the linear spring with a dashpot of :func:`spring_record`: F = K·(x − XR) + C·ẋ
K, XR, C = 300.0, 0.1, 5.0


def sine() -> tuple[np.ndarray, np.ndarray]:
    """t [s] and x [mm] of the record: x = X0 + AMP·sin(W·t)."""
    t = np.arange(10 * SPC + 1) / (F_HZ * SPC)
    return t, X0 + AMP * np.sin(W * t)


def on_samples(window: Any, t: np.ndarray) -> Any:
    """``window`` (a steady window) moved onto the samples: t_start = t[I0], t_end = t[I1], its cycles those four."""
    return dataclasses.replace(window, t_start=float(t[I0]), t_end=float(t[I1]),
                               cycles_kept=list(range((I1 - I0) // SPC)))


def spring_record(spike_at: int | None = None) -> Record:
    """The record ``h`` of a linear spring with a dashpot on :func:`sine`'s motion, with 10⁶ N added to the force
    sample ``spike_at`` (None: no spike)."""
    t, x = sine()
    F = K * (x - XR) + C * AMP * W * np.cos(W * t)
    if spike_at is not None:
        F[spike_at] += 1e6
    return Record("h", t, x, F)
