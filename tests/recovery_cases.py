"""Simulated data sets with a known truth for the recovery tests of the diagnosis (built on :mod:`sim_devices`).

Each builder returns ``(records, holdout, model, truth)``: the noisy records, the held-out test ids, the base
model to give ``diagnose`` (None: a linear device, fitted blind; ``ChainModel()``: the chain), and the true
parameters under the diagnosis' names (``effect.param``).

Devices (units mm, N, s, kg):

* linear device: F = k·x + c·ẋ + m·ẍ·1e-3 + effect + a preload per record, k = 10 N/mm, c = 0.2 N·s/mm, m = 0;
  random motion 0.2–4 Hz, RMS 1 mm, 200 Hz, 4 000 samples; noise σ_x = 1 µm, σ_F = 0.1 N;
* chain: F = F_k(x) (``ChainModel().force``) + m_chain·ẍ·1e-3 + c·ẋ + effect, c = 30 N·s/mm, x about 2 mm with
  RMS 0.15 mm (peaks near ±0.3 mm), 0.3–4 Hz; noise σ_x = 0.2 µm, σ_F = 5 N;
* harmonic sets: steady sines at 6 (f, A) pairs, 8 cycles each, 64 samples per cycle (the harmonic route).
"""
from __future__ import annotations

import math
from typing import Callable

import numpy as np

import sim_devices as sd

#: the linear device
K_LIN, C_LIN = 10.0, 0.2
FS_LIN, N_LIN, BAND_LIN, RMS_LIN = 200.0, 4000, (0.2, 4.0), 1.0
SX_LIN, SF_LIN = 1e-3, 0.1
#: the chain
C_CHAIN, X0_CHAIN, RMS_CHAIN, BAND_CHAIN = 30.0, 2.0, 0.15, (0.3, 4.0)
FS_CHAIN, N_CHAIN = 200.0, 4000
SX_CHAIN, SF_CHAIN = 2e-4, 5.0
#: the (frequency [Hz], amplitude [mm]) pairs of a harmonic set
HARMONIC_PAIRS = ((0.5, 0.6), (0.5, 1.2), (1.0, 0.9), (1.0, 1.5), (2.0, 0.6), (2.0, 1.2))


def _preload(i: int) -> float:
    return 3.0 * i - 5.0  # a different force offset per record [N] (per-test nuisance of a linear base)


def linear_random(extra: Callable[[sd.MotionFn, np.ndarray], np.ndarray] | None = None, n_rec: int = 5,
                  seed: int = 0, k: float = K_LIN, c: float = C_LIN, m: float = 0.0, rms: float = RMS_LIN,
                  band: tuple[float, float] = BAND_LIN, fs: float = FS_LIN, n: int = N_LIN,
                  sigma_x: float = SX_LIN, sigma_F: float = SF_LIN, delay: float = 0.0,
                  covariates: list[dict] | None = None, rest: float = 0.0) -> list:
    """Records of the linear device under random motion; ``extra(motion, t)`` the effect's force [N] (it may use
    the exact motion); ``delay`` [s]: the force channel lags the displacement (F_meas(t) = F(t − delay));
    ``rest`` [s] > 0: the device rests at 0 for that long, then the motion fades in over as long again."""
    t = sd.sample_times(n, fs)
    recs = []
    for i, mo in enumerate(sd.random_motions(n_rec, n, fs, band[0], band[1], rms, 0.0, seed)):
        if rest > 0:
            mo = sd.onset(mo, rest, rest)
        te = t - delay
        x, xd, xdd = mo(te)
        F = k * x + c * xd + m * xdd * 1e-3 + _preload(i)
        if extra is not None:
            F = F + extra(mo, te)
        xm = mo(t)[0]
        recs.append(sd.noisy(f"r{i}", t, xm, F, sigma_x, sigma_F, seed * 100 + i,
                             covariates[i] if covariates else None))
    return recs


def chain_random(extra: Callable[[sd.MotionFn, np.ndarray], np.ndarray] | None = None, n_rec: int = 5,
                 seed: int = 0, c: float = C_CHAIN, extra_mass: float = 0.0, band: tuple[float, float] = BAND_CHAIN,
                 rms: float = RMS_CHAIN, fs: float = FS_CHAIN, n: int = N_CHAIN) -> tuple[list, object]:
    """Records of the built-in chain under random motion about 2 mm (``extra_mass`` [kg] moves with it)."""
    from chainid.model import ChainModel

    model = ChainModel()
    t = sd.sample_times(n, fs)
    recs = []
    for i, mo in enumerate(sd.random_motions(n_rec, n, fs, band[0], band[1], rms, X0_CHAIN, seed)):
        x, xd, xdd = mo(t)
        F = np.asarray(model.force(x), float) + (model.mass_kg + extra_mass) * xdd * 1e-3 + c * xd
        if extra is not None:
            F = F + extra(mo, t)
        recs.append(sd.noisy(f"r{i}", t, x, F, SX_CHAIN, SF_CHAIN, seed * 100 + i))
    return recs, model


def harmonic_set(force: Callable[[sd.MotionFn, np.ndarray, float, float], np.ndarray], pairs=HARMONIC_PAIRS,
                 cycles: int = 8, per_cycle: int = 64, sigma_x: float = SX_LIN, sigma_F: float = SF_LIN,
                 x0: float = 0.0, seed: int = 0) -> list:
    """Steady sine tests: ``force(motion, t, f, A)`` the device's force [N] on x = x0 + A·sin(2πft)."""
    recs = []
    for i, (f, A) in enumerate(pairs):
        fs = per_cycle * f
        t = sd.sample_times(cycles * per_cycle, fs)
        mo = sd.sine(f, A, x0)
        recs.append(sd.noisy(f"h{i}", t, mo(t)[0], force(mo, t, f, A), sigma_x, sigma_F, seed * 100 + i))
    return recs


def hysteresis_force(F_y: float, x_y: float, n: float, r: float, over: int = 8
                     ) -> Callable[[sd.MotionFn, np.ndarray], np.ndarray]:
    """The Bouc–Wen force F_y·z along the exact motion (z from 0 at the first sample)."""

    def fn(mo: sd.MotionFn, t: np.ndarray) -> np.ndarray:
        _, xf, _ = sd.fine_path(mo, t, over)
        return F_y * sd.bouc_wen_z(xf, x_y, n, r)[::over]

    return fn


def band_centre(mo_freqs: np.ndarray, amps: np.ndarray) -> float:
    """The power-weighted mean angular frequency [rad/s] of a sum of sines (the band centre ω_c)."""
    return float(2 * math.pi * np.sum(amps**2 * mo_freqs) / np.sum(amps**2))


# ---------------------------------------------------------------------------------------------------- diagnoses
_RUNS: dict = {}


def diagnosed(key: str, build: Callable[[], tuple], **kw) -> tuple[dict, list, object]:
    """``diagnose`` of the data set ``build()`` → (records, holdout, model), run once per session per key: the
    result, the records and the model."""
    if key not in _RUNS:
        import warnings

        from chainid.gap.diagnose import diagnose

        recs, hold, model = build()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            _RUNS[key] = (diagnose(recs, hold, model, quiet=True, **kw), recs, model)
    return _RUNS[key]


def final_params(res: dict) -> dict:
    """The parameters of the last trusted step of the chain (the steps before the first one that raised the held-out
    error), with its base (``_base``) and mass (``_mass_kg``)."""
    steps = res["steps"]
    k = next((i - 1 for i in range(1, len(steps)) if steps[i].get("worsened_holdout")), len(steps) - 1)
    return steps[k]["params"] | {"_base": steps[k].get("base"), "_mass_kg": steps[k].get("mass_kg")}


def rel_err(got: float, truth: float) -> float:
    """|got − truth|/|truth|."""
    return abs(got - truth) / abs(truth)
