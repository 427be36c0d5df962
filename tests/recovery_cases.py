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
    ``rest`` [s] > 0: the device rests at 0 for that long at each end of the record, the motion fading in and out
    over as long again."""
    t = sd.sample_times(n, fs)
    recs = []
    for i, mo in enumerate(sd.random_motions(n_rec, n, fs, band[0], band[1], rms, 0.0, seed)):
        if rest > 0:
            mo = sd.between_rests(mo, rest, n / fs - rest, rest)
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
                 x0: float = 0.0, seed: int = 0, phase: float = 0.0) -> list:
    """Steady sine tests: ``force(motion, t, f, A)`` the device's force [N] on x = x0 + A·sin(2πft + φ), φ = ``phase``
    [rad] (default 0: with a whole number of samples per quarter cycle, a sample on every reversal; π/per_cycle puts
    them half a step off, as a rig's clock, not locked to its actuator, does)."""
    recs = []
    for i, (f, A) in enumerate(pairs):
        fs = per_cycle * f
        t = sd.sample_times(cycles * per_cycle, fs)
        mo = sd.sine(f, A, x0, phase)
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


# ---------------------------------------------------------------------------------------------------- shared sets
def damping_dominated_set() -> tuple[list, list, None]:
    """A damping-dominated linear device F = 1·x + 2·ẋ + preload (c·ẋ about 75× the spring's dynamic force): random
    motion 0.5–10 Hz, RMS 1 mm, 1 kHz, 5 records of 5 000 samples, σ_x = 2 µm, σ_F = 0.5 N."""
    return linear_random(k=1.0, c=2.0, band=(0.5, 10.0), fs=1000.0, n=5000, sigma_x=2e-3, sigma_F=0.5), ["r4"], None


def stribeck_set() -> tuple[list, list, None]:
    """Linear device + Stribeck friction F_c = 2 N, F_s = 3.5 N, v_s = 3 mm/s on the true velocity."""
    return linear_random(lambda mo, t: sd.stribeck_force(mo(t)[1], 2.0, 1.5, 3.0)), ["r4"], None


def fixture_mass_set() -> tuple[list, list, object]:
    """The chain with a 20 kg fixture: random motion 1–20 Hz at 1 kHz, 5 records of 5 000 samples."""
    recs, model = chain_random(extra_mass=20.0, band=(1.0, 20.0), fs=1000.0, n=5000)
    return recs, ["r4"], model


#: the resonant device: m [kg], k [N/mm], c [N·s/mm] (ω_n = 100 rad/s, 15.9 Hz; damping ratio 0.05)
RES_M, RES_K, RES_C = 2.0, 20.0, 0.02


def _resonant_records(sigma_x: float, steady: bool, preload: bool) -> list:
    """Five records of the resonant device force-driven by a random multisine 2–30 Hz (RMS 5 N, seeds 50–54), 1 kHz,
    6 000 samples each, σ_x [mm] on x and σ_F = 0.05 N on F: from rest, or (``steady``) after one period of the
    force run in first, the transient gone by e^-30, each record one whole period; with a preload per record."""
    fs, n = 1000.0, 6000
    run_in = n if steady else 0
    t = sd.sample_times(n + run_in, fs)
    recs = []
    for i in range(5):
        force = sd.force_sines(n / fs, 2.0, 30.0, 5.0, seed=50 + i)
        x, _, _ = sd.resonant_response(force, t, RES_M, RES_C, RES_K)
        F = force(t[run_in:]) + (_preload(i) if preload else 0.0)
        recs.append(sd.noisy(f"r{i}", t[:n], x[run_in:], F, sigma_x, 0.05, seed=i))
    return recs


def resonant_set() -> tuple[list, list, None]:
    """The resonant device force-driven from rest, σ_x = 0.1 µm, a preload per record (:func:`_resonant_records`)."""
    return _resonant_records(1e-4, steady=False, preload=True), ["r4"], None


def resonant_noisy_x_set(sigma_x: float = 5e-3) -> tuple[list, list, None]:
    """The resonant device in steady state with a noisy displacement channel, σ_x [mm] (5 µm: m·ẍ's noise at a
    band-edge cut is about the force noise), and no preload (:func:`_resonant_records`)."""
    return _resonant_records(sigma_x, steady=True, preload=False), ["r4"], None


#: coil currents [A] of the covariate set and the friction law F_c = F0 + F1·i [N, N/A]
COV_I = (0.0, 0.25, 0.5, 0.75, 1.0)
COV_F0, COV_F1 = 1.0, 2.0


def covariate_friction_records(seed: int = 0, ids: Callable[[int, float], str] | None = None) -> list:
    """Linear device + Coulomb friction (F0 + F1·i)·sgn(ẋ) at the currents :data:`COV_I` (``Record.covariates``
    {"i": value}); ``ids(k, i)`` names the records (default r0 … r4)."""
    t = sd.sample_times(N_LIN, FS_LIN)
    recs = []
    for k, mo in enumerate(sd.random_motions(len(COV_I), N_LIN, FS_LIN, BAND_LIN[0], BAND_LIN[1], RMS_LIN, 0.0, seed)):
        x, xd, _ = mo(t)
        F = K_LIN * x + C_LIN * xd + _preload(k) + (COV_F0 + COV_F1 * COV_I[k]) * np.sign(xd)
        recs.append(sd.noisy(ids(k, COV_I[k]) if ids else f"r{k}", t, x, F, SX_LIN, SF_LIN, seed * 100 + k,
                             {"i": COV_I[k]}))
    return recs


def covariate_set() -> tuple[list, list, None]:
    """:func:`covariate_friction_records` with r2 (i = 0.5 A) held out."""
    return covariate_friction_records(), ["r2"], None


def chain_friction_delay_problem():
    """The harmonic problem of the paper's chain with friction F_c = 150 N and a sensor delay τ = 37.5 ms: nine
    tests at ω = 1, 2, 4 rad/s × A = 0.1, 0.2, 0.3 mm about 2 mm, 8 cycles of 256 samples, force noise 20 N, the
    damping law 40·(…)⁴ of the resampling tests; tests 3 and 7 held out.  Returns ``(problem, friction fitted
    alone)``."""
    from chainid.gap.harmonic.prepare import prepare_test
    from chainid.gap.harmonic.problem import Problem
    from chainid.model.base import ChainModel
    from chainid.model.effects import compose_hooks, parse_effect
    from chainid.model.laws import PolynomialLaw
    from chainid.records.simulate import grid_plan, simulate

    model = ChainModel()
    plan = grid_plan((1.0, 2.0, 4.0), (0.1, 0.2, 0.3), 2.0)
    hook = compose_hooks([parse_effect("friction:F_c=150", model), parse_effect("sensor_delay:tau=0.0375", model)])

    recs = simulate(plan, model, PolynomialLaw([0.0, 0.0, 0.0, 0.0, 40.0]), n_cycles=8, samples_per_cycle=256,
                    noise_F=20.0, seed=6, force_fn=hook)
    prob = Problem([prepare_test(r) for r in recs], model, [recs[2].test, recs[6].test], "auto")
    return prob, prob.fit(["friction"])
