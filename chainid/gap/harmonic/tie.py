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
Coulomb law exactly, the paper's Eq. 21 polynomial in part over a plan's range — so a tie to it moves the effect
instead of informing it: tied to the polynomial law on the harmonic benchmark grid (a viscous device), friction's
F_c came out 1–3 % low and its 90 % intervals covered 20 of 32 true values, against 29 of 32 with each test's own
c_e (``chainid benchmark-gap --excitations harmonic --resamples 200``).

The tie is kept when the tests do not refute it: the nested-model F test of the training χ² with each test's own
c_e (n_train of them) against the law's coefficients (fewer), at :data:`LEVEL`; the noise scale is the free fit's
χ² per degree of freedom.  A tie that pins a parameter at a bound the free fit did not is not kept.  A kept tie
applies to every later fit of the step's effect set (jack-knife, resamples, profiles:
:attr:`chainid.gap.harmonic.problem.Problem.ties`), and the step is scored again with its tied parameters and
law.

Units: χ² dimensionless; parameters in their own units.
"""

from __future__ import annotations

from typing import Any

from scipy.stats import f as f_dist

from chainid.gap.harmonic import law_choice as L

__all__ = ["LEVEL", "TIED_LAW", "tie_damping", "f_test"]

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


def tie_damping(prob: Any, cand: Any, base_hold: float) -> bool:
    """Tie a step's c_e to its damping law where it is :data:`TIED_LAW` and the training tests allow it; the
    candidate is refitted and scored again in place (``cand.tied_law`` names the law).  Returns whether the tie was
    kept."""
    names = tuple(cand.names)
    law = cand.law
    if not names or law != TIED_LAW or L.LAWS[law] >= len(prob.train):
        return False
    chi2_free, n, p_free = prob.train_chi2(list(names), cand.params)
    prob.ties[names] = law
    tied = prob.fit(list(names), start=cand.params)
    chi2_tied, _, p_tied = prob.train_chi2(list(names), tied.params)
    stat, crit = f_test(chi2_free, chi2_tied, n, p_free, p_tied)
    if stat > crit or not set(tied.at_bound) <= set(cand.at_bound):
        del prob.ties[names]
        return False
    new = prob.score(tied, list(names), base_hold, laws=[law])
    keep = {"param_sd", "step_test"}
    cand.__dict__.update({k: v for k, v in new.__dict__.items() if k not in keep})
    cand.tied_law = law
    return True
