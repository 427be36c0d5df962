"""The harmonic route of ``chainid diagnose``: steady harmonic tests folded into phase bins.

Problem (:mod:`.problem`) → baseline → where it misses (:mod:`.where`) → the explanation chain by forward selection
(:mod:`chainid.gap.core.selection`) → what is left: dB over noise and stationarity
(:mod:`chainid.gap.core.stationarity`) → verdict (:mod:`chainid.gap.core.verdict`).  Parameter standard deviations
come from leave-one-test-out refits (a jack-knife over the training tests).

Units: mm, N, s.
"""

from __future__ import annotations

import math
import warnings
from typing import Any, Sequence

import numpy as np

from chainid.gap.core import selection as fw
from chainid.gap.core.candidate import Candidate, jackknife_sd
from chainid.gap.core.interpret import interpretation, separating_test
from chainid.gap.core.openworld import open_world
from chainid.gap.core.profile import attach_profiles, problem_hooks
from chainid.gap.core.resample import attach, resample
from chainid.infra.progress import stage
from chainid.gap.core.stationarity import check as stationarity_check
from chainid.gap.core.verdict import contract, decide, joint_notes, overfit_warning, trusted_path
from chainid.gap.harmonic.problem import Problem, damping_separable
from chainid.gap.harmonic.tie import tie_path
from chainid.gap.harmonic.where import localise

__all__ = ["diagnose_harmonic", "jackknife"]


def diagnose_harmonic(data: Sequence[Any], hold: Sequence[str], model: Any, *, effects: Sequence[str] | None,
                      max_combo: int, damping_law: str, uncertainty: bool,
                      excluded: Sequence[dict[str, str]] = (), resamples: int = 0, seed: int = 0,
                      fit_mass: bool = False) -> dict[str, Any]:
    """Diagnose a set of prepared harmonic tests (:class:`chainid.gap.harmonic.prepare.TestData`).

    Parameters
    ----------
    data : prepared tests (the usable ones)
    hold : held-out test ids (whole tests, all usable)
    model : baseline stiffness model (chain model or fitted linear spring)
    effects, max_combo, damping_law, uncertainty, resamples, seed : as :func:`chainid.gap.diagnose.diagnose`
    excluded : tests left out, with their reason (reported)
    fit_mass : a linear baseline fits its moving mass (``model=None`` and no ``--mass``)

    Returns
    -------
    dict
        The JSON contract of ``chainid diagnose`` (:func:`chainid.gap.core.verdict.contract`).
    """
    prob = Problem(data, model, hold, damping_law, fit_mass=fit_mass)
    warn: list[str] = [f"test {e['test']} excluded: {e['reason']}" for e in excluded]
    if prob.law == "polynomial" and damping_law == "polynomial":
        ok, msg = damping_separable(prob.train)
        if not ok:
            warn.append(msg)
            warnings.warn(msg, stacklevel=4)  # the caller of chainid.gap.diagnose
    stage("baseline")
    base_c = fw.baseline_candidate(prob)
    where = localise(prob, base_c._ev)  # type: ignore[attr-defined]
    r2, f2, db0 = prob.noise_db(base_c._ev, "hold")  # type: ignore[attr-defined]
    nbin = prob.n_cells("hold")
    sig_hold = math.sqrt(np.mean([d.sigma**2 for d in prob.hold]))
    excess = math.sqrt(max(r2 - f2, 0.0))
    consistent = fw.at_noise_floor(r2, f2, sig_hold, nbin)
    fwd = fw.forward_select(prob, fw.library(prob, effects), base_c, base_c.nrmse_holdout, max_effects=int(max_combo))
    fwd["path"] = tie_path(prob, fwd["path"], base_c.nrmse_holdout)  # c_e tied where the tests allow (.tie: why)
    path: list[Candidate] = fwd["path"]
    singles: list[Candidate] = sorted(fwd["singles"], key=lambda c: c.nrmse_loto)
    ok_path, bad = trusted_path(path)
    if bad is not None:
        warn.append(overfit_warning(path, bad))
    warn.extend(joint_notes(ok_path))
    final = ok_path[-1] if len(ok_path) > 1 else None
    best = final if final is not None else (singles[0] if singles else None)
    if uncertainty:
        for c in path[1:]:
            c.param_sd = jackknife(prob, c)
        if final is None and best is not None and best.n_params:
            best.param_sd = jackknife(prob, best)
    stat = stationarity_check(prob.data)
    left = final if final is not None else base_c
    r2l, f2l, dbl = prob.noise_db(left._ev, "hold")  # type: ignore[attr-defined]
    residual = {"db_over_noise": dbl, "nrmse_holdout": left.nrmse_holdout,
                "excess_rms_N": math.sqrt(max(r2l - f2l, 0.0)), "stationary": stat["stationary"],
                "trend_change_N": stat["trend_change_N"], "trend_z": stat["z"], "finding": stat["finding"],
                "at_noise_floor": fw.at_noise_floor(r2l, f2l, sig_hold, nbin)}
    verdict = decide(consistent, final, stat, excess, path, fwd, where, warn, best)
    confounded = [cf | {"separate_by": separating_test(*cf["pair"])} for cf in fwd["confounded"]]
    interp = interpretation(ok_path, prob, verdict)  # the verdict's chain, no cut step
    tests = [{"test": d.test, "omega": d.omega, "A": d.A, "x0": d.x0, "sigma_N": d.sigma, "window": d.window,
              "split": "holdout" if d in prob.hold else "train", "nrmse_before": base_c.per_test[d.test],
              "nrmse_after": left.per_test.get(d.test)} for d in prob.data]
    noise = {"excess_rms_N": excess, "noise_sigma_N": sig_hold, "chi2_ratio": r2 / f2 if f2 > 0 else None,
             "db_over_noise": db0}
    out = contract(prob, model, base_c, noise, fwd, verdict, interp, residual, where, list(excluded), confounded,
                   warn, list(hold), tests)
    stage("model-free check")
    out["open_world"] = open_world(prob.state_table(left._ev), bool(residual["at_noise_floor"]),  # type: ignore
                                   keep_model=True, stat=stat)
    if resamples:
        stage("resampling", f"{resamples} resamples")
        from chainid.gap.harmonic import resampling

        stab = resample(prob, resampling, fwd, ok_path, n=resamples, seed=seed, max_effects=int(max_combo))
        stage("profile likelihood")
        attach_profiles(stab, ok_path, lambda c: problem_hooks(prob, c))
        attach(out, stab)
    return out


def jackknife(prob: Problem, cand: Candidate) -> dict[str, float]:
    """Parameter standard deviations [their units] by leave-one-test-out refits (jack-knife over training tests)."""
    names = cand.names
    keys = [k for k in cand.params if not k.startswith("law.")]
    vals = []
    tr = prob.train
    for i in range(len(tr)):
        sub = tr[:i] + tr[i + 1:]
        c = prob.fit(names, train_only=sub, start=cand.params, polish_only=True)
        vals.append([c.params.get(k, float("nan")) for k in keys])
    return dict(zip(keys, (float(s) for s in jackknife_sd(np.array(vals)))))
