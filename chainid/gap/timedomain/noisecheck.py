"""Each time-domain record's force noise σ, read again from what a fitted chain leaves on it.

The force noise of a record is first read from its force alone (:func:`chainid.gap.timedomain.data.prepare_time`:
the robust second difference of F, 1.4826·MAD(Δ²F)/√6, or the spectrum above the excitation band, the smaller).
Both take force content for noise where the force switches often on the sample scale: a friction, a play or a
stick–slip that reverses every few samples of a record sampled a dozen times its band puts its jumps into most
second differences and its harmonics into the whole spectrum.  There σ comes out several times the noise (ten
times for a 200 N friction on the chain under random motion sampled at 200 Hz with a 15 Hz band and 5 N of noise:
tests/gap/timedomain/test_noise_check.py); every residual then looks as if it were at the noise floor, a weaker
effect fails the step rule, and the profile intervals are as many times too wide.

The same estimator on the residual of a fitted chain does not: the chain takes out the smooth force and the bulk
of the jumps, a switch it places a sample off is one outlier the median ignores, and what it misses within the
band is smooth on the sample scale.  σ_c = 1.4826·MAD(Δ²r)/√6/√s, with s the share of the noise's
second-difference power a record compared below a cut keeps (:func:`.bandlimit.difference_share`; 1 on the whole
band).  It is not the residual's size: a misfit within the band still shows as residual power over σ_c².

The residual read is the kept chain's (the baseline's when none is kept). A switching effect that the inflated σ
itself kept out of the chain leaves its jumps in that residual, so the check does not fire there; a switching force
strong enough to inflate σ is in practice far over it and is kept. Where σ_c² is under :data:`RATIO` of the power
read first (3 dB under it), the first reading is refuted: that record's σ is capped at σ_c and the diagnosis runs
once more on the capped σ (:func:`chainid.gap.timedomain.route.diagnose_any`), its comparison cut decided again on
it (:func:`chainid.gap.timedomain.bandlimit.residual_cut`). A σ read right from thousands of samples agrees with σ_c
to a few per cent (the estimator's standard error is about 1.7/√n), so the check does not fire by chance, and where
it does not fire nothing changes.

Units: σ, residuals N.
"""

from __future__ import annotations

import math
from typing import Any, Sequence

import numpy as np

from chainid.gap.core.noise import force_noise
from chainid.gap.timedomain.bandlimit import difference_share

__all__ = ["RATIO", "caps", "note", "refuting", "residual_sigma"]

#: the noise power read again from a chain's residual, as a share of the power first read from the force, under
#: which that first reading is refuted
RATIO = 0.5


def residual_sigma(r: np.ndarray, fs: float, f_res: float) -> float:
    """The force noise σ_c read from a fitted chain's residual: its robust second difference
    (:func:`chainid.gap.core.noise.force_noise`) over the share of the noise's second-difference power that the
    comparison keeps (:func:`chainid.gap.timedomain.bandlimit.difference_share`).

    Parameters
    ----------
    r : ndarray
        The residual [N] of one record, sample by sample (uniform sampling).
    fs : float
        Its sampling rate [Hz].
    f_res : float
        The cut [Hz] it is compared below (NaN: the whole band).

    Returns
    -------
    float
        σ_c [N]; NaN under 5 samples.
    """
    r = np.asarray(r, float)
    if r.size < 5:
        return float("nan")
    share = difference_share(fs, f_res)
    return force_noise(r) / math.sqrt(share) if share > 0.0 else float("nan")


def refuting(sigma: float, r: np.ndarray, fs: float, f_res: float) -> float | None:
    """σ_c [N] of the residual ``r`` [N] (:func:`residual_sigma`, ``fs`` [Hz], ``f_res`` [Hz]) where it refutes the
    noise ``sigma`` [N] first read from the force, σ_c² < :data:`RATIO` · σ²; None where that reading stands."""
    s_c = residual_sigma(r, fs, f_res)
    return s_c if math.isfinite(s_c) and s_c > 0.0 and s_c * s_c < RATIO * sigma * sigma else None


def caps(tdata: Sequence[Any], res: dict[str, np.ndarray]) -> dict[str, float]:
    """The records whose first σ reading a fitted candidate's residual refutes.

    Parameters
    ----------
    tdata : sequence of TimeData
        The records as prepared (``test``, ``sigma`` [N] as read, ``fs`` [Hz], ``f_res`` [Hz]).
    res : dict
        Per test, the residual [N] sample by sample (:meth:`TimeProblem.evaluate`'s ``res``).

    Returns
    -------
    dict
        ``{test: σ_c}`` [N] where σ_c² < :data:`RATIO` · σ² (empty: every σ stands).
    """
    out = {}
    for d in tdata:
        s_c = refuting(d.sigma, res[d.test], d.fs, d.f_res) if d.test in res else None
        if s_c is not None:
            out[d.test] = s_c
    return out


def note(tdata: Sequence[Any], capped: dict[str, float]) -> str:
    """The warning that says which records' σ was refuted and read again, with both numbers [N] (``tdata`` the
    records as prepared, ``capped`` :func:`caps`' result)."""
    parts = ", ".join(f"{d.test} {d.sigma:.3g} → {capped[d.test]:.3g} N" for d in tdata if d.test in capped)
    return (f"force noise read again: on {len(capped)} record(s) the noise read from the fitted chain's residual "
            f"is under half the power read from the force ({parts}), which took force content for noise (a force "
            f"that switches every few samples does this); the diagnosis was run again on the noise so read")
