"""Resampling hooks of the time-domain problem: its training blocks drawn with replacement.

A resample gives every training block a multiplicity (a multinomial draw of as many blocks as there are; held-out
blocks stay out).  :func:`rescore` scores a fitted candidate on a resample at its fitted shape parameters with every
amplitude refitted exactly from the blocks' Gram matrices (:mod:`.lsq`): the leave-one-block-out error of each
drawn block, weighted by its multiplicity — what the step rule compares.  :func:`refit` refits a candidate on a
resample, its shape parameters polished from the full fit (:class:`.problem.TimeProblem`'s ``fit`` with the
multiplicities as weights): the parameter values whose spread gives the intervals.

Units: N² for the errors; each parameter's own unit.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from chainid.gap.timedomain.lsq import Blocks, sse_at

__all__ = ["unit_keys", "draw", "identity", "rescore", "refit"]


def unit_keys(prob: Any) -> list[tuple[str, int]]:
    """(record, block) of every block, in the problem's stacking order."""
    return [(d.test, b) for d in prob.tdata for b in range(d.n_blocks)]


def draw(prob: Any, rng: np.random.Generator) -> np.ndarray:
    """Multiplicities of every block (stacking order): a multinomial draw over the training blocks, 0 elsewhere."""
    base = prob._train_mult()
    idx = np.flatnonzero(base > 0)
    out = np.zeros_like(base)
    out[idx] = rng.multinomial(idx.size, np.full(idx.size, 1.0 / idx.size))
    return out


def identity(prob: Any) -> np.ndarray:
    """The multiplicities of the data as they are: every training block once."""
    return prob._train_mult()


def rescore(prob: Any, cand: Any, mult: np.ndarray) -> tuple[dict[str, float], float, bool]:
    """Leave-one-block-out errors of a candidate on a resample (its shapes fixed, amplitudes refitted): the
    per-unit numerators ``{"test#block": m·SSE [N²]}`` of drawn blocks, the pooled LOTO NRMSE, and whether that
    residual is at the noise floor (the step rule's first test, on the resample)."""
    ev = cand._ev  # type: ignore[attr-defined]
    bl: Blocks = ev["blocks"]
    keys = unit_keys(prob)
    sig = {d.test: d.sigma for d in prob.tdata}
    names = cand.names
    loto, den, r2, f2, n = {}, 0.0, 0.0, 0.0, 0.0
    floor = {d.test: prob.noise_floor(d, cand.params) for d in prob.tdata}
    for u in np.flatnonzero(mult > 0):
        mm = mult.copy()
        mm[u] = 0.0
        a = prob._solve(names, bl, mm)
        one = Blocks(bl.G[u:u + 1], bl.h[u:u + 1], bl.s[u:u + 1], bl.w[u:u + 1], bl.n[u:u + 1])
        t, b = keys[u]
        sse = float(sse_at(one, a)[0]) * sig[t] ** 2
        loto[f"{t}#{b}"] = mult[u] * sse
        den += mult[u] * ev["var"][(t, b)]
        r2 += mult[u] * sse
        f2 += mult[u] * bl.n[u] * floor[t]
        n += mult[u] * bl.n[u]
    nrmse = math.sqrt(sum(loto.values()) / den) if den > 0 else float("nan")
    at_floor = f2 > 0 and (r2 / n) / (f2 / n) < 1 + 5 * math.sqrt(2.0 / max(n, 1.0) + prob.floor_rel_sd("train") ** 2)
    return loto, nrmse, bool(at_floor)


def refit(prob: Any, cand: Any, mult: np.ndarray) -> dict[str, float]:
    """A candidate's fitted parameters refitted on a resample (shapes polished from the full fit, amplitudes
    exact); the fixed references they are stated against (a law's w_ref, A_ref and box, hardening's x_ref: not
    estimates, so no interval) are left out."""
    c = prob.fit(cand.names, start=cand.params, polish_only=True, weights=mult)
    refs = prob.references(cand.names)
    return {k: v for k, v in c.params.items() if k not in refs}
