"""The time route's base damping: one dashpot, or a law over the records' features chosen by leave-one-record-out.

As in the paper (Eq. 21–28), a record's damping follows c_e(ω, A).  On records of any excitation the base carries
that law over record features (:class:`chainid.gap.timedomain.design.Base`),

    c_r = c + b_w·(ω_r − w_ref) + b_A·(A_r − A_ref)        [N·s/mm; ω_r rad/s, A_r mm],

ω_r the record's band centre and A_r its half range.  Which features it follows is chosen as the harmonic route
chooses its law (:mod:`chainid.gap.harmonic.law_choice`): by the error with which it predicts a record it was not
fitted on.

**The rule** (:func:`law_by_records`).  The candidates are one c, and a law over each non-empty subset of the
features that spread over the training records (:func:`chainid.gap.timedomain.design.law_features`).  For each
training record in turn the base (its spring and mass too, for a linear device) is fitted on the other training
records, by least squares within the amplitudes' bounds, and the left-out record's training samples are predicted:
the score is the χ² of each left-out record.  A candidate is scored only where every fold can determine it: the
other records must hold at least as many distinct feature points as the law has coefficients (a law with as many
coefficients as records interpolates them and predicts nothing).  Taken fewest features first, a candidate
replaces the best so far when its summed χ² is lower by more than one standard error of the paired per-record
differences (:func:`better`, the one-standard-error rule): a gain at the level of the noise keeps the simpler
law.  Three training records with distinct features are the fewest for any law (:data:`MIN_LAW_RECORDS`).

Three records whose dampings scatter about one value, and a held-out record at twice their band centre, are the
case this guards against: the three-coefficient law passes through the three exactly and its slopes, extrapolated,
gave that record c = 48 N·s/mm for a true 9.3 (a start-up case of ``benchmark-gap``, seed 102017).
"""

from __future__ import annotations

from itertools import combinations
from typing import Any, Sequence

import numpy as np

from chainid.gap.timedomain.design import Base, ColumnCache, amplitude_bounds, amplitude_names, build
from chainid.gap.timedomain.lsq import Blocks, solve, sse_at

__all__ = ["MIN_LAW_RECORDS", "loo_scores", "better", "law_by_records", "law_choice"]

#: fewest training records with distinct features for a damping law over them
MIN_LAW_RECORDS = 3

_SLOPE = {"w": "damping_law.b_w", "A": "damping_law.b_A"}


def _points(records: Sequence[Any]) -> int:
    """Distinct (band centre, half range) points of ``records``."""
    return len({(round(d.omega_c, 6), round(d.A_c, 6)) for d in records})


def _candidates(feats: Sequence[str]) -> list[tuple[str, ...]]:
    """One c, then every non-empty subset of ``feats``, fewest features first."""
    return [()] + [tuple(s) for k in range(1, len(feats) + 1) for s in combinations(feats, k)]


def _blocks(base: Base, records: Sequence[Any], views: dict[str, tuple], cache: ColumnCache
            ) -> tuple[list[Blocks], list[str]]:
    """Per record, the block statistics of the base with its full law (columns :func:`amplitude_names`)."""
    out = []
    for d in records:
        idx, lead = views[d.test]
        f, Phi, y = build(base, [], {}, d, idx, cache, lead)
        blk = d.block if idx is None else d.block[idx]
        out.append(Blocks.from_columns(Phi, y - f, blk, d.n_blocks, 1.0 / d.sigma ** 2))
    return out, amplitude_names(base, [])


def loo_scores(base: Base, records: Sequence[Any], train: dict[str, np.ndarray], views: dict[str, tuple],
               cache: ColumnCache) -> dict[tuple[str, ...], np.ndarray]:
    """χ² of each left-out training record predicted from the others, per candidate feature set (see the module
    docstring); a candidate that some fold cannot determine is left out.

    ``base`` carries the full law (``law_features``: the features that spread); ``train`` maps a test to the
    boolean training mask of its blocks (n_blocks,); ``views`` a test to its (samples, lead-in mask)."""
    recs = [d for d in records if train[d.test].any()]
    stats, amps = _blocks(base, recs, views, cache)
    lo, hi = amplitude_bounds(amps)
    masks = [train[d.test].astype(float) for d in recs]
    out: dict[tuple[str, ...], np.ndarray] = {}
    for cand in _candidates(base.law_features):
        keep = np.array([a not in _SLOPE.values() or any(_SLOPE[k] == a for k in cand) for a in amps])
        if any(_points(recs[:i] + recs[i + 1:]) < 1 + len(cand) for i in range(len(recs))):
            continue
        chi2 = np.zeros(len(recs))
        for i in range(len(recs)):
            G = sum(np.tensordot(masks[j], stats[j].G, axes=1) for j in range(len(recs)) if j != i)
            h = sum(masks[j] @ stats[j].h for j in range(len(recs)) if j != i)
            a = np.zeros(len(amps))
            a[keep] = solve(G[np.ix_(keep, keep)], h[keep], lo[keep], hi[keep])
            chi2[i] = float(masks[i] @ sse_at(stats[i], a))
        out[cand] = chi2
    return out


def better(rich: np.ndarray, simple: np.ndarray) -> bool:
    """Whether per-record left-out χ² ``rich`` beat ``simple`` by more than one standard error of their paired
    difference, √K·sd(d) over the K records (the one-standard-error rule of cross-validation, Hastie, Tibshirani
    & Friedman, *The Elements of Statistical Learning*, §7.10: a noise-level gain keeps the simpler law)."""
    d = np.asarray(simple, float) - np.asarray(rich, float)
    return bool(d.sum() > np.sqrt(d.size) * float(np.std(d, ddof=1)))


def law_by_records(base: Base, records: Sequence[Any], train: dict[str, np.ndarray], views: dict[str, tuple],
                   cache: ColumnCache) -> tuple[tuple[str, ...], dict[tuple[str, ...], float]]:
    """The features the base's law follows (``()``: one c) by leave-one-record-out, and every candidate's summed
    score (see the module docstring, :func:`loo_scores` and :func:`better`)."""
    scores = loo_scores(base, records, train, views, cache)
    best: tuple[str, ...] = ()
    for cand, s in scores.items():  # fewest features first: a richer law must beat the best so far
        if cand and better(s, scores[best]):
            best = cand
    return best, {c: float(s.sum()) for c, s in scores.items()}


def law_choice(feature: bool, asked: str, n_train: int, scores: dict[tuple[str, ...], float] | None = None
               ) -> tuple[str, str]:
    """The base's damping on the time route and why: ``"feature"`` (the dashpot follows the records' band centre
    and amplitude, :class:`chainid.gap.timedomain.design.Base`) or ``"viscous"`` (one c), for the law ``asked``
    (``--damping-law``: ``viscous`` keeps one c; any other, the feature law where the records separate it and it
    predicts a left-out record better, ``scores`` from :func:`law_by_records`)."""
    loo = ""
    if scores:
        names = {(): "one c"} | {c: "law over " + "+".join("ω" if k == "w" else "A" for k in c) for c in scores if c}
        loo = "; leave-one-record-out χ²: " + ", ".join(f"{names[c]} {s:.4g}" for c, s in scores.items())
    if feature:
        return "feature", (f"time domain: the dashpot follows the records' features, c_r = c + b_w·(ω_r − w_ref) + "
                           f"b_A·(A_r − A_ref) (the paper's c_e(ω, A) over records of any excitation; {n_train} "
                           f"training records separate it{loo})")
    if asked == "viscous":
        return "viscous", "given"
    if scores and len(scores) > 1:
        return "viscous", ("time domain: viscous c·ẋ (no law over the records' features predicts a left-out record "
                           f"better than one c{loo})")
    return "viscous", (f"time domain: viscous c·ẋ (fewer than {MIN_LAW_RECORDS} training records with distinct band "
                       "centre and amplitude: no law over record features)")
