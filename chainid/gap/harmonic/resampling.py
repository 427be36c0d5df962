"""Resampling hooks of the harmonic problem: its training tests drawn with replacement.

A resample gives every training test a multiplicity (a multinomial draw of as many tests as there are; held-out
tests stay out).  :func:`rescore` scores a fitted candidate on a resample at its fitted parameters: each test's
c_e is its own projection (as in the selection's fits), the damping law is refitted on the drawn tests by weighted
least squares and each drawn test's error is that of the law refitted without it, weighted by its multiplicity.
When the other drawn tests are fewer than the law's coefficients (a 5-coefficient law and few distinct tests in
the draw), the law without that test is fitted on every other training test instead (the plain leave-one-test-out):
a resample never loses a test, so the steps' stability is not diluted by draws that could score nothing.
:func:`refit` polishes a candidate's parameters on the drawn tests (each weighted by its multiplicity; each test's
c_e free, also for a step whose point estimate tied them to its law, :mod:`chainid.gap.harmonic.tie`).

Units: N² for the errors; each parameter's own unit.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from chainid.gap.harmonic import law_choice as L

__all__ = ["unit_keys", "draw", "identity", "rescore", "refit"]


def unit_keys(prob: Any) -> list[str]:
    """The training tests, in order (the resampled units)."""
    return [d.test for d in prob.train]


def draw(prob: Any, rng: np.random.Generator) -> np.ndarray:
    """Multiplicities of the training tests: a multinomial draw of as many tests as there are."""
    n = len(prob.train)
    return rng.multinomial(n, np.full(n, 1.0 / n)).astype(float)


def identity(prob: Any) -> np.ndarray:
    """The multiplicities of the data as they are: every training test once."""
    return np.ones(len(prob.train))


def _wfit(X: np.ndarray, c: np.ndarray, w: np.ndarray) -> np.ndarray:
    sw = np.sqrt(w)
    return np.linalg.lstsq(X * sw[:, None], c * sw, rcond=None)[0]


def rescore(prob: Any, cand: Any, mult: np.ndarray) -> tuple[dict[str, float], float, bool]:
    """Leave-one-test-out errors of a candidate on a resample (its parameters fixed, the damping law refitted): the
    per-test numerators ``{test: m·SSE [N²]}`` of drawn tests, the pooled LOTO NRMSE, and whether that residual is
    at the noise floor (phase bins, σ²/n per bin)."""
    ev = cand._ev  # type: ignore[attr-defined]
    tr = prob.train
    X = L.design(cand.law, *prob._wak(tr))
    c = np.array([ev["c_e"][d.test] for d in tr])
    loto, den, r2, f2, n = {}, 0.0, 0.0, 0.0, 0
    for i in np.flatnonzero(mult > 0):
        w = mult.copy()
        w[i] = 0.0
        if np.count_nonzero(w) < X.shape[1]:  # the drawn tests do not determine the law: its fit on every other
            w = np.ones_like(mult)            # training test (the plain leave-one-test-out), never a skipped test
            w[i] = 0.0
        ci = float(X[i] @ _wfit(X, c, w))
        d = tr[i]
        Fn, v = ev["parts"][d.test]
        r = d.Fbar - Fn - ci * v
        sse = float(np.sum(d.counts * r**2))
        loto[d.test] = mult[i] * sse
        den += mult[i] * float(np.sum(d.counts * (d.Fbar - np.sum(d.counts * d.Fbar) / np.sum(d.counts)) ** 2))
        r2 += mult[i] * float(np.sum(r**2))
        f2 += mult[i] * float(np.sum(d.sigma**2 / np.maximum(d.counts, 1)))
        n += int(mult[i]) * r.size
    nrmse = math.sqrt(sum(loto.values()) / den) if den > 0 else float("nan")
    at_floor = f2 > 0 and r2 / f2 < 1 + 5 * math.sqrt(2.0 / max(n, 1))
    return loto, nrmse, bool(at_floor)


def refit(prob: Any, cand: Any, mult: np.ndarray) -> dict[str, float]:
    """A candidate's parameters polished on a resample's tests (each weighted by its multiplicity)."""
    drawn = [(d, float(m)) for d, m in zip(prob.train, mult) if m > 0]
    c = prob.fit(cand.names, train_only=[d for d, _ in drawn], weights=[m for _, m in drawn], start=cand.params,
                 polish_only=True)
    return dict(c.params)
