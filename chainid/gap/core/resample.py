"""How far to believe a diagnosis: the explanation chain and its parameters over resamples of the training units.

The training units (time blocks, harmonic tests) are drawn with replacement ``n`` times (a block bootstrap: whole
tests and contiguous blocks, never single samples).  On every resample:

* **the chain is chosen again** by the step rule (:mod:`.steprule`: significance over units, materiality,
  identification, and the one-step look-ahead at a close runner-up, :func:`.steprule.look_ahead`, among the
  extensions the diagnosis fitted), then the final chain's family exchange and split of a richer effect
  (:func:`exchange_replay`, :func:`split_replay`), among the effect sets the diagnosis fitted, each scored on the
  resample with its amplitudes (or its damping law) refitted exactly and its shape parameters kept (the route's
  ``rescore``) — the share of resamples that choose each step is its *stability*;
* **the parameters of every step of the chain are refitted** (the route's ``refit``: shapes polished from the full
  fit, amplitudes exact) — the 5th and 95th percentiles of each are its 90 % interval, recentred on the
  reported estimate: every refit is shifted by θ̂ − θ*₀, θ*₀ the same refit on the data as they are (the route's
  ``identity`` multiplicities).  The refit's polish need not end where the diagnosis' own fit did (another
  search, another subset); without the shift an interval can miss its own estimate.

A step is *confident* when its stability is at least :data:`CONFIDENT`.  The resamples run on forked
worker processes (:func:`chainid.infra.forkpool.fork_map`: the problem is inherited, not copied) when there are
at least :data:`POOL_MIN` of them, and in this process otherwise.

Units: each parameter's own.
"""

from __future__ import annotations

import math
from types import SimpleNamespace
from typing import Any, Sequence

import numpy as np

from chainid.gap.core.steprule import (FAMILIES, SIMPLER, look_ahead, near_tie_first, newest, pick,
                                      refuted_member, split_acceptable, step_test, swap_acceptable, takes)
from chainid.infra.forkpool import can_fork, fork_map

__all__ = ["CONFIDENT", "RESAMPLES", "resample", "replay", "exchange_replay", "split_replay", "order_replay", "widen",
           "attach"]

#: a step is named as confident when at least this share of resamples chooses it
CONFIDENT = 0.8
#: resamples by default
RESAMPLES = 200
#: fewest resamples worth a process pool
POOL_MIN = 40

def replay(prob: Any, hooks: Any, cache: dict[tuple[str, ...], Any], base: Any, mult: np.ndarray,
           max_effects: int) -> list[str]:
    """The chain the step rule chooses on one resample among the fitted effect sets in ``cache``."""
    scored: dict[tuple[str, ...], Any] = {}

    def score(c: Any) -> Any:
        key = tuple(sorted(c.names))
        if key not in scored:
            loto, nrmse, floor = hooks.rescore(prob, c, mult)
            scored[key] = SimpleNamespace(names=c.names, loto_num=loto, nrmse_loto=nrmse, at_floor=floor,
                                          at_bound=c.at_bound, n_params=c.n_params, bic=c.bic,
                                          params=getattr(c, "params", {}))  # nested_pair reads a friction's μ, x_s
        return scored[key]

    def extend(c: Any, n: str) -> Any:
        """The fitted set of c's terms plus n, rescored, or None (not fitted by the diagnosis)."""
        key = tuple(sorted(set(c.names) | {n}))
        if key not in cache:
            return None
        e = score(cache[key])
        return e if set(e.loto_num) == set(c.loto_num) else None

    library = sorted(set().union(*cache)) if cache else []
    cur = score(base)
    chain: list[str] = []
    while len(chain) < max_effects and not cur.at_floor:
        nxt = [c for key, c in cache.items() if len(key) == len(chain) + 1 and set(chain) <= set(key)]
        ok = [c for c in map(score, nxt)
              if set(c.loto_num) == set(cur.loto_num) and takes(c, step_test(cur, c), newest(c, chain))]
        if not ok:
            break
        chosen, _ = pick(ok)
        remaining = [n for n in library if n not in chain]
        chosen = look_ahead(chain, chosen, ok, remaining, max_effects, extend, lambda c: c.at_floor)
        chain.append(newest(chosen, chain))
        cur = chosen
    swapped, cur = exchange_replay(chain, cur, cache, score)
    split = split_replay(swapped, cur, cache, score, max_effects)
    return chain if split == chain else order_replay(split, cache, score)


def order_replay(effects: list[str], cache: dict[tuple[str, ...], Any], score: Any) -> list[str]:
    """An effect set ordered as the diagnosis orders a chain its exchange or split changed
    (:func:`chainid.gap.core.refine.rebuild`): greedily, the effect whose fitted set with those before it has the
    lowest rescored LOTO first; effects whose sets were not fitted keep their order at the end."""
    path: list[str] = []
    left = list(effects)
    while left:
        keys = [(n, tuple(sorted(path + [n]))) for n in left]
        fitted = [(score(cache[k]).nrmse_loto, i, n) for i, (n, k) in enumerate(keys) if k in cache]
        if not fitted:
            return path + left
        n = min(fitted)[2]
        path.append(n)
        left.remove(n)
    return path


def exchange_replay(chain: list[str], cur: Any, cache: dict[tuple[str, ...], Any], score: Any
                    ) -> tuple[list[str], Any]:
    """The final chain's family exchange (:func:`chainid.gap.core.refine.exchange`) on one resample, among the
    effect sets fitted (chains of two or more effects, as there; at most two passes): an effect swaps for a member
    of its family when that set, rescored, is identified and lower by more than ``TIE``, or within it with fewer
    parameters pinned or fewer parameters.  Returns the new chain (in the old one's order) and its scored set."""
    chain = list(chain)
    if len(chain) < 2:
        return chain, cur

    def fitted(key: tuple[str, ...]) -> Any:
        """The rescored set of ``key`` (its sorted names), or None when the diagnosis did not fit it."""
        return score(cache[key]) if key in cache else None

    for _ in range(2):
        improved = False
        for i, n in enumerate(list(chain)):
            for m in next((f for f in FAMILIES if n in f), ()):
                names = [m if k == n else k for k in chain]
                key = tuple(sorted(names))
                if m == n or m in chain or key not in cache:
                    continue
                sc = score(cache[key])
                if swap_acceptable(sc, cur, m) and not refuted_member(sc, names, m, fitted):
                    chain[i], cur, improved = m, sc, True
                    break
        if not improved:
            break
    return chain, cur


def split_replay(chain: list[str], cur: Any, cache: dict[tuple[str, ...], Any], score: Any, max_effects: int
                 ) -> list[str]:
    """The final chain's split (:func:`chainid.gap.core.refine.split_richer`) on one resample, among the effect sets
    fitted: a richer effect n of ``chain`` (scored ``cur``) becomes its simpler member plus a next effect x when that
    set was fitted and, rescored, has no more parameters, is identified and is lower by more than ``TIE`` or within
    it and first in the near-tie order; the best such set over every richer effect wins.  (The backward check of
    the full diagnosis is not repeated here.)"""
    if len(chain) + 1 > max_effects:
        return chain
    alts = []
    for n in chain:
        a = SIMPLER.get(n)
        if a is None or a in chain:
            continue
        rest = set(chain) - {n}
        for key, c in cache.items():
            extra = set(key) - rest - {a}
            if len(key) != len(chain) + 1 or a not in key or n in key or not rest <= set(key) or len(extra) != 1:
                continue
            sc = score(c)
            x = extra.pop()
            if split_acceptable(sc, cur, (a, x)):
                alts.append((sc, n, a, x))
    if not alts:
        return chain
    _, n, a, x = near_tie_first(alts)[0]
    return [a if k == n else k for k in chain] + [x]


def _one(j: dict[str, Any], i: int) -> tuple[list[str], list[dict[str, float]]]:
    mult = j["mult"][i]
    chain = replay(j["prob"], j["hooks"], j["cache"], j["base"], mult, j["max_effects"])
    if j["cut"] in chain:  # an effect the route cut as rate-dependent is cut from every resample's chain too
        chain = chain[: chain.index(j["cut"])]
    params = [j["hooks"].refit(j["prob"], c, mult) for c in j["steps"]]
    return chain, params


def resample(prob: Any, hooks: Any, fwd: dict[str, Any], steps: Sequence[Any], n: int = RESAMPLES, seed: int = 0,
             max_effects: int = 3, workers: int | None = None) -> dict[str, Any]:
    """Stability of the chain and percentile intervals of its parameters over ``n`` resamples.

    Parameters
    ----------
    prob, hooks : the route's problem and its resampling module (``draw``, ``identity``, ``rescore``, ``refit``)
    fwd : the forward selection's result (its ``_cache`` of fitted effect sets, its ``path``; a
        ``rate_dependence`` finding's effect is cut from every resample's chain, as from the diagnosis')
    steps : the steps of the chain to report (baseline first)
    n, seed : resamples and the seed of their draws
    max_effects : the most effects in a chain

    Returns
    -------
    dict
        ``resamples``, ``seed``, ``confident_at``, ``steps`` (per step: ``effect``, ``stability`` — the share of
        resamples whose chain contains it —, ``chosen_at_step``, ``params_ci90``), ``chains`` (the commonest
        chains and their shares), ``same_chain`` (the share of resamples choosing exactly the diagnosis' chain),
        ``units`` (the training units drawn: tests or time blocks).
    """
    rng = np.random.default_rng(seed)
    mult = [hooks.draw(prob, rng) for _ in range(n)]
    ident = hooks.identity(prob)
    shift = [{k: float(v) - float(c0[k]) for k, v in st.params.items() if k in c0 and math.isfinite(c0[k])
              and math.isfinite(v)} for st, c0 in ((st, hooks.refit(prob, st, ident)) for st in steps)]
    job = dict(prob=prob, hooks=hooks, cache=fwd["_cache"], base=fwd["path"][0], mult=mult, steps=list(steps),
               max_effects=max_effects, cut=(fwd.get("rate_dependence") or {}).get("name"))
    out = fork_map(lambda i: _one(job, i), range(n), workers, min_items=POOL_MIN,
                   chunksize=max(1, n // (4 * (can_fork(workers) or 1))))
    return _summarise([o[0] for o in out], [o[1] for o in out], steps, n, seed, shift) | {
        "units": int(np.count_nonzero(ident))}


def _summarise(chains: list[list[str]], params: list[list[dict[str, float]]], steps: Sequence[Any], n: int,
               seed: int, shift: Sequence[dict[str, float]] | None = None) -> dict[str, Any]:
    names = [s.names[-1] for s in steps[1:]]
    rows = []
    for k, s in enumerate(steps):
        vals: dict[str, list[float]] = {}
        d = shift[k] if shift else {}
        for p in params:
            for key, v in p[k].items():
                if math.isfinite(v):
                    vals.setdefault(key, []).append(v + d.get(key, 0.0))
        ci = {key: [float(np.percentile(v, 5)), float(np.percentile(v, 95))] for key, v in vals.items()
              if len(v) >= max(10, n // 2)}
        row: dict[str, Any] = {"effect": "baseline" if k == 0 else names[k - 1], "params_ci90": ci}
        if k:
            e = names[k - 1]
            row["stability"] = sum(e in c for c in chains) / n
            row["chosen_at_step"] = sum(len(c) >= k and c[k - 1] == e for c in chains) / n
        rows.append(row)
    counts: dict[str, int] = {}
    for c in chains:
        key = "+".join(c) or "(none)"
        counts[key] = counts.get(key, 0) + 1
    top = sorted(counts.items(), key=lambda kv: -kv[1])[:5]
    same = sum(set(c) == set(names) for c in chains) / n
    return {"resamples": n, "seed": seed, "confident_at": CONFIDENT, "steps": rows,
            "chains": [{"chain": k, "share": v / n} for k, v in top], "same_chain": same}


def widen(stab: dict[str, Any], shifts: Sequence[dict[str, float]], key: str = "bias_dt",
          bounds: Sequence[dict[str, Any]] | None = None) -> None:
    """Widen each step's 90 % interval by a bias that resampling cannot see (the same in every resample).

    ``shifts[k][param]`` is the estimated bias of step k's parameter [its unit] (the time sampling's,
    :mod:`chainid.gap.timedomain.discretisation`; the displacement noise's, :mod:`chainid.gap.timedomain.simex`);
    the interval [lo, hi] becomes the union of itself and [lo − bias, hi − bias], so a bias within the resampling
    spread changes little and a larger one is taken in.  Widening by two biases in turn takes in their sum where
    they share a sign and each alone where they do not; a widened edge stops at the parameter's bound (``bounds[k]``:
    step k's ``{param: (lo, hi)}``, when given).  The biases are kept per step under ``key``, and the intervals
    before any widening under ``params_ci90_percentile``."""
    for k, (row, sh) in enumerate(zip(stab["steps"], shifts)):
        row[key] = dict(sh)
        row.setdefault("params_ci90_percentile", {n: list(v) for n, v in row["params_ci90"].items()})
        lims = bounds[k] if bounds is not None and k < len(bounds) else {}
        for name, (lo, hi) in list(row["params_ci90"].items()):
            b = sh.get(name)
            if b is not None and math.isfinite(b):
                blo, bhi = lims.get(name, (-math.inf, math.inf))
                # widened towards the bias, never past the bound, never narrowed
                row["params_ci90"][name] = [min(lo, max(lo - b, blo)), max(hi, min(hi - b, bhi))]


def attach(result: dict[str, Any], stab: dict[str, Any]) -> None:
    """Put a resampling's numbers into a diagnosis result: per step ``stability`` and ``params_ci90`` (and the
    chain's line, ``chain_text``, with those intervals), the whole under ``stability``, and ``confidence`` —
    ``confident`` when every step of the verdict's chain is chosen by at least :data:`CONFIDENT` of the
    resamples, else ``tentative``."""
    for st, row in zip(result["steps"], stab["steps"]):
        if "stability" in row:
            st["stability"] = row["stability"]
        st["params_ci90"] = row["params_ci90"]
    result["stability"] = stab
    if result.get("residual"):  # the chain's line again, with the resampled intervals
        from chainid.gap.core.verdict import chain_text

        result["chain_text"] = chain_text(result["steps"], result.get("trusted_steps", len(result["steps"])),
                                          result["residual"])
    shares = [r["stability"] for r in stab["steps"][1:]]
    result["confidence"] = "confident" if all(v >= CONFIDENT for v in shares) else "tentative"
    if shares and result["confidence"] == "tentative":
        weak = ", ".join(f"{r['effect']} {100 * r['stability']:.0f} %" for r in stab["steps"][1:]
                         if r["stability"] < CONFIDENT)
        result["warnings"].append(f"tentative: step(s) chosen by fewer than {100 * CONFIDENT:.0f} % of "
                                  f"{stab['resamples']} resamples ({weak})")
