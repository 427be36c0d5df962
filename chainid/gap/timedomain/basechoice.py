"""What the time route's base carries, from its training records alone: the operating conditions that differ between
them, and whether the dashpot follows the records' features.

* :func:`distinct_covariates`: the covariates (operating conditions: a pressure, a coil current) that vary over the
  records, one per condition;
* :func:`law_choice`: the base's damping, ``"feature"`` (c_r = c + b_w·(ω_r − w_ref) + b_A·(A_r − A_ref), the
  paper's c_e(ω, A) carried to any excitation) or ``"viscous"`` (one c), and why.  The law needs
  :data:`MIN_LAW_RECORDS` training records with distinct features; records at different operating conditions keep
  one c in the base, since the condition moves a record's damping and, through the device, its band and amplitude
  (a seal's friction slows the actuator as the pressure rises): a law over the features would stand in for the
  condition.  The dashpot following the condition (``damping.c@cov``) and the features (the effect
  ``damping_law``) are then steps the held-out data judge.

Units: ω rad/s, A mm, c N·s/mm.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np

__all__ = ["MIN_LAW_RECORDS", "distinct_covariates", "law_choice"]

#: fewest training records with distinct features for a damping law over them
MIN_LAW_RECORDS = 3


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
    return "viscous", (f"time domain: viscous c·ẋ (fewer than {MIN_LAW_RECORDS} training records with distinct band "
                       "centre and amplitude: no law over record features)")
