"""Forward selection conditional on what is already explained (the explanation chain).

Step k fits every remaining library effect *on top of* the model of step k−1 —
all parameters refitted jointly, the damping law re-identified — and scores it
leave-one-test-out (LOTO) over the training tests.  The best candidate is kept
when the improvement is significant; then a backward pass drops any earlier
effect that the later ones made redundant.

The acceptance rule (stated, tested, and the same for every data set):

1. **Above the noise floor.** The current model's LOTO residual on the training
   tests is not yet statistically consistent with the noise (χ² ratio test,
   :func:`train_floor`).
2. **Significant over tests.** Per training test, the log ratio of its LOTO
   error before and after the step, g_i = ½·ln(SSE_{k−1,i}/SSE_{k,i}); the mean
   of g over the tests must exceed ``Z`` times its jack-knife standard error
   (sd/√n): the improvement must hold across tests, so one test cannot carry
   (or veto) a step.
3. **Material.** The LOTO NRMSE falls by at least ``MIN_GAIN`` (a tenth) of
   what is left: an effect that explains less is not worth a name.
4. **Identified.** None of the new effect's parameters is pinned at a bound of
   its physical range (then its form does not fit what is left).

Near-ties at a step (LOTO within ``TIE`` of the best) go to the effect with fewer
parameters pinned at a bound, then fewer parameters, then BIC; they are reported
as confounded.
"""

from __future__ import annotations

import copy
import math
from typing import Any, Sequence

import numpy as np

from chainid.gap.core.candidate import Candidate, Problem
from chainid.infra.forkpool import fork_map
from chainid.infra.progress import stage

#: jack-knife z of the LOTO improvement required to keep a step
Z = 2.0
#: smallest relative LOTO improvement that earns a name
MIN_GAIN = 0.10
#: candidates within this relative LOTO NRMSE of the best are "equally good" (confounded)
TIE = 0.05
#: systematic residual below this fraction of the raw noise σ counts as "consistent with the noise"
NONE_FRACTION = 0.5
#: effects that are the same physics as another library member for the diagnosis (kept for ``simulate``)
ALIASES = {"machine_compliance": "stiffness_level"}


def at_noise_floor(r2: float, f2: float, sigma: float, n_bins: int, f2_rel_sd: float = 0.0) -> bool:
    """Whether a mean squared bin residual r2 [N²] is consistent with its noise floor f2 [N²].

    Consistent when the systematic part sqrt(r2 − f2) is below ``NONE_FRACTION``·σ
    (σ the raw per-sample noise [N]) or the ratio r2/f2 is within 5 standard
    deviations of 1: sqrt(2/n_bins) for the χ² of the residual, and ``f2_rel_sd`` for the floor itself when it is
    an estimate (a force noise measured on the record).
    """
    excess = math.sqrt(max(r2 - f2, 0.0))
    ratio = r2 / f2 if f2 > 0 else float("inf")
    return excess < NONE_FRACTION * sigma or ratio < 1 + 5 * math.sqrt(2.0 / max(n_bins, 1) + f2_rel_sd**2)


def loto_jackknife(prev: Candidate, new: Candidate) -> tuple[float, float]:
    """Mean over training tests of the log LOTO-error ratio, g_i = ½·ln(SSE_prev,i / SSE_new,i), and its
    jack-knife standard error (for a mean: sd/√n).

    Scale-free per test, so one test with a large force cannot carry (or veto) a step alone; g > 0 means
    the new model predicts the left-out tests better.
    """
    tests = list(prev.loto_num)
    a = np.array([prev.loto_num[t] for t in tests])
    b = np.array([new.loto_num[t] for t in tests])
    tiny = 1e-300
    g = 0.5 * (np.log(np.maximum(a, tiny)) - np.log(np.maximum(b, tiny)))  # a difference of logs: never overflows
    n = g.size
    if n < 2:
        return float(g.mean()) if n else 0.0, float("inf")
    return float(g.mean()), float(g.std(ddof=1) / math.sqrt(n))


def step_test(prev: Candidate, new: Candidate) -> dict[str, float]:
    """The step rule's numbers for going from ``prev`` to ``new``: mean log error ratio over the training
    tests, its jack-knife SE, z, and the relative drop of the pooled LOTO NRMSE."""
    delta, se = loto_jackknife(prev, new)
    gain = 1.0 - new.nrmse_loto / prev.nrmse_loto if prev.nrmse_loto > 0 else 0.0
    return {"delta_loto": delta, "se_jackknife": se, "z": delta / se if se > 0 else float("inf"),
            "relative_gain": gain}


def passes(st: dict[str, float]) -> bool:
    """Rules 2 and 3: significant over tests (> ``Z`` jack-knife SE) and material (>= ``MIN_GAIN``)."""
    return st["delta_loto"] > Z * st["se_jackknife"] and st["relative_gain"] >= MIN_GAIN


def train_floor(prob: Problem, cand: Candidate) -> bool:
    """Whether the candidate's LOTO residual on the training tests is statistically at the noise floor:
    the ratio of the mean squared bin residual to its noise floor within 5 standard deviations of a χ²
    mean (the stricter half of :func:`at_noise_floor`; a residual a little above the noise can still hold a
    second effect, and the step rule decides whether it does)."""
    ev = cand._ev  # type: ignore[attr-defined]
    r2, f2, _ = prob.noise_db(ev, "train")
    n = prob.n_cells("train")  # noise cells: phase bins of harmonic tests, samples of time-domain records
    u = getattr(prob, "floor_rel_sd", lambda split: 0.0)("train")
    return f2 > 0 and r2 / f2 < 1 + 5 * math.sqrt(2.0 / max(n, 1) + u**2)


def term_prefix(term: str) -> str:
    """The parameter prefix of a chain term: ``effect.`` for an effect and for ``effect@cov`` (the effect with its
    amplitudes following a covariate); the term itself for a slope ``effect.param@cov``."""
    head = term.split("@", 1)[0]
    return head + "." if "." not in head else term


def pinned_params(c: Candidate) -> list[str]:
    """The parameters of the candidate's newest term pinned at a bound of their physical range."""
    if not c.names:
        return []
    new = term_prefix(c.names[-1])
    return [k for k in c.at_bound if k.startswith(new)]


def pick(cands: list[Candidate]) -> tuple[Candidate, list[Candidate]]:
    """Best LOTO candidate; near-ties go to the one with fewer parameters pinned at a physical bound (a
    pinned parameter means the effect's form does not fit), then fewer parameters, then BIC.
    Returns (chosen, tied others)."""
    cands = sorted(cands, key=lambda c: c.nrmse_loto)
    best = cands[0]
    ties = [c for c in cands if c.nrmse_loto <= (1 + TIE) * best.nrmse_loto]
    chosen = min(ties, key=lambda c: (len(c.at_bound), c.n_params, c.bic))
    return chosen, [c for c in ties if c is not chosen]


def fit_cached(cache: dict[tuple[str, ...], Candidate], fit: Any, names: list[str]) -> Candidate:
    """The fitted candidate of an effect set, fitted once per set (``fit(names)`` on a miss), whatever the order
    the chain reaches it in; returned named in ``names``' order (a copy when the cached fit came in another)."""
    key = tuple(sorted(names))
    if key not in cache:
        stage("selection", f"step {len(names)}: {'+'.join(names)}")
        cache[key] = fit(list(names))
    hit = cache[key]
    if hit.names != list(names):  # the same set reached in another order: named in this chain's order
        hit = copy.copy(hit)
        hit.name = "+".join(names)
    return hit


def forward_select(prob: Problem, names: Sequence[str], base: Candidate, base_hold: float,
                   max_effects: int = 3) -> dict[str, Any]:
    """Run the forward (then backward) selection.

    Parameters
    ----------
    prob : Problem
    names : library effects to consider
    base : the scored baseline candidate (no effect)
    base_hold : baseline held-out NRMSE (for shrinkage)
    max_effects : most effects in the chain

    Returns
    -------
    dict
        ``path`` (list of Candidate, baseline first), ``singles`` (every effect on the
        baseline, scored), ``stop`` (why the chain ended), ``confounded`` (per step),
        ``dropped`` (effects removed by the backward pass).
    """
    cache: dict[tuple[str, ...], Candidate] = {}

    def cached(cur: Candidate, n: str) -> Candidate:
        return fit_cached(cache, lambda names_k: _fit_score(prob, names_k, cur.params, base_hold), cur.names + [n])

    path = [base]
    cur = base
    remaining = [n for n in names]
    singles: list[Candidate] = []
    confounded: list[dict[str, Any]] = []
    rejected: list[dict[str, Any]] = []
    stop = ""
    while True:
        if len(cur.names) >= max_effects:
            stop = f"the chain has the maximum of {max_effects} effects"
            break
        if train_floor(prob, cur):
            stop = "the training residual is at the noise floor"
            break
        if not remaining:
            stop = "no library effect left"
            break
        prefetch(prob, cache, [(cur, n) for n in remaining], base_hold)
        cands = [cached(cur, n) for n in remaining]
        if not singles:
            singles = list(cands)
        for c in cands:
            c.step_test = step_test(cur, c)  # type: ignore[attr-defined]
        # the best candidate that passes the rule (the lowest-LOTO one may fail it: an improvement carried by
        # a few tests), near-ties resolved by pick, then the one-step look-ahead among those that pass; a step
        # must be physically identified: the new effect's parameters inside their bounds (rule 4)
        passing = [c for c in cands if not pinned_params(c) and passes(c.step_test)]  # type: ignore[attr-defined]
        if not passing:
            rejected = rejections(cands)
            stop = stop_message(rejected)
            break
        chosen, ties = pick(passing)
        chosen = _look_ahead(prob, cur, chosen, passing, remaining, cached, max_effects,
                             lambda jobs: prefetch(prob, cache, jobs, base_hold))
        for t in ties:
            confounded.append({"step": len(path), "pair": [chosen.names[-1], t.names[-1]],
                               "loto": [chosen.nrmse_loto, t.nrmse_loto]})
        path.append(chosen)
        cur = chosen
        remaining.remove(chosen.names[-1])
    swaps: list[str] = []
    if len(path) > 2:
        final, swaps = _exchange(prob, path[-1], names, base_hold)
        if swaps:
            path[:] = _rebuild(prob, base, final, base_hold)
    dropped = _backward(prob, path, base_hold)
    alts = _two_for_one(prob, path[-1], names, base_hold)
    confounded += [a["report"] for a in alts]
    _take_tie_break(prob, base, path, alts, base_hold)
    return {"path": path, "singles": singles, "stop": stop, "rejected": rejected, "confounded": confounded,
            "dropped": dropped, "swapped": swaps, "_cache": cache}


def rejections(cands: Sequence[Candidate]) -> list[dict[str, Any]]:
    """Why each candidate of a step was not taken, best LOTO first: ``{"effect", "nrmse_loto", "nrmse_holdout",
    "reason"}`` — a parameter at a bound of its physical range (rule 4), or the step rule's numbers (rules 2, 3)."""
    out = []
    for c in sorted(cands, key=lambda c: c.nrmse_loto):
        st = getattr(c, "step_test", None) or {}
        pins = pinned_params(c)
        if pins:
            reason = (f"parameter(s) {', '.join(pins)} at the bound of their physical range: its form does not fit "
                      "what is left")
        elif st and not st["delta_loto"] > Z * st["se_jackknife"]:
            reason = (f"not significant over the training units: mean log error ratio {st['delta_loto']:.3g}, "
                      f"jack-knife SE {st['se_jackknife']:.2g} (needs > {Z:g} SE)")
        elif st:
            reason = (f"not material: lowers the LOTO NRMSE by {100 * st['relative_gain']:.1f} % (needs >= "
                      f"{100 * MIN_GAIN:.0f} %)")
        else:
            reason = "not scored against the chain"
        out.append({"effect": c.names[-1] if c.names else c.name, "nrmse_loto": c.nrmse_loto,
                    "nrmse_holdout": c.nrmse_holdout, "relative_gain_loto": st.get("relative_gain"), "reason": reason})
    return out


def stop_message(rejected: Sequence[dict[str, Any]]) -> str:
    """Why the chain stopped when no candidate passed: the best next effect by LOTO and why it was not taken, and
    the best identified one (no parameter at a bound) when that is another."""
    if not rejected:
        return "no library effect left"
    top = rejected[0]
    msg = (f"no next effect passes the step rule: the best by LOTO, {top['effect']} (LOTO NRMSE "
           f"{top['nrmse_loto']:.4g}), was not taken: {top['reason']}")
    free = next((r for r in rejected if not r["reason"].startswith("parameter(s)")), None)
    if free is not None and free is not top:
        msg += f"; the best identified one, {free['effect']} (LOTO NRMSE {free['nrmse_loto']:.4g}): {free['reason']}"
    return msg


def _tie_key(c: Candidate) -> tuple[int, int, float]:
    """The near-tie order of :func:`pick`: fewer parameters pinned at a bound, then fewer parameters, then BIC."""
    return (len(c.at_bound), c.n_params, c.bic)


def _take_tie_break(prob: Problem, base: Candidate, path: list[Candidate], alts: list[dict[str, Any]],
                    base_hold: float) -> None:
    """Apply the step rule's near-tie order to the two-for-one alternatives of the final chain.

    An alternative within ``TIE`` that comes first in :func:`_tie_key` (same number of parameters and a lower BIC:
    a Hertz law's scale and exponent against a stiffness level and a slack) replaces the chain, when each of its
    effects survives the backward pass; otherwise the chain stands.  Either way the pair is reported as confounded.
    """
    full = path[-1]
    better = [a for a in alts if _tie_key(a["cand"]) < _tie_key(full)]
    if not better:
        return
    pick = min(better, key=lambda a: _tie_key(a["cand"]))
    new = _rebuild(prob, base, pick["cand"], base_hold)
    if not _backward(prob, new, base_hold):
        path[:] = new
        rep = pick["report"]  # now the chain's pair is the verdict and the replaced effect the alternative
        rep["pair"], rep["loto"] = rep["pair"][::-1], rep["loto"][::-1]


def _two_for_one(prob: Problem, full: Candidate, allowed: Sequence[str], base_hold: float) -> list[dict[str, Any]]:
    """Stiffness-side effects that the plan cannot tell apart from a pair of others (e.g. a Hertz law with a
    fitted exponent vs a stiffness level plus an offset), each as ``{"report": confounded entry, "cand": the
    alternative's fit}``."""
    out: list[dict[str, Any]] = []
    fam = FAMILIES[0]
    for n in full.names:
        if n not in fam:
            continue
        others = [m for m in fam if m != n and m not in full.names and m in allowed]
        for i, a in enumerate(others):
            for b in others[i + 1:]:
                names = [k for k in full.names if k != n] + [a, b]
                start = {k: v for k, v in full.params.items() if not k.startswith(term_prefix(n))}
                c = _fit_score(prob, names, start, base_hold)
                if c.nrmse_loto <= (1 + TIE) * full.nrmse_loto and not c.at_bound:
                    out.append({"report": {"step": len(full.names), "pair": [n, f"{a}+{b}"],
                                           "loto": [full.nrmse_loto, c.nrmse_loto]}, "cand": c})
    return out


#: a runner-up within this relative LOTO NRMSE of the step's choice is explored one step further
LOOKAHEAD = 0.3


def _look_ahead(prob: Problem, cur: Candidate, chosen: Candidate, cands: list[Candidate], remaining: list[str],
                cached: Any, max_effects: int, fetch: Any = None) -> Candidate:
    """Greedy selection with a one-step look-ahead.

    Two effects can explain part of each other's signature (a delayed Coulomb switch looks like Dahl
    hysteresis with a short travel), so the best single step can block the best pair.  When a runner-up is
    within ``LOOKAHEAD`` of the choice, both are extended by every remaining effect; the runner-up is taken
    when its best extension beats the choice's best extension by more than ``TIE``.  ``fetch(jobs)``, when
    given, fits all those extensions at once first (:func:`prefetch`).
    """
    if len(cur.names) + 2 > max_effects or len(remaining) < 2:
        return chosen
    alts = sorted((c for c in cands if c is not chosen and c.nrmse_loto <= (1 + LOOKAHEAD) * chosen.nrmse_loto),
                  key=lambda c: c.nrmse_loto)[:1]
    if not alts:
        return chosen

    def best_next(c: Candidate) -> float:
        return min(cached(c, n).nrmse_loto for n in remaining if n not in c.names)

    alt = alts[0]
    if fetch is not None:  # both extensions' fits at once (in parallel on a large problem)
        fetch([(c, n) for c in (chosen, alt) for n in remaining if n not in c.names])
    mine = best_next(chosen)
    return alt if best_next(alt) < (1 - TIE) * mine else chosen


#: effects that can stand in for each other (same physical family): the exchange pass swaps within these
FAMILIES = (("stiffness_level", "contact_law", "slack", "machine_compliance"),
            ("friction", "hysteresis", "stribeck", "bouc_wen"))


def prefetch(prob: Problem, cache: dict[tuple[str, ...], Candidate], jobs: Sequence[tuple[Candidate, str]],
             base_hold: float) -> None:
    """Fit and score, into ``cache``, the effect sets ``current + [new]`` of ``jobs`` that it lacks, on forked
    workers (:func:`chainid.infra.forkpool.fork_map`), when the problem says its fits are worth it
    (``prob.parallel_fits``); otherwise nothing: the selection fits them one by one as it reaches them.

    Parameters
    ----------
    prob : Problem
    cache : the selection's fitted effect sets, keyed by their sorted names
    jobs : (current chain's candidate, effect to add) pairs; each set is fitted exactly as :func:`fit_cached`
        would fit it (named in that order, warm-started from the current chain's parameters), the first job
        naming a set winning as in the serial order
    base_hold : the baseline's held-out NRMSE (the shrinkage of each)
    """
    if not getattr(prob, "parallel_fits", False):
        return
    todo: dict[tuple[str, ...], tuple[list[str], dict[str, float]]] = {}
    for cur, n in jobs:
        key = tuple(sorted(cur.names + [n]))
        if key not in cache and key not in todo:
            todo[key] = (cur.names + [n], cur.params)
    if len(todo) < 2:
        return
    stage("selection", f"{len(todo)} effect sets on worker processes")
    fits = fork_map(lambda job: _fit_score(prob, job[0], job[1], base_hold), list(todo.values()))
    cache.update(zip(todo, fits))


def _fit_score(prob: Problem, names: list[str], start: dict[str, float], base_hold: float) -> Candidate:
    """Fit ``names`` (warm-started from ``start``) and score it."""
    return prob.score(prob.fit(names, start=start), names, base_hold)


def _exchange(prob: Problem, full: Candidate, allowed: Sequence[str], base_hold: float) -> tuple[Candidate, list[str]]:
    """Swap a chosen effect for a member of its family when that fits better (LOTO lower by more than TIE, or
    within TIE with fewer parameters) and is identified (rule 4: none of its parameters at a bound of its physical
    range): the first pick of a step is made before later effects are known."""
    swaps: list[str] = []
    for _ in range(2):
        improved = False
        for n in list(full.names):
            fam = next((f for f in FAMILIES if n in f), ())
            for m in fam:
                if m == n or m in full.names or m not in allowed:
                    continue
                names = [m if k == n else k for k in full.names]
                start = {k: v for k, v in full.params.items() if not k.startswith(term_prefix(n))}
                c = _fit_score(prob, names, start, base_hold)
                # rule 4 holds for a swap too: a member whose parameters sit at a bound of their physical range
                # does not fit (Dahl hysteresis with x_h at its floor is Coulomb friction under another name)
                if any(k.startswith(m + ".") for k in c.at_bound):
                    continue
                better = c.nrmse_loto < (1 - TIE) * full.nrmse_loto or (
                    c.nrmse_loto <= (1 + TIE) * full.nrmse_loto
                    and (len(c.at_bound), c.n_params) < (len(full.at_bound), full.n_params))
                if better:
                    swaps.append(f"{n} -> {m}")
                    full, improved = c, True
                    break
        if not improved:
            break
    return full, swaps


def _rebuild(prob: Problem, base: Candidate, final: Candidate, base_hold: float) -> list[Candidate]:
    """The explanation chain for the effect set of ``final``, ordered greedily (largest LOTO drop first)."""
    left = list(final.names)
    path = [base]
    while left:
        if len(left) == 1:  # the final fit, named in the chain's order
            ck = final
            ck.name = "+".join(path[-1].names + left)
        else:
            cands = []
            for n in left:
                sub = path[-1].names + [n]
                start = {k: v for k, v in final.params.items() if k.split(".", 1)[0] in sub or k.startswith("spring.")}
                cands.append(_fit_score(prob, sub, start, base_hold))
            ck = min(cands, key=lambda c: c.nrmse_loto)
        prev = path[-1]
        ck.step_test = step_test(prev, ck)  # type: ignore[attr-defined]
        path.append(ck)
        left.remove(ck.names[-1])
    return path


def _backward(prob: Problem, path: list[Candidate], base_hold: float) -> list[str]:
    """Drop effects made redundant by later ones (refit without each; drop if not significantly worse)."""
    dropped: list[str] = []
    while len(path[-1].names) >= 2:
        full = path[-1]
        best_drop = None
        for n in full.names:
            rest = [m for m in full.names if m != n]
            start = {k: v for k, v in full.params.items() if not k.startswith(term_prefix(n))}
            c = _fit_score(prob, rest, start, base_hold)
            if not passes(step_test(c, full)):
                if best_drop is None or c.nrmse_loto < best_drop[1].nrmse_loto:
                    best_drop = (n, c)
        if best_drop is None:
            break
        n, c = best_drop
        dropped.append(n)
        path[:] = _rebuild(prob, path[0], c, base_hold)
    return dropped


def baseline_candidate(prob: Any) -> Candidate:
    """The scored baseline (no effect) the selection starts from: a base with free parameters fitted on the training
    data (a linear spring re-fitted with ``--model linear``; the time domain's dashpot, mass and spring) or the chain
    model as given; shrinkage 0 by definition."""
    fits = getattr(prob, "fits_base", not prob.is_chain)  # a base with free parameters is fitted first
    base_c = prob.fit([]) if fits else Candidate("baseline", {}, 0)
    base_c.name = "baseline"
    prob.score(base_c, [], 1.0)
    base_c.shrinkage = 0.0
    return base_c


def library(prob: Any, effects: Sequence[str] | None) -> list[str]:
    """The library effects the selection considers: those that apply to the problem (restricted to ``effects``
    when given), aliases of the same physics removed."""
    names = [n for n in prob.applicable() if effects is None or n in effects]
    for alias, canon in ALIASES.items():
        if alias in names and canon in names:
            names.remove(alias)
    return names
