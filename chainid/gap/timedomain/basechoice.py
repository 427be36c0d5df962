"""What the time route's base carries, from its training records alone: the operating conditions that differ between
them, and whether the dashpot follows the records' features.

* :func:`distinct_covariates`: the covariates (operating conditions: a pressure, a coil current) that vary over the
  records, one per condition;
* :func:`law_choice`: the base's damping, ``"feature"`` (c_r = c + b_w·(ω_r − w_ref) + b_A·(A_r − A_ref), the
  paper's c_e(ω, A) carried to any excitation) or ``"viscous"`` (one c), and why.  The law needs more training
  records with distinct features than it has coefficients (:func:`law_records_needed`); records at different
  operating conditions keep one c in the base, since the condition moves a record's damping and, through the device,
  its band and amplitude (a seal's friction slows the actuator as the pressure rises): a law over the features would
  stand in for the condition.  The dashpot following the condition (``damping.c@cov``) and the features (the effect
  ``damping_law``) are then steps the held-out data judge.

Units: ω rad/s, A mm, c N·s/mm.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np

__all__ = ["law_records_needed", "distinct_covariates", "law_choice"]


def law_records_needed(features: Sequence[str]) -> int:
    """Fewest training records with distinct features for a dashpot law over ``features`` (``"w"``, ``"A"``): its
    coefficients (c and one slope per feature) and one more, so that every record can be left out and predicted by
    the law fitted on the others (the harmonic route's rule for its laws, :func:`chainid.gap.harmonic.law_choice.
    allowed`).  With no more records than coefficients the law interpolates them: it cannot be judged, and it
    extrapolates a held-out record's damping from slopes the noise set."""
    return len(features) + 2


def distinct_covariates(records: Sequence[Any], names: Sequence[str]) -> list[str]:
    """The covariates that vary over ``records`` and are not (correlation above 0.999) an affine function of one kept
    before (a set pressure and the measured mean pressure of the same tests are one operating condition)."""
    kept: list[str] = []
    for c in names:
        v = np.array([d.covariates[c] for d in records], float)
        if not np.all(np.isfinite(v)) or np.ptp(v) == 0:
            continue
        dup = False
        for k in kept:
            u = np.array([d.covariates[k] for d in records], float)
            r = np.corrcoef(u, v)[0, 1]
            dup = dup or bool(abs(r) > 0.999)
        if not dup:
            kept.append(c)
    return kept


def law_choice(feature: bool, asked: str, n_train: int, conditions: Sequence[str] = ()) -> tuple[str, str]:
    """The base's damping on the time route and why: ``"feature"`` (the dashpot follows the records' band centre and
    amplitude, :class:`chainid.gap.timedomain.design.Base`) or ``"viscous"`` (one c), for the law ``asked``
    (``--damping-law``: ``viscous`` keeps one c; any other, the feature law where the records separate it and no
    operating condition does: ``conditions``, the covariates that differ between the training records)."""
    if feature:
        return "feature", (f"time domain: the dashpot follows the records' features, c_r = c + b_w·(ω_r − w_ref) + "
                           f"b_A·(A_r − A_ref) (the paper's c_e(ω, A) over records of any excitation; {n_train} "
                           "training records separate it)")
    if asked == "viscous":
        return "viscous", "given"
    if conditions:
        cov = ", ".join(conditions)
        return "viscous", (f"time domain: viscous c·ẋ in the base (the training records differ by the operating "
                           f"condition {cov}, which moves their features too: whether the damping follows the "
                           f"condition, damping.c@{conditions[0]}, or the features, damping_law, is a step the "
                           "held-out data judge)")
    return "viscous", ("time domain: viscous c·ẋ (no law over record features: it needs more training records with "
                       "distinct band centre and amplitude than its coefficients)")
