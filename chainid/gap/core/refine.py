"""The final chain's second look: family exchanges, the backward pass, and the alternatives that explain as
much with as few parameters.

* :func:`exchange` swaps a chosen effect for a member of its family that fits better (the first pick of a step is
  made before later effects are known);
* :func:`backward` drops an effect that later ones made redundant;
* :func:`two_for_one` finds stiffness-side pairs the plan cannot tell from one effect, and :func:`take_tie_break`
  applies the near-tie order to them;
* :func:`split_richer` replaces a richer effect (Stribeck, Bouc–Wen) by its simpler member plus a second cause;
* :func:`rebuild` orders an effect set as an explanation chain (largest LOTO drop first);
* :func:`second_look` runs them in order on the final chain.
"""

from __future__ import annotations

from typing import Any, Sequence

from chainid.gap.core.candidate import Candidate, Problem
from chainid.gap.core.steprule import (FAMILIES, SIMPLER, TIE, fit_score, near_tie_first, passes, refuted_member,
                                      split_acceptable, step_test, swap_acceptable, term_prefix, tie_key)


def exchange(prob: Problem, full: Candidate, allowed: Sequence[str], base_hold: float,
             cache: dict[tuple[str, ...], Candidate] | None = None) -> tuple[Candidate, list[str]]:
    """Swap a chosen effect for a member of its family when that fits better (LOTO lower by more than TIE, or
    within TIE with fewer parameters) and is identified (rule 4: none of its parameters at a bound of its physical
    range): the first pick of a step is made before later effects are known.  Every set fitted is added to
    ``cache`` when given (a resample's replay chooses among them)."""
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
                c = fit_score(prob, names, start, base_hold)
                if cache is not None:
                    cache.setdefault(tuple(sorted(names)), c)
                if swap_acceptable(c, full, m) and not refuted_member(c, names, m, (cache or {}).get):
                    swaps.append(f"{n} -> {m}")
                    full, improved = c, True
                    break
        if not improved:
            break
    return full, swaps


def rebuild(prob: Problem, base: Candidate, final: Candidate, base_hold: float) -> list[Candidate]:
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
                cands.append(fit_score(prob, sub, start, base_hold))
            ck = min(cands, key=lambda c: c.nrmse_loto)
        prev = path[-1]
        ck.step_test = step_test(prev, ck)  # type: ignore[attr-defined]
        path.append(ck)
        left.remove(ck.names[-1])
    return path


def backward(prob: Problem, path: list[Candidate], base_hold: float) -> list[str]:
    """Drop effects made redundant by later ones (refit without each; drop if not significantly worse)."""
    dropped: list[str] = []
    while len(path[-1].names) >= 2:
        full = path[-1]
        best_drop = None
        for n in full.names:
            rest = [m for m in full.names if m != n]
            start = {k: v for k, v in full.params.items() if not k.startswith(term_prefix(n))}
            c = fit_score(prob, rest, start, base_hold)
            if not passes(step_test(c, full)):
                if best_drop is None or c.nrmse_loto < best_drop[1].nrmse_loto:
                    best_drop = (n, c)
        if best_drop is None:
            break
        n, c = best_drop
        dropped.append(n)
        path[:] = rebuild(prob, path[0], c, base_hold)
    return dropped


def two_for_one(prob: Problem, full: Candidate, allowed: Sequence[str], base_hold: float) -> list[dict[str, Any]]:
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
                c = fit_score(prob, names, start, base_hold)
                if c.nrmse_loto <= (1 + TIE) * full.nrmse_loto and not c.at_bound:
                    out.append({"report": {"step": len(full.names), "pair": [n, f"{a}+{b}"],
                                           "loto": [full.nrmse_loto, c.nrmse_loto]}, "cand": c})
    return out


def take_tie_break(prob: Problem, base: Candidate, path: list[Candidate], alts: list[dict[str, Any]],
                    base_hold: float) -> None:
    """Apply the step rule's near-tie order to the two-for-one alternatives of the final chain.

    An alternative within ``TIE`` that comes first in :func:`tie_key` (same number of parameters and a lower BIC:
    a Hertz law's scale and exponent against a stiffness level and a slack) replaces the chain, when each of its
    effects survives the backward pass; otherwise the chain stands.  Either way the pair is reported as confounded.
    """
    full = path[-1]
    better = [a for a in alts if tie_key(a["cand"]) < tie_key(full)]
    if not better:
        return
    pick = min(better, key=lambda a: tie_key(a["cand"]))
    new = rebuild(prob, base, pick["cand"], base_hold)
    if not backward(prob, new, base_hold):
        path[:] = new
        rep = pick["report"]  # now the chain's pair is the verdict and the replaced effect the alternative
        rep["pair"], rep["loto"] = rep["pair"][::-1], rep["loto"][::-1]


#: next effects tried with the simpler member: the best of the last round's candidates by LOTO
N_SPLIT = 3


def split_richer(prob: Problem, path: list[Candidate], cache: dict[tuple[str, ...], Candidate],
                 allowed: Sequence[str], base_hold: float, max_effects: int) -> dict[str, Any] | None:
    """Replace a richer effect of the final chain by its simpler member plus a next effect, when that explains as
    much with no more parameters.

    A richer effect's extra parameters can stand in for a second cause (a Stribeck peak and asymmetry for a slack
    at the stroke's end), and then the second cause no longer passes the step rule on top of it.  For each richer
    effect n of the chain (:data:`~chainid.gap.core.steprule.SIMPLER`) and each of the ``N_SPLIT`` best next
    effects x of the last round (by LOTO, from ``cache``; x neither in the chain nor n's simpler member), the chain
    with n → SIMPLER[n] plus x is fitted.  It replaces the chain when it has no more parameters, is identified (no parameter of the new effects at
    a bound), its LOTO is lower by more than ``TIE`` or within ``TIE`` and first in the near-tie order
    (:func:`~chainid.gap.core.steprule.tie_key`), and every effect of it survives the backward pass.

    Parameters
    ----------
    prob : the diagnosis problem (fits and scores effect sets)
    path : the explanation chain, baseline first; rebuilt in place on a replacement
    cache : the selection's fitted sets by sorted names; every set fitted here is added
    allowed : the library effects the selection may name
    base_hold : the baseline's held-out NRMSE (for the shrinkage)
    max_effects : most effects in a chain

    Returns
    -------
    dict or None
        The confounded-pair report of a replacement (``step``, ``pair`` [the split, the richer effect], ``loto``),
        else None.
    """
    full = path[-1]
    if len(full.names) + 1 > max_effects:
        return None
    nexts = sorted((c for k, c in cache.items() if len(k) == len(full.names) + 1 and set(full.names) <= set(k)),
                   key=lambda c: c.nrmse_loto)
    order = [next(n for n in c.names if n not in full.names) for c in nexts]
    tried: list[tuple[Candidate, str, str, str]] = []
    for n in full.names:
        a = SIMPLER.get(n)
        if a is None or a in full.names or a not in allowed:
            continue
        start = {k: v for k, v in full.params.items() if not k.startswith(term_prefix(n))}
        for x in [x for x in order if x != a and x in allowed][:N_SPLIT]:
            names = [a if k == n else k for k in full.names] + [x]
            c = fit_score(prob, names, start, base_hold)
            cache.setdefault(tuple(sorted(names)), c)
            if split_acceptable(c, full, (a, x)):
                tried.append((c, n, a, x))
    if not tried:
        return None
    for c, n, a, x in near_tie_first(tried):  # near-ties to the best go by the near-tie order, as in a step
        new = rebuild(prob, path[0], c, base_hold)
        if backward(prob, new, base_hold):
            continue
        path[:] = new
        return {"step": len(c.names), "pair": [f"{a}+{x}", n], "loto": [c.nrmse_loto, full.nrmse_loto]}
    return None


def split_text(split: dict[str, Any]) -> str:
    """The stop text's account of a split (:func:`split_richer`'s report)."""
    return (f"; then {split['pair'][1]} was split into {split['pair'][0]}: as good a fit (LOTO NRMSE "
            f"{split['loto'][0]:.4g} against {split['loto'][1]:.4g}) with no more parameters")


def second_look(prob: Problem, path: list[Candidate], allowed: Sequence[str], base_hold: float,
                cache: dict[tuple[str, ...], Candidate], max_effects: int) -> dict[str, Any]:
    """The final chain's second look, in order: the family exchange (chains of two or more effects), the backward
    pass, the split of a richer effect, and the two-for-one alternatives with the near-tie break.  ``path`` (baseline
    first) is rebuilt in place; every set fitted goes into ``cache``, and so do the final chain's (a resample's
    replay chooses among them).  Returns ``dropped`` and ``swapped`` (lists of str), ``confounded`` (reports) and
    ``stop`` (text to add to the forward steps' stop message)."""
    base = path[0]
    swaps: list[str] = []
    if len(path) > 2:
        final, swaps = exchange(prob, path[-1], allowed, base_hold, cache)
        if swaps:
            path[:] = rebuild(prob, base, final, base_hold)
    dropped = backward(prob, path, base_hold)
    confounded, stop = [], ""
    split = split_richer(prob, path, cache, allowed, base_hold, max_effects)
    if split is not None:
        confounded.append(split)
        swaps.append(f"{split['pair'][1]} -> {split['pair'][0]}")
        stop = split_text(split)
    alts = two_for_one(prob, path[-1], allowed, base_hold)
    confounded += [a["report"] for a in alts]
    take_tie_break(prob, base, path, alts, base_hold)
    for c in path[1:]:
        cache.setdefault(tuple(sorted(c.names)), c)
    return {"dropped": dropped, "swapped": swaps, "confounded": confounded, "stop": stop}
