"""Forward selection conditional on what is already explained (the explanation chain).

Step k fits every remaining library effect *on top of* the model of step k−1 —
all parameters refitted jointly, the damping law re-identified — and scores it
leave-one-test-out (LOTO) over the training tests.  The best candidate is kept
when the improvement is significant; then a backward pass drops any earlier
effect that the later ones made redundant.

The acceptance rule and the near-tie order live in :mod:`chainid.gap.core.steprule`; the final chain's second
look (exchanges, backward pass, alternatives) in :mod:`chainid.gap.core.refine`.
"""

from __future__ import annotations

from typing import Any, Sequence

from chainid.gap.core.candidate import Candidate, Problem
from chainid.gap.core.refine import second_look
from chainid.gap.core.steprule import (ALIASES, FAMILIES, LOOKAHEAD, MIN_GAIN, NONE_FRACTION, TIE, Z, at_noise_floor,
                                      fit_cached, fit_score, look_ahead, loto_jackknife, passes, pick, pinned_params,
                                      step_test, takes, term_prefix, train_floor)
from chainid.infra.forkpool import fork_map
from chainid.infra.progress import stage

__all__ = ["ALIASES", "FAMILIES", "LOOKAHEAD", "MIN_GAIN", "NONE_FRACTION", "TIE", "Z", "at_noise_floor",
           "baseline_candidate", "fit_cached", "fit_score", "forward_select", "library", "loto_jackknife", "passes",
           "pick", "pinned_params", "prefetch", "rejections", "step_test", "stop_message", "term_prefix",
           "train_floor"]


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
        return fit_cached(cache, lambda names_k: fit_score(prob, names_k, cur.params, base_hold), cur.names + [n])

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
        passing = [c for c in cands if takes(c, c.step_test)]  # type: ignore[attr-defined]
        if not passing:
            rejected = rejections(cands)
            stop = stop_message(rejected)
            break
        chosen, ties = pick(passing)
        chosen = look_ahead(cur.names, chosen, passing, remaining, max_effects, cached,
                            lambda c: train_floor(prob, c), lambda jobs: prefetch(prob, cache, jobs, base_hold))
        for t in ties:
            confounded.append({"step": len(path), "pair": [chosen.names[-1], t.names[-1]],
                               "loto": [chosen.nrmse_loto, t.nrmse_loto]})
        path.append(chosen)
        cur = chosen
        remaining.remove(chosen.names[-1])
    out = second_look(prob, path, names, base_hold, cache, max_effects)
    return {"path": path, "singles": singles, "stop": stop + out["stop"], "rejected": rejected,
            "confounded": confounded + out["confounded"], "dropped": out["dropped"], "swapped": out["swapped"],
            "_cache": cache}


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
    fits = fork_map(lambda job: fit_score(prob, job[0], job[1], base_hold), list(todo.values()))
    cache.update(zip(todo, fits))


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
