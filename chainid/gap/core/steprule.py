"""The step rule of the explanation chain: when a candidate effect earns its place, and the near-tie order.

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


def significant(st: dict[str, float]) -> bool:
    """Rule 2: the mean log error ratio over the training units above ``Z`` jack-knife SE."""
    return st["delta_loto"] > Z * st["se_jackknife"]


def passes(st: dict[str, float]) -> bool:
    """Rules 2 and 3: significant over tests (> ``Z`` jack-knife SE) and material (>= ``MIN_GAIN``)."""
    return significant(st) and st["relative_gain"] >= MIN_GAIN


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


def pinned_params(c: Candidate, new: str | None = None) -> list[str]:
    """The parameters of the candidate's term ``new`` (default: its newest) pinned at a bound of their physical
    range."""
    if new is None:
        if not c.names:
            return []
        new = c.names[-1]
    pre = term_prefix(new)
    return [k for k in c.at_bound if k.startswith(pre)]


def takes(c: Candidate, st: dict[str, float], new: str | None = None) -> bool:
    """Rules 2-4 for a step to ``c`` with step-test numbers ``st`` (:func:`step_test`): significant, material, and
    the parameters of the term it adds (``new``, default its newest) inside their bounds."""
    return not pinned_params(c, new) and passes(st)


def newest(c: Any, chain: Sequence[str]) -> str:
    """The term a step candidate ``c`` adds to ``chain`` (its one name not in the chain)."""
    return next(n for n in c.names if n not in chain)


#: a runner-up within this relative LOTO NRMSE of the step's choice is explored one step further
LOOKAHEAD = 0.3


def look_ahead(chain: Sequence[str], chosen: Any, cands: Sequence[Any], remaining: Sequence[str], max_effects: int,
               extend: Any, at_floor: Any, fetch: Any = None) -> Any:
    """The step's choice after a one-step look-ahead (the forward selection's and its replay on a resample's).

    Two effects can explain part of each other's signature (a delayed Coulomb switch looks like Dahl hysteresis
    with a short travel), so the best single step can block the best pair.  When a runner-up is within
    ``LOOKAHEAD`` of the choice, both are extended by every remaining effect; the runner-up is taken when its best
    extension beats the choice's best extension by more than ``TIE``.  An extension counts only when the step rule
    would take it (above the training noise floor, significant, material, its parameters inside their bounds): a
    path whose better next step the rule forbids ends where it is.  A runner-up that nests the choice or is nested
    in it (:data:`NESTS`: Stribeck and Coulomb friction, Bouc–Wen and Dahl hysteresis or Jenkins friction) is not
    explored when the chain leaves room for a later split: between nested shapes significance decides
    (:func:`pick`, and the final chain's exchange and split); the best other runner-up within ``LOOKAHEAD`` is.

    Parameters
    ----------
    chain : the current chain's terms; ``chosen`` and ``cands`` (the candidates the rule takes) each add one
    remaining : the library terms not in the chain
    extend : ``extend(c, n)`` → the scored candidate of c's terms plus n, or None when there is none (a replay among
        the diagnosis' fits: then no look-ahead, the paths could not be compared alike)
    at_floor : ``at_floor(c)`` → whether c's training residual is at the noise floor (rule 1: the chain ends at c)
    fetch : ``fetch(jobs)``, when given, fits every ``(c, n)`` extension of the choice and the runner-up at once
    """
    if len(chain) + 2 > max_effects or len(remaining) < 2:
        return chosen
    new = newest(chosen, chain)
    # a nested runner-up is left to pick's rule and the final chain's exchange and split, when the chain leaves them
    # room: one more step and a split's extra effect (else it is explored here, as any runner-up: its path's chain
    # of two is then judged again by the exchange, between nested shapes by the step rule)
    nested = ({new} | set(NESTS.get(new, ())) | {k for k, v in NESTS.items() if new in v}
              if len(chain) + 2 < max_effects else {new})
    alts = sorted((c for c in cands if c is not chosen and newest(c, chain) not in nested
                   and c.nrmse_loto <= (1 + LOOKAHEAD) * chosen.nrmse_loto), key=lambda c: c.nrmse_loto)[:1]
    if not alts:
        return chosen

    def best_next(c: Any) -> float | None:
        """Where the path through c gets in one more step: the lowest LOTO of the extensions the step rule would
        take (c above its training noise floor, then rules 2-4), else c's own (the chain would stop at c); None
        when an extension was not fitted (a replay)."""
        if at_floor(c):
            return c.nrmse_loto
        here = set(chain) | {newest(c, chain)}
        ext = [(extend(c, n), n) for n in remaining if n not in here]
        if any(e is None for e, _ in ext):
            return None
        return min((e.nrmse_loto for e, n in ext if takes(e, step_test(c, e), n)), default=c.nrmse_loto)

    alt = alts[0]
    if fetch is not None:  # both extensions' fits at once (in parallel on a large problem)
        fetch([(c, n) for c in (chosen, alt) for n in remaining if n not in c.names])
    mine = best_next(chosen)
    theirs = best_next(alt) if mine is not None else None
    if mine is None or theirs is None:  # the paths cannot be compared alike
        return chosen
    return alt if theirs < (1 - TIE) * mine else chosen


def pick(cands: list[Candidate]) -> tuple[Candidate, list[Candidate]]:
    """Best LOTO candidate; near-ties go to the one with fewer parameters pinned at a physical bound (a
    pinned parameter means the effect's form does not fit), then fewer parameters, then BIC.  A richer shape that
    does not beat a member it nests by the step rule (:func:`nested_simpler`) is given up and the choice made again
    among the others, less the members it nests that it beats significantly (:func:`beaten_member`).  Returns
    (chosen, the others it was chosen over: the near-ties, and a richer shape given up for it)."""
    cands = sorted(cands, key=lambda c: c.nrmse_loto)
    given_up: list[Candidate] = []
    while True:
        best = cands[0]
        ties = [c for c in cands if c.nrmse_loto <= (1 + TIE) * best.nrmse_loto]
        chosen = min(ties, key=lambda c: (len(c.at_bound), c.n_params, c.bic))
        if nested_simpler(chosen, cands) is None:
            break
        given_up.append(chosen)
        cands = [c for c in cands if c is not chosen and not beaten_member(chosen, c)]
    rivals = [g for g in given_up if nested_pair(g, chosen) is not None]
    return chosen, [c for c in ties if c is not chosen] + rivals


#: the library members a richer effect reduces to in a limit of its shape: Bouc–Wen is Dahl hysteresis at n = r = 1
#: and a Jenkins friction (elastic stick, then sliding; no load-dependent part μ) as n → ∞ with r = ½; Stribeck
#: friction without its static peak and direction asymmetry is Coulomb friction (no stick travel, no μ)
NESTS = {"bouc_wen": ("hysteresis", "friction"), "stribeck": ("friction",)}
#: the simpler member a richer effect is split into (:func:`chainid.gap.core.refine.split_richer`), the first of NESTS
SIMPLER = {k: v[0] for k, v in NESTS.items()}
#: a friction parameter at most this is read as absent when friction is compared with a shape that has no such part
#: (μ [-]; x_s [mm]: 0.1 µm, below any stick travel a record resolves)
NESTED_ZERO = {"friction.mu": 1e-4, "friction.x_s": 1e-4}


def nested_pair(richer: Any, simpler: Any) -> tuple[str, str] | None:
    """``(richer effect, simpler effect)`` when the two candidates differ in one effect each, the first's nests the
    second's (:data:`NESTS`) and the simpler one's fitted parts that the richer shape lacks are absent
    (:data:`NESTED_ZERO`: a friction's μ, and against Stribeck its stick travel x_s); else None.  Compared as sets
    of terms: a resample's replay keeps the order in which a set was first fitted."""
    a, b = set(richer.names) - set(simpler.names), set(simpler.names) - set(richer.names)
    if len(a) != 1 or len(b) != 1:
        return None
    (r,), (m,) = a, b
    if m not in NESTS.get(r, ()):
        return None
    lacks = ["friction.mu"] + (["friction.x_s"] if r == "stribeck" else [])
    params = getattr(simpler, "params", {}) or {}
    if m == "friction" and any(abs(params.get(k, 0.0)) > NESTED_ZERO[k] for k in lacks):
        return None
    return r, m


def nested_simpler(chosen: Any, cands: Sequence[Any]) -> Any | None:
    """The simpler rival that ``chosen`` has to give way to, or None.

    A rival is a candidate that differs from ``chosen`` only by a member its richer effect nests
    (:func:`nested_pair`), with no parameter of that member at a bound and fewer parameters.  The richer shape is
    named only where the data show its extra shape parameters: its improvement over the simpler rival significant
    over the training units (:func:`significant` of :func:`step_test` from the rival to it; the materiality bar,
    a tenth of what is left, is for naming one more effect, not for the shape of one: at a high signal-to-noise
    ratio a Bouc–Wen knee 8 % below a Jenkins friction is real).  Otherwise the data do not tell the shapes apart
    and the simpler one, the best-fitting such rival by LOTO, is named.
    """
    rivals = []
    for c in cands:
        pair = nested_pair(chosen, c) if c is not chosen else None
        if pair is not None and not pinned_params(c, pair[1]) and c.n_params < chosen.n_params:
            rivals.append(c)
    rivals = [c for c in sorted(rivals, key=lambda c: c.nrmse_loto) if not significant(step_test(c, chosen))]
    return rivals[0] if rivals else None


def beaten_member(given_up: Any, c: Any) -> bool:
    """Whether ``c`` is a member nested in ``given_up`` (:func:`nested_pair`) that ``given_up`` beats significantly
    over the training units.  A richer shape is given up for a member it does not beat; a member it does beat is
    refuted by the same data (Bouc–Wen no better than a Jenkins friction but significantly better than Dahl
    hysteresis names the friction, even where the hysteresis sits within the near-tie band of it)."""
    return nested_pair(given_up, c) is not None and significant(step_test(c, given_up))


def refuted_member(c: Any, names: Sequence[str], new: str, fitted: Any) -> bool:
    """Whether swapping to ``new`` (``c``: ``names`` with ``new`` in) is refuted by a richer shape that nests it: the
    set with that shape in ``new``'s place was fitted (``fitted(key)``, its sorted names, gives its candidate, or
    None), its own parameters inside their bounds, and it beats ``c`` significantly (:func:`beaten_member`).  The
    exchange pass asks this of a family swap as ``pick`` does of its second choice: a Bouc–Wen given up for a
    friction, but significantly better than Dahl hysteresis, keeps the hysteresis out."""
    for richer, members in NESTS.items():
        if new not in members or richer in names:
            continue
        r = fitted(tuple(sorted(richer if k == new else k for k in names)))
        if r is not None and not pinned_params(r, richer) and beaten_member(r, c):
            return True
    return False


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


#: effects that can stand in for each other (same physical family): the exchange pass swaps within these
FAMILIES = (("stiffness_level", "contact_law", "slack", "machine_compliance"),
            ("friction", "hysteresis", "stribeck", "bouc_wen"))


def tie_key(c: Candidate) -> tuple[int, int, float]:
    """The near-tie order of :func:`pick`: fewer parameters pinned at a bound, then fewer parameters, then BIC."""
    return (len(c.at_bound), c.n_params, c.bic)


def fit_score(prob: Problem, names: list[str], start: dict[str, float], base_hold: float) -> Candidate:
    """Fit ``names`` (warm-started from ``start``) and score it."""
    return prob.score(prob.fit(names, start=start), names, base_hold)


def split_acceptable(c: Any, full: Any, new: Sequence[str]) -> bool:
    """Whether a split ``c`` (a richer effect of ``full`` replaced by its simpler member plus a next effect; ``new``
    the two effects it brings) may replace ``full``: no more parameters, none of the new effects' parameters at a
    bound, and a LOTO lower by more than ``TIE`` or within it and first in the near-tie order (:func:`tie_key`).
    Both need ``nrmse_loto``, ``n_params``, ``at_bound`` and ``bic``."""
    if c.n_params > full.n_params or any(k.startswith(tuple(term_prefix(n) for n in new)) for k in c.at_bound):
        return False
    return c.nrmse_loto < (1 - TIE) * full.nrmse_loto or (
        c.nrmse_loto <= (1 + TIE) * full.nrmse_loto and tie_key(c) < tie_key(full))


def near_tie_first(cands: Sequence[Any]) -> list[Any]:
    """``cands`` (each ``(candidate, …)``) with those within ``TIE`` of the best LOTO first, in the near-tie order,
    then the others, in the same order."""
    best = min(t[0].nrmse_loto for t in cands)
    return sorted(cands, key=lambda t: (t[0].nrmse_loto > (1 + TIE) * best, tie_key(t[0])))


def swap_acceptable(c: Any, full: Any, new: str) -> bool:
    """Whether ``c`` (``full`` with one effect swapped for ``new``, a member of its family) may replace ``full``:
    none of ``new``'s parameters at a bound of its physical range (rule 4 holds for a swap too: Dahl hysteresis with
    x_h at its floor is Coulomb friction under another name), and a LOTO lower by more than ``TIE``, or within it
    with fewer parameters pinned at a bound or fewer parameters.  Between an effect and a member it nests
    (:data:`NESTS`) significance decides, as in :func:`nested_simpler`: the richer one comes in only when it is
    significantly better than the simpler one over the training units, and gives way to it when it is not.  Both
    need ``nrmse_loto``, ``n_params``, ``at_bound`` and ``loto_num``."""
    if any(k.startswith(term_prefix(new)) for k in c.at_bound):
        return False
    if nested_pair(c, full) is not None:  # to the richer shape: the data must show its shape
        return significant(step_test(full, c))
    if nested_pair(full, c) is not None and c.n_params < full.n_params:  # to the simpler shape
        return not significant(step_test(c, full))
    return c.nrmse_loto < (1 - TIE) * full.nrmse_loto or (
        c.nrmse_loto <= (1 + TIE) * full.nrmse_loto
        and (len(c.at_bound), c.n_params) < (len(full.at_bound), full.n_params))
