"""The discretisation bias of the time route's estimates, by Richardson extrapolation in the sampling interval.

A parameter fitted on sampled records can be biased by the sampling itself: the kinematics are filtered and
differenced estimates, and a memory operator or a switch is evaluated at the samples.  Resampling whole tests and
blocks cannot see that bias (every resample has the same sampling), so a percentile interval of a well-identified
parameter can be narrower than it.

The records are decimated by 2 (every other sample: the sampling interval Δt doubled) and every step of the chain
refitted from its estimates (shapes polished, amplitudes exact).  For a bias of order p in Δt,
bias(Δt) ≈ (θ(2Δt) − θ(Δt)) / (2^p − 1); p = :data:`ORDER` = 2, the order of central differences.  Checked on a
closed form (θ₀ + b·Δt²: the shift is b·Δt²) and on Coulomb friction of the linear device (noise-free records,
200 Hz, band 0.5–4 Hz), where the force sampled at instants is now fitted at instants and no bias is left to remove:
|F_c error| <= 0.0004 % at Δt, and the shift is as small (tests/gap/timedomain/test_discretisation_bias.py).  (While
samples within a third of a step of a reversal were given the stick force 0, F_c was 0.08–0.12 % low; that was
the model's error, not the sampling's.)

The shift θ(Δt) − bias is reported, and the 90 % interval is widened to take in the interval shifted by it
(:func:`chainid.gap.core.resample.widen`): a bias smaller than the resampling spread changes nothing.

Decimation needs the records sampled well above their band: it is skipped (no shift, the reason said) when a
decimated record would have fewer than :data:`MIN_PER_PERIOD` samples per period of its band's top, or too few
samples for the route.

Units: each parameter's own.
"""

from __future__ import annotations

import dataclasses
from typing import Any, Sequence

import numpy as np

__all__ = ["ORDER", "MIN_PER_PERIOD", "METHOD", "decimated", "refit_shifts", "richardson_shifts"]

#: the assumed order of the discretisation bias in Δt
ORDER = 2
#: the fewest samples per period of a record's band top after decimation
MIN_PER_PERIOD = 8
#: how the bias is estimated (``stability.discretisation.method`` of a result)
METHOD = f"Richardson extrapolation in the sampling interval (records decimated by 2), bias order {ORDER}"


def decimated(records: Sequence[Any], q: int = 2) -> list[Any]:
    """Every record with every ``q``-th sample kept (t, x, F and its channels; its covariates as they are)."""
    return [dataclasses.replace(r, t=r.t[::q], x=r.x[::q], F=r.F[::q], estimate=None,
                                channels={k: v[::q] for k, v in r.channels.items()}) for r in records]


def too_coarse(prob: Any, q: int = 2) -> str | None:
    """Why the records of ``prob`` cannot be decimated by ``q`` (None: they can)."""
    for d in prob.tdata:
        per = d.fs / (q * max(d.f_band, 1e-300))
        if per < MIN_PER_PERIOD:
            return (f"test {d.test}: {per:.3g} samples per period of its band top ({d.f_band:.3g} Hz) after "
                    f"decimating by {q}; at least {MIN_PER_PERIOD} are needed")
    return None


def refit_shifts(prob: Any, steps: Sequence[Any]) -> list[dict[str, float]]:
    """Per step of the chain, how far each parameter moves when the step is refitted on ``prob`` from its estimates
    (shapes polished, amplitudes exact): θ_refit − θ [its unit], for the parameters finite in both."""
    out = []
    for c in steps:
        th = prob.fit(c.names, start=c.params, polish_only=True).params
        out.append({k: float(th[k]) - float(v) for k, v in c.params.items()
                    if k in th and np.isfinite(th[k]) and np.isfinite(v)})
    return out


def richardson_shifts(records: Sequence[Any], prob: Any, steps: Sequence[Any], build: Any
                      ) -> tuple[list[dict[str, float]], str | None]:
    """Per step of the chain, the estimated discretisation bias of every parameter.

    Parameters
    ----------
    records : the records the diagnosis ran on (Record: t s, x mm, F N)
    prob : the time problem built on them (its ``tdata`` give each record's sampling rate and band)
    steps : the chain's candidates (baseline first), each with ``names`` and ``params``
    build : ``build(records) -> problem``, the route's problem builder with the diagnosis' split and base

    Returns
    -------
    (shifts, reason)
        ``shifts[k][param]`` = (θ(2Δt) − θ(Δt))/(2^ORDER − 1), the bias of step k's parameter [its unit];
        ``reason``: why nothing was estimated (too coarse a sampling, a failed refit), else None.
    """
    why = too_coarse(prob)
    if why is not None:
        return [{} for _ in steps], why
    try:
        moved = refit_shifts(build(decimated(records)), steps)
        out = [{k: d / (2 ** ORDER - 1) for k, d in sh.items()} for sh in moved]
    except (ValueError, np.linalg.LinAlgError) as exc:
        return [{} for _ in steps], f"the decimated records could not be refitted ({exc})"
    return out, None
