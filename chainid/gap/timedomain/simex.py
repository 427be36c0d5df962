"""The displacement-noise bias of the time route's estimates, by simulation–extrapolation (SIMEX).

The time route evaluates a model on kinematics made from the measured displacement.  Noise in x is noise in a
regressor, and a regressor's noise biases a fit, whatever its resampling says: the classic attenuation of a
slope (Fuller 1987, *Measurement Error Models*), and here above all the switch of a friction or a play operator,
which the noise moves, blurs or leaves at rest near a reversal (each misplaced switch costs 2·F_c).  The bias is
the same in every resample of the training blocks (each has the same noise level), so no resampling interval
sees it.

SIMEX (Cook & Stefanski 1994, *J. Am. Stat. Assoc.* 89:1314–1328; Carroll et al. 2006, *Measurement Error in
Nonlinear Models*, ch. 5) measures it by adding more of the same noise: every record gets independent white noise
of its own displacement noise σ_x (:func:`chainid.gap.core.noise.displacement_noise`) added to x, the total
variance becomes (1 + λ)·σ_x² with λ = 1, and every step of the chain is refitted from its estimates (shapes
polished, amplitudes exact) on those records, :data:`DRAWS` times with independent draws.  Extrapolating θ(λ)
linearly to the noise-free λ = −1, the bias of the estimate is θ(1) − θ(0), the mean over the draws.  The linear
extrapolant is the standard conservative choice: it under-corrects a bias that grows faster than σ_x².

What it does not hold fixed: the records with added noise go through the route's own preparation again, which
reads each record's band, and so its smoothing cut, from the record.  White noise raises the noise floor the band
is read above, so at a few per cent of displacement noise the band and the cut move up (on 5 % noise: a 4–16 Hz
band read as 40–67 Hz) and θ(1) − θ(0) also holds the change of preparation: there the shift overstates the bias
(by 64 % on one friction case) and the interval is wider than it need be, never narrower.  At the 0–0.3 % of the
benchmark's records the band does not move.  A record whose σ_x cannot be measured (not smoothed: its band reaches
the sampling, or its noise hides the band's top) gets no noise, and the reason says which.

The shift is reported, and the 90 % interval is widened to take in the interval shifted by it
(:func:`chainid.gap.core.resample.widen`), with the time sampling's bias (:mod:`.discretisation`): a bias smaller
than the resampling spread changes little.  Nothing is estimated for records with no measurable displacement
noise (σ_x = 0: noise-free or unsmoothed records).

Checked on a closed form (a straight line fitted to a regressor with noise: the attenuation σ_x²/(σ_ξ² + σ_x²)
of the slope) and on Coulomb friction with noise in x (tests/gap/timedomain/test_simex_bias.py).

Units: x mm, σ_x mm; each parameter's own.
"""

from __future__ import annotations

import dataclasses
from typing import Any, Callable, Sequence

import numpy as np

from chainid.gap.core.noise import CUT_FACTOR, displacement_noise, excitation_band, lowpass, sample_rate
from chainid.gap.timedomain.discretisation import refit_shifts

__all__ = ["DRAWS", "LAMBDA", "METHOD", "record_sigma_x", "noisier", "simex_shifts"]

#: independent draws of the added noise (their mean shift is the bias; each draw is one refit of every step)
DRAWS = 2
#: the added noise variance in units of the record's own σ_x²
LAMBDA = 1.0
#: how the bias is estimated (``stability.displacement_noise.method`` of a result)
METHOD = (f"SIMEX: each record's own displacement noise added again to x ({DRAWS} draws), every step refitted, "
          "extrapolated linearly to no noise")


def record_sigma_x(t: np.ndarray, x: np.ndarray) -> float:
    """The displacement noise σ_x [mm] of one record: what its zero-phase low-pass at ``CUT_FACTOR`` times its
    excitation band removes (:func:`chainid.gap.core.noise.displacement_noise`); 0 when it is not smoothed."""
    fs = sample_rate(t)
    f_cut = CUT_FACTOR * excitation_band(t, x)
    return displacement_noise(x, lowpass(x, fs, f_cut), fs, f_cut)


def noisier(records: Sequence[Any], sigmas: Sequence[float], rng: np.random.Generator, lam: float = LAMBDA
            ) -> list[Any]:
    """Every record with white noise of standard deviation √lam·σ_x [mm] (its own ``sigmas`` entry) added to x, the
    rest (t, F, channels, covariates) as it is."""
    return [dataclasses.replace(r, x=r.x + rng.normal(0.0, np.sqrt(lam) * s, r.x.size), estimate=None)
            for r, s in zip(records, sigmas)]


def simex_shifts(records: Sequence[Any], steps: Sequence[Any], build: Callable[[list[Any]], Any],
                 seed: int = 0) -> tuple[list[dict[str, float]], str | None]:
    """Per step of the chain, the estimated displacement-noise bias of every parameter.

    Parameters
    ----------
    records : the records the diagnosis ran on (Record: t s, x mm, F N)
    steps : the chain's candidates (baseline first), each with ``names`` and ``params``
    build : ``build(records) -> problem``, the route's problem builder with the diagnosis' split and base
    seed : seed of the added noise (the shifts are reproducible)

    Returns
    -------
    (shifts, reason)
        ``shifts[k][param]`` = mean over :data:`DRAWS` draws of θ(λ = 1) − θ(0), the bias of step k's parameter
        [its unit]; ``reason``: why nothing was estimated (no displacement noise, a failed refit), or which records
        got no noise, else None.
    """
    sigmas = [record_sigma_x(r.t, r.x) for r in records]
    if not any(s > 0.0 for s in sigmas):
        return [{} for _ in steps], "no measurable displacement noise (sigma_x = 0 in every record)"
    none = [str(r.test) for r, s in zip(records, sigmas) if not s > 0.0]
    rng = np.random.default_rng(seed)
    got: list[dict[str, list[float]]] = [{} for _ in steps]
    try:
        for _ in range(DRAWS):
            for acc, sh in zip(got, refit_shifts(build(noisier(records, sigmas, rng)), steps)):
                for k, d in sh.items():
                    acc.setdefault(k, []).append(d)
    except (ValueError, ArithmeticError, RuntimeError, np.linalg.LinAlgError) as exc:
        return [{} for _ in steps], f"the records with added displacement noise could not be refitted ({exc})"
    why = f"no measurable displacement noise in {', '.join(none)}: no noise added there" if none else None
    return [{k: float(np.mean(d)) for k, d in acc.items() if len(d) == DRAWS} for acc in got], why
