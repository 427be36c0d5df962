"""`chainid diagnose` on any excitation: time-domain records, alone or mixed with harmonic tests.

Called by :func:`chainid.gap.diagnose.diagnose` when a record is not a steady harmonic
test (or ``holdout_blocks`` is given).  Harmonic tests keep the phase-bin route as the
harmonic part of :class:`chainid.gap.timedomain.problem.AnyProblem` when there are at least
``MIN_TRAIN`` of them for training; otherwise they join the time-domain records.  The same
forward selection and step rule (:mod:`chainid.gap.core.selection`) run on the combined problem;
the verdict rules are those of the harmonic route.  The result has the same JSON contract
keys, plus ``route``, ``noise`` and the time-domain ``where`` findings (state maps, spectrum,
ringing/chatter, drift).

Units: mm, N, s.
"""

from __future__ import annotations

import math
import sys
from typing import Any, Sequence

from chainid.gap.core import selection as fw
from chainid.gap.core.interpret import interpretation, separating_test
from chainid.gap.core.candidate import MIN_TRAIN, Candidate
from chainid.gap.harmonic.problem import Problem
from chainid.gap.timedomain.data import prepare_time
from chainid.gap.timedomain.problem import AnyProblem
from chainid.gap.core.verdict import contract, decide
from chainid.gap.harmonic.where import localise
from chainid.gap.timedomain.where import drift, localise_time

#: blocks per record for leave-one-block-out scoring when whole tests are held out
LOO_BLOCKS = 4


def build_problem(records: Sequence[Any], hdata: Sequence[Any], time_recs: Sequence[Any], holdout: Sequence[str],
                  holdout_blocks: int, model: Any, damping_law: str, warn: list[str]) -> AnyProblem:
    """The combined problem: harmonic part (when it has >= MIN_TRAIN training tests) + time-domain records."""
    hold = set(holdout)
    h_train = [d for d in hdata if d.test not in hold]
    hprob = None
    time_recs = list(time_recs)
    if hdata and len(h_train) >= MIN_TRAIN and holdout_blocks == 0:
        hprob = Problem(hdata, model, [d.test for d in hdata if d.test in hold], damping_law, require_hold=False)
    elif hdata:
        ids = {d.test for d in hdata}
        time_recs += [r for r in records if r.test in ids]
        warn.append(f"{len(hdata)} harmonic test(s) analysed in the time domain with the other records "
                    + ("(--holdout-blocks splits every record in time)" if holdout_blocks else
                       f"(fewer than {MIN_TRAIN} harmonic training tests for the phase-bin route)"))
    nb = holdout_blocks if holdout_blocks > 0 else LOO_BLOCKS
    tdata = [prepare_time(r, nb) for r in time_recs]
    return AnyProblem(tdata, model, holdout, holdout_blocks, hprob)


def larger_sd(linear: dict[str, float], refit: dict[str, float], at_bound: Sequence[str]) -> dict[str, float]:
    """Per parameter the larger of two jack-knife sds [its units]: the linearised one misses a cost that is not
    smooth in the parameter, a local refit misses one that is flat or jagged around the fit.  Parameters pinned at a
    bound get none (they are not estimated)."""
    keys = [k for k in dict.fromkeys([*linear, *refit]) if k not in at_bound]
    return {k: max(linear.get(k, 0.0), refit.get(k, 0.0)) for k in keys}


def diagnose_any(records: Sequence[Any], hdata: Sequence[Any], time_recs: Sequence[Any], holdout: Sequence[str],
                 model: Any, *, holdout_blocks: int = 0, effects: Sequence[str] | None = None, max_combo: int = 3,
                 damping_law: str = "auto", excluded: Sequence[dict[str, str]] = (), quiet: bool = False,
                 uncertainty: bool = True) -> dict[str, Any]:
    """Diagnose a set with time-domain records (see the module docstring); returns the JSON contract dict.

    Parameters
    ----------
    records : all records (Record; t s, x mm, F N)
    hdata : prepared harmonic tests (TestData)
    time_recs : records that are not steady harmonic tests
    holdout : held-out test ids (whole tests)
    model : baseline stiffness model (fitted linear spring or chain model)
    holdout_blocks : K > 0: every record in K contiguous blocks, the last one held out
    uncertainty : the reported parameter sds of the chosen steps also from leave-one-unit-out refits
        (:meth:`AnyProblem.refit_sd`; the larger of it and the linearised block jack-knife is kept)
    """
    warn: list[str] = []
    for r in time_recs:
        if not quiet:
            print(f"chainid diagnose: test {r.test} is not a steady harmonic test: time-domain route", file=sys.stderr)
    prob = build_problem(records, hdata, time_recs, holdout, holdout_blocks, model, damping_law, warn)
    base_c = fw.baseline_candidate(prob)
    base_hold = base_c.nrmse_holdout
    bev = base_c._ev  # type: ignore[attr-defined]
    where = localise_time(prob.tdata, bev["time"]["res"], bev["time"]["force"])
    if prob.hprob is not None:
        where += localise(prob.hprob, bev["harmonic"])
    r2, f2, db0 = prob.noise_db(bev, "hold")
    sig = prob.sigma_raw
    excess = math.sqrt(max(r2 - f2, 0.0))
    consistent = fw.at_noise_floor(r2, f2, sig, prob.n_cells("hold"))
    fwd = fw.forward_select(prob, fw.library(prob, effects), base_c, base_hold, max_effects=int(max_combo))
    path: list[Candidate] = fwd["path"]
    singles = sorted(fwd["singles"], key=lambda c: c.nrmse_loto)
    final = path[-1] if len(path) > 1 else None
    best = final if final is not None else (singles[0] if singles else None)
    if uncertainty:
        for c in path[1:] + ([best] if final is None and best is not None and best.n_params else []):
            c.param_sd = larger_sd(c.param_sd, prob.refit_sd(c.names, c.params), c.at_bound)
    left = final if final is not None else base_c
    lev = left._ev  # type: ignore[attr-defined]
    stat = drift(prob.tdata, lev["time"]["res"])
    left_where = localise_time(prob.tdata, lev["time"]["res"], lev["time"]["force"])
    chatter = next((f for f in left_where if f.get("kind") == "chatter"), None)
    if chatter is not None and not any(f.get("kind") == "chatter" for f in where):
        where.insert(0, chatter | {"finding": "after the chain: " + chatter["finding"]})
    r2l, f2l, dbl = prob.noise_db(lev, "hold")
    residual = {"db_over_noise": dbl, "nrmse_holdout": left.nrmse_holdout, "excess_rms_N": math.sqrt(max(r2l - f2l, 0.0)),
                "stationary": stat["stationary"], "trend_change_N": stat["trend_change_N"], "trend_z": stat["z"],
                "finding": stat["finding"], "at_noise_floor": fw.at_noise_floor(r2l, f2l, sig, prob.n_cells("hold")),
                "chatter": bool(chatter), "where": left_where}
    verdict = decide(consistent, final, stat, excess, path, fwd, where, warn, best)
    if chatter is not None:
        warn.append("stick-slip chatter after reversals (" + f"{chatter['frequency_Hz']:.3g} Hz, RMS "
                    f"{chatter['rms_N']:.3g} N): no library effect covers it; the named effects do not include it")
    confounded = [cf | {"separate_by": separating_test(*cf["pair"])} for cf in fwd["confounded"]]
    interp = interpretation(path, prob, verdict)
    tests = [{"test": d.test, "route": "time", "omega": d.omega, "A": d.A, "x0": d.x0, "sigma_N": d.sigma,
              "sigma_hf_N": d.sigma_hf, "band_Hz": d.f_band, "window": d.window,
              "split": ("holdout" if d in prob.hold and not any(u[0] is d for u in prob.train_units) else
                        "train+holdout-block" if d in prob.hold else "train"),
              "nrmse_before": base_c.per_test.get(d.test),
              "nrmse_after": best.per_test.get(d.test) if best is not None else None} for d in prob.tdata]
    if prob.hprob is not None:
        hp = prob.hprob
        tests += [{"test": d.test, "route": "harmonic", "omega": d.omega, "A": d.A, "x0": d.x0, "sigma_N": d.sigma,
                   "window": d.window, "split": "holdout" if d in hp.hold else "train",
                   "nrmse_before": base_c.per_test.get(d.test),
                   "nrmse_after": best.per_test.get(d.test) if best is not None else None} for d in hp.data]
    noise = {"excess_rms_N": excess, "noise_sigma_N": sig, "chi2_ratio": r2 / f2 if f2 > 0 else None,
             "db_over_noise": db0}
    summary = {"route": "mixed" if prob.hprob is not None else "time"} | contract(
        prob, model, base_c, noise, fwd, verdict, interp, residual, where, list(excluded), confounded, warn,
        list(holdout), tests)
    summary["holdout_blocks"] = holdout_blocks  # > 0: the last of that many blocks of every record is held out
    summary["noise"] = {"method": "per record: sigma = 1.4826*MAD(second difference of F)/sqrt(6); sigma_hf from the "
                                  "force spectrum above 4x the excitation band (a check: equal for white noise)",
                        "tests": {d.test: {"sigma_N": d.sigma, "sigma_hf_N": d.sigma_hf, "band_Hz": d.f_band}
                                  for d in prob.tdata}}
    return summary
