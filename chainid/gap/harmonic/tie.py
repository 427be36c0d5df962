"""A step's damping tied to its law: a step scored with one viscous c for every test has its effect parameters
refitted with every training test's c_e given by that law instead of each test's own projection, when the tests do
not refute the tie.

Why.  The harmonic route fits an effect set with each test's c_e free (the paper's per-test damping, Eq. 27 on
the cycle-averaged loop).  A dissipative effect's first harmonic is then spent twice: c_e·ẋ of one sine test is
exactly the quadrature first harmonic of a friction, so a friction force is identified from its higher harmonics
alone (the corners of its loop), and the parameters of a shaped friction (Stribeck's F_c, ΔF_s, v_s) trade
against each other there.  With c_e tied to one c for every test, the friction's first harmonic, 4·F_c/(π·ω·A) on
each test, is the friction's again.

Only the one law that does not vary with the test is tied to: ``viscous``, one c for every test.  A law that
varies with ω or A can take up part of a dissipative effect's first harmonic, which varies with them too — the
Coulomb law exactly, the paper's Eq. 21 polynomial in part over a plan's range — so a tie to it would move the
effect instead of informing it.

The tie is kept when the tests do not refute it: the nested-model F test of the training χ² with each test's own c_e
(n_train of them) against the law's coefficients (fewer), at :data:`LEVEL`; the noise scale is the free fit's χ² per
degree of freedom.  A tie that pins a parameter at a bound the free fit did not, or under which the chain would not
pass the step rule, is not kept.  A kept tie gives the step's parameters (the point estimate), and the step is
scored again with them.  Everything else keeps each test's own c_e: the selection (its fits, its scores, the
resamples' replay of it) and the uncertainty (jack-knife, resample refits, profiles).  The intervals thus do not
lean on the tie: the resampled interval, recentred on the reported estimate as every one is, has the width of the
free fit, and the profile is the free fit's.  That is wider than the tied estimate's own scatter where the tie holds
(backlash on the harmonic grid: the free profile's half-width over 1.645 is 1.6 times the tied estimate's rms error
over 25 noise seeds, ``python benchmarks/interval_scatter.py --case harmonic/single/backlash --param backlash.b``),
and the intervals of the tied fit itself were tried: on the harmonic grid's seed 0 (``chainid benchmark-gap
--excitations harmonic --resamples 200 --seed 0``) they covered backlash in 30 of 33 cases (32 free) but friction's
F_c in 21 of 32 (31 free), every miss on the low side.  F_c is biased low by the noise where its partner μ sits
at its bound of no effect, as it does in the grid's truth: without noise the fit is exact
(``tests/gap/harmonic/test_damping_tie.py``); with 1 % force noise one case's F_c came out 1.1 % low with μ =
1.0·10⁻⁴, and the tied χ² put the true F_c (μ refitted to its bound) just past the level.  A bound of no effect
makes the profile's χ² steeper on the side the bound blocks.  No resample sees a bias that every fit shares; the
free fit's wider intervals take it in.

Units: χ² dimensionless; parameters in their own units.
"""

from __future__ import annotations

import copy
from typing import Any

from scipy.stats import f as f_dist

from chainid.gap.core.steprule import passes, step_test

__all__ = ["LEVEL", "TIED_LAW", "f_test", "tie_damping", "tie_path"]

#: confidence level of the F test that refutes a tie
LEVEL = 0.95
#: the one damping law a step's c_e is tied to (it does not vary with the test)
TIED_LAW = "viscous"


def f_test(chi2_free: float, chi2_tied: float, n: int, p_free: int, p_tied: int) -> tuple[float, float]:
    """The F statistic of a nested least-squares fit (the tied one, ``p_tied`` fitted values, within the free one,
    ``p_free``; ``n`` residuals) and its critical value at :data:`LEVEL`."""
    dnu, nu = p_free - p_tied, n - p_free
    if dnu <= 0 or nu <= 0 or chi2_free <= 0:
        return float("inf"), 0.0
    stat = (max(chi2_tied - chi2_free, 0.0) / dnu) / (chi2_free / nu)
    return float(stat), float(f_dist.ppf(LEVEL, dnu, nu))


def tie_damping(prob: Any, cand: Any, base_hold: float) -> Any:
    """A step's candidate with its c_e tied to :data:`TIED_LAW` (a scored copy, ``tied_law`` naming the law), or
    None: the step is not scored with that law, or the training tests refute the tie (F test), or the tied fit
    pins a parameter at a bound the free fit did not.  The copy is scored as every step is (each test's c_e its
    projection, the law fitted on them; LOTO and held-out from the law), at the tied parameters."""
    names = list(cand.names)
    if not names or cand.law != TIED_LAW:
        return None
    chi2_free, n, p_free = prob.train_chi2(names, cand.params)
    with prob.tied(names, TIED_LAW):  # the tie is the point estimate's alone: later fits leave each c_e free
        tied = prob.fit(names, start=cand.params)
        chi2_tied, _, p_tied = prob.train_chi2(names, tied.params)
    stat, crit = f_test(chi2_free, chi2_tied, n, p_free, p_tied)
    if stat > crit or not set(tied.at_bound) <= set(cand.at_bound):
        return None
    new = prob.score(tied, names, base_hold, laws=[TIED_LAW])
    new.name = cand.name
    new.tied_law = TIED_LAW
    return new


def tie_path(prob: Any, path: list[Any], base_hold: float) -> list[Any]:
    """The explanation chain with each step's c_e tied where :func:`tie_damping` allows and the chain still passes
    the step rule (rules 2 and 3 of :mod:`chainid.gap.core.steprule`, each step against the one before, both as
    reported): a tie under which the step, or the step after it, would not have been taken is undone.  Every step
    gets its ``step_test`` against the step before as reported; the candidates of the selection (its cache, its
    single effects) are left as they were fitted."""
    out = [path[0]]
    for i, c in enumerate(path[1:], start=1):
        t = tie_damping(prob, c, base_hold)
        if t is not None:
            after = path[i + 1] if i + 1 < len(path) else None
            ok = passes(step_test(out[-1], t)) and (after is None or passes(step_test(t, after)))
            if not ok:
                t = None
        nxt = t if t is not None else copy.copy(c)  # (a tied candidate is already a new object)
        nxt.step_test = step_test(out[-1], nxt)  # type: ignore[attr-defined]
        out.append(nxt)
    return out
