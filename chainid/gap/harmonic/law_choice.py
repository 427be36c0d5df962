"""Damping laws c_e(ω, A) of the diagnosis and their leave-one-test-out fit.

Each law is linear in its coefficients, c_e = X(ω, A, k_e) · p [N·s/mm]:

* ``polynomial``   — the paper's Eq. 21, c_e = α₁ω² + α₂ω + α₃A² + α₄A + α₅ (5 coefficients);
* ``viscous``      — c_e = c (1);
* ``coulomb``      — Coulomb-equivalent, c_e = 4F_f/(πωA) (1);
* ``hysteretic``   — structural, c_e = η·k_e(x0)/ω (1);
* sums of the last three.

Units: ω rad/s, A mm, k_e N/mm, c_e N·s/mm.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from chainid.model.timedamping import LAWS, design  # noqa: F401  (one definition of the laws, in the model floor)

#: the forms the ``damping_law`` effect tries instead of the baseline's law
ALT_LAWS = ("viscous+hysteretic", "viscous+coulomb", "viscous+coulomb+hysteretic", "coulomb", "hysteretic")
#: choices of ``--damping-law``
CHOICES = ("auto", "polynomial", "viscous", "coulomb", "viscous+coulomb", "hysteretic")


def fit_loo(X: np.ndarray, c: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Least-squares coefficients and leave-one-out predictions of c.

    c_loo,i = c_i − r_i/(1 − h_i) with the leverages of :func:`chainid.model.laws.leverages` (memory linear in the
    number of tests).
    """
    from chainid.model.laws import leverages

    X = np.asarray(X, float)
    c = np.asarray(c, float)
    p, *_ = np.linalg.lstsq(X, c, rcond=None)
    h = np.minimum(leverages(X), 1.0 - 1e-9)
    resid = c - X @ p
    return p, c - resid / (1.0 - h)


def allowed(n_train: int, candidates: Sequence[str] = tuple(LAWS)) -> list[str]:
    """Laws with no more coefficients than training tests − 1 (so that leave-one-out is defined)."""
    return [k for k in candidates if LAWS[k] <= n_train - 1]


#: a leave-one-out error below this share of the RMS c_e is round-off: an exact fit
ROUND_OFF = 1e-12


def choose(w: np.ndarray, A: np.ndarray, ke: np.ndarray, c: np.ndarray,
           candidates: Sequence[str]) -> tuple[str, dict[str, float]]:
    """The law with the smallest leave-one-out RMS error of c_e among ``candidates`` (fewer coefficients on ties).

    Returns the name and the LOO RMS error [N·s/mm] of every candidate.
    """
    errs: dict[str, float] = {}
    for k in candidates:
        _, cl = fit_loo(design(k, w, A, ke), c)
        errs[k] = float(np.sqrt(np.mean((c - cl) ** 2)))
    if not errs:
        raise ValueError("no damping law has fewer coefficients than the training tests")
    # errors at round-off of the c_e themselves are all zero (an exact fit): equal, as are errors within 1e-9 of
    # each other; the law with fewer coefficients ranks first
    floor = ROUND_OFF * float(np.sqrt(np.mean(np.square(c))))
    best = min(errs, key=lambda k: (max(errs[k], floor) * (1 + 1e-9 * LAWS[k]), LAWS[k]))
    return best, errs
