"""The time-domain route of ``chainid diagnose``: records of any excitation (and harmonic tests among them).

Every record is prepared for the time domain (:mod:`.data`), the problem built on the chosen base
(:class:`.problem.TimeProblem`: the chain, or a linear mass–spring–damper fitted here), and the same forward
selection and step rule (:mod:`chainid.gap.core.selection`) and the same verdict rule
(:mod:`chainid.gap.core.verdict`) as on the harmonic route run on it.  Covariate terms (an amplitude that varies
linearly with an operating condition) are candidates of the selection like the effects: those of the base from
the start, those of an effect once it is chosen.  A loop effect of the kept chain whose parameters change with
the speed is cut from it (:mod:`.ratecheck`: it stands in for a rate-dependent mechanism).  The result has the
JSON contract keys, plus ``route``, ``noise`` (per record: force noise and the kinematics' estimator and predicted
errors) and the time-domain ``where`` findings (state maps, spectrum, ringing/chatter, backbone, drift, rate
dependence).  Where the fitted chain's residual refutes a record's force noise as read from its force (a force
that switches on the sample scale, :mod:`.noisecheck`), the noise is read again from that residual and the
diagnosis runs once more.

Units: mm, N, s, kg.
"""

from __future__ import annotations

import math
import sys
from functools import partial
from types import SimpleNamespace
from typing import Any, Sequence

import numpy as np

from chainid.gap.core import selection as fw
from chainid.gap.core.candidate import Candidate
from chainid.gap.core.interpret import interpretation, separating_test
from chainid.gap.core.openworld import open_world
from chainid.gap.core.profile import attach_profiles, problem_hooks
from chainid.gap.core.resample import attach, resample, widen
from chainid.infra.progress import stage
from chainid.gap.core.verdict import (contract, decide, fallback_best, joint_notes, kept_path, overfit_warning,
                                      trusted_path)
from chainid.gap.timedomain import noisecheck
from chainid.gap.timedomain.data import prepare_time
from chainid.gap.timedomain.lawreach import law_extrapolation
from chainid.gap.timedomain.problem import TimeProblem
from chainid.gap.timedomain.ratecheck import rate_cut
from chainid.gap.timedomain.where import drift, localise_time

__all__ = ["LOO_BLOCKS", "build_problem", "diagnose_any", "floor_shrinkage", "held_out_floor2", "read_as_none"]

#: blocks per record for leave-one-block-out scoring when whole tests are held out
LOO_BLOCKS = 4


def build_problem(records: Sequence[Any], holdout: Sequence[str], holdout_blocks: int, model: Any,
                  mass_kg: float | None = None, damping_law: str = "auto",
                  sigma_caps: dict[str, float] | None = None) -> TimeProblem:
    """The time-domain problem of ``records`` (every one sample by sample), cut in blocks; ``sigma_caps``: per test,
    an upper bound on its force noise [N] (:mod:`.noisecheck`)."""
    nb = holdout_blocks if holdout_blocks > 0 else LOO_BLOCKS
    tdata = [prepare_time(r, nb, (sigma_caps or {}).get(r.test)) for r in records]
    return TimeProblem(tdata, model, holdout, holdout_blocks, mass_kg=mass_kg, damping_law=damping_law)


def _tests(prob: TimeProblem, base_c: Candidate, left: Candidate) -> list[dict[str, Any]]:
    out = []
    for d in prob.tdata:
        hold = ~prob.train_mask(d.test)
        split = "holdout" if hold.all() else ("train+holdout-block" if hold.any() else "train")
        out.append({"test": d.test, "route": "time", "omega": d.omega, "omega_c": d.omega_c, "A": d.A, "x0": d.x0,
                    "sigma_N": d.sigma, "sigma_hf_N": d.sigma_hf, "band_Hz": d.f_band, "window": d.window,
                    "covariates": dict(d.covariates), "split": split,
                    "nrmse_before": base_c.per_test.get(d.test), "nrmse_after": left.per_test.get(d.test)})
    return out


def kinematic_none(final: Candidate | None, r2: float, kin_floor: float, f2: float, prob: TimeProblem,
                   ow: dict[str, Any]) -> bool:
    """Whether a baseline above its force noise is still a ``none``: what it leaves is the kinematic floor.

    A record's displacement noise reaches the model force through the estimated ẋ and ẍ (c·e_v, m·e_a, k·e_x,
    :meth:`TimeProblem.kinematic_floor`): even the true model leaves it.  Counted only when nothing else can claim
    the excess: no effect passed the step rule (``final`` None), the held-out residual r2 [N²] is at the kinematic
    floor by the rule of :func:`chainid.gap.core.steprule.at_noise_floor`, and the model-free learner finds no
    state variable that predicts what is left and no change in time (``ow``).  A fitted mass or dashpot standing
    in for a missing effect would raise the kinematic floor, but the missing effect then passes the step rule or
    leaves a residual the learner predicts.
    """
    if final is not None or ow.get("missing_effect") or not (kin_floor > 0.0 and f2 > 0.0):
        return False
    return fw.at_noise_floor(r2, kin_floor**2, math.sqrt(f2), prob.n_cells("hold"), prob.floor_rel_sd("hold"))


def read_as_none(prob: TimeProblem, base_c: Candidate, final: Candidate | None, floors: tuple[float, float, float],
                 ow: dict[str, Any], where: list[dict[str, Any]], warn: list[str]) -> str | None:
    """How a baseline above its force noise is still read as ``none`` (``"kinematic_floor"`` or
    ``"damping_extrapolation"``; None: it is not), with a warning and, for the law, a ``where`` finding.

    Two readings, each only when no effect passed the step rule and the model-free check is silent: the residual is
    the kinematic floor (:func:`kinematic_none`), or the held-out gap is the base's damping law read beyond the
    training records (:func:`chainid.gap.timedomain.lawreach.law_extrapolation`).  ``floors``: the baseline's
    held-out mean squared residual r2, its force-noise floor f2 [N²] and the kinematic floor [N].
    """
    if final is not None or ow.get("missing_effect"):
        return None
    r2, f2, kin_floor = floors
    if kinematic_none(final, r2, kin_floor, f2, prob, ow):
        warn.append(f"the baseline's held-out residual ({math.sqrt(r2):.3g} N RMS) is at the kinematic floor "
                    f"({kin_floor:.3g} N: the force noise and the displacement noise through the estimated ẋ, ẍ), "
                    "no effect passes the step rule and no state variable predicts what is left: read as noise")
        return "kinematic_floor"
    reach = law_extrapolation(prob, list(base_c.names), base_c.params)
    if reach is None:
        return None
    where.insert(0, reach)
    warn.append(reach["finding"] + ": read as the law's reach, not an effect (training records that span the "
                "held-out conditions would fix the law)")
    return "damping_extrapolation"


def diagnose_any(records: Sequence[Any], holdout: Sequence[str], model: Any, *, holdout_blocks: int = 0,
                 effects: Sequence[str] | None = None, max_combo: int = 3, excluded: Sequence[dict[str, str]] = (),
                 quiet: bool = False, mass_kg: float | None = None, warn: list[str] | None = None,
                 resamples: int = 0, seed: int = 0, damping_law: str = "auto", why: str = "") -> dict[str, Any]:
    """Diagnose records in the time domain (see the module docstring); returns the JSON contract dict.

    Parameters
    ----------
    records : every record to analyse (Record; t s, x mm, F N; ``covariates`` when they have them)
    holdout : held-out test ids (whole records)
    model : the chain base (ChainModel), or None: a linear mass–spring–damper fitted on the training data
    holdout_blocks : K > 0: every record in K contiguous blocks, the last one held out
    effects, max_combo : the library restricted, the most effects in the chain
    mass_kg : the given mass of a linear base [kg] (None: fitted)
    resamples, seed : resamples of the training blocks for the chain's stability and the parameters' intervals
        (:mod:`chainid.gap.core.resample`; 0: none)
    damping_law : ``viscous``: one dashpot for every record; otherwise the dashpot follows the records' features
        where they separate it (:func:`chainid.gap.timedomain.basechoice.law_choice`)
    why : why the set takes this route, said once on stderr (empty: nothing said)
    """
    if not quiet:
        _say_route(records, why)
    build = partial(build_problem, holdout=holdout, holdout_blocks=holdout_blocks, model=model, mass_kg=mass_kg,
                    damping_law=damping_law)  # also the decimated and noisier records' problem (_trust)
    sel = _select(records, build, effects, max_combo, list(warn or []))
    capped = noisecheck.caps(sel.prob.tdata, (sel.final or sel.base_c)._ev["res"])
    if capped:  # the σ read from a force that switches on the sample scale is refuted by the chain's residual
        build = partial(build, sigma_caps=capped)
        sel = _select(records, build, effects, max_combo, list(warn or []) + [noisecheck.note(sel.prob.tdata,
                                                                                                  capped)])
    prob, base_c, where, fwd, ok_path, final, rate, warn = (sel.prob, sel.base_c, sel.where, sel.fwd, sel.ok_path,
                                                            sel.final, sel.rate, sel.warn)
    path: list[Candidate] = fwd["path"]
    bev = base_c._ev  # type: ignore[attr-defined]
    r2, f2, db0 = prob.noise_db(bev, "hold")
    sig = prob.sigma_raw
    excess = math.sqrt(max(r2 - f2, 0.0))
    consistent = fw.at_noise_floor(r2, f2, math.sqrt(f2), prob.n_cells("hold"), prob.floor_rel_sd("hold"))
    left = final if final is not None else base_c
    lev = left._ev  # type: ignore[attr-defined]
    stat = drift(prob.tdata, lev["res"])
    left_where = localise_time(prob.tdata, lev["res"], lev["force"])
    chatter = next((f for f in left_where if f.get("kind") == "chatter"), None)
    if chatter is not None and not any(f.get("kind") == "chatter" for f in where):
        where.insert(0, chatter | {"finding": "after the chain: " + chatter["finding"]})
    residual = _left_residual(prob, left, stat, chatter, left_where)
    kin_floor = residual["kinematic_floor_N"]
    singles = sorted(fwd["singles"], key=lambda c: c.nrmse_loto)
    best = final if final is not None else fallback_best(singles, fwd)
    stage("model-free check")
    ow = open_world(prob.state_table(lev), bool(residual["at_noise_floor"]), keep_model=True, stat=stat,
                    chatter=chatter)
    reading = _reading(prob, base_c, final, (r2, f2, kin_floor), ow, where, warn, residual, consistent, rate)
    consistent = reading is not None
    verdict = decide(consistent, final, stat, excess, path, fwd, where, warn, best)
    if chatter is not None:
        warn.append("stick-slip chatter after reversals (" + f"{chatter['frequency_Hz']:.3g} Hz, RMS "
                    f"{chatter['rms_N']:.3g} N): no library effect covers it; the named effects do not include it")
    confounded = [cf | {"separate_by": separating_test(*cf["pair"])} for cf in fwd["confounded"]]
    interp = interpretation(ok_path, prob, verdict)  # the verdict's chain, no cut step
    noise = {"excess_rms_N": excess, "noise_sigma_N": sig, "noise_floor_N": math.sqrt(f2),
             "chi2_ratio": r2 / f2 if f2 > 0 else None, "db_over_noise": db0}
    base_model = prob.model if prob.is_chain else SimpleNamespace(
        name="linear device: m·ẍ + c·ẋ + k·x, a force offset per test" + (f", m = {mass_kg:g} kg given" if mass_kg
                                                                           is not None else ""))
    summary = {"route": "time"} | contract(prob, base_model, base_c, noise, fwd, verdict, interp, residual, where,
                                           list(excluded), confounded, warn, list(holdout),
                                           _tests(prob, base_c, left))
    summary["open_world"] = ow
    summary["none_reading"] = reading if verdict == "none" else None
    if resamples:
        attach(summary, _trust(prob, records, build, fwd, ok_path, resamples, seed, int(max_combo)))
    summary["holdout_blocks"] = holdout_blocks  # > 0: the last of that many blocks of every record is held out
    summary["base"] = {"model": prob.base.kind, "mass_given_kg": mass_kg, "offsets": "per test" if prob.base.offsets
                       else "none", "covariates": list(prob.covariates)}
    summary["noise"] = _noise_method(prob)
    return summary


def _select(records: Sequence[Any], build: Any, effects: Sequence[str] | None, max_combo: int,
            warn: list[str]) -> SimpleNamespace:
    """One pass of the diagnosis up to its kept chain, on the problem ``build(records)`` makes: the baseline, its
    ``where`` findings, the forward selection ``fwd`` and the kept chain (:func:`_kept_chain`: ``ok_path``,
    ``final``, ``rate``), with ``warn`` (the list given, added to)."""
    stage("preparing", f"{len(records)} records")
    prob = build(records)
    stage("baseline")
    base_c = fw.baseline_candidate(prob)
    bev = base_c._ev  # type: ignore[attr-defined]
    where = localise_time(prob.tdata, bev["res"], bev["force"])
    lib = fw.library(prob, effects) + prob.covariate_terms()
    fwd = fw.forward_select(prob, lib, base_c, base_c.nrmse_holdout, max_effects=int(max_combo))
    ok_path, final, rate = _kept_chain(prob, fwd["path"], fwd, where, warn)
    return SimpleNamespace(prob=prob, base_c=base_c, where=where, fwd=fwd, ok_path=ok_path, final=final, rate=rate,
                           warn=warn)


def _say_route(records: Sequence[Any], why: str) -> None:
    """On stderr: why the set takes the time-domain route (once, when given), then each record's line."""
    if why:
        print(f"chainid diagnose: every record takes the time-domain route: {why}", file=sys.stderr)
    for r in records:
        print(f"chainid diagnose: test {r.test}: time-domain route", file=sys.stderr)


def _reading(prob: TimeProblem, base_c: Candidate, final: Candidate | None, floors: tuple[float, float, float],
             ow: dict[str, Any], where: list[dict[str, Any]], warn: list[str], residual: dict[str, Any],
             consistent: bool, rate: dict[str, Any] | None) -> str | None:
    """How the baseline's held-out residual is read: "noise" when it is ``consistent`` with the noise floor, never
    as none after a ``rate`` cut, else :func:`read_as_none`; and the chain's share of the gap above the kinematic
    floor (:func:`floor_shrinkage`) put on ``final`` for the verdict and in ``residual``."""
    if final is not None:
        final.shrinkage_floor = floor_shrinkage(prob, base_c, final, ow)  # type: ignore[attr-defined]
        residual["shrinkage_above_kinematic_floor"] = final.shrinkage_floor  # type: ignore[attr-defined]
    if consistent:
        return "noise"
    return None if rate is not None else read_as_none(prob, base_c, final, floors, ow, where, warn)


def _kept_chain(prob: TimeProblem, path: list[Candidate], fwd: dict[str, Any], where: list[dict[str, Any]],
                warn: list[str]) -> tuple[list[Candidate], Candidate | None, dict[str, Any] | None]:
    """The verdict's chain: the explanation chain up to its held-out minimum, cut before a loop effect that changes
    with the speed (:func:`.ratecheck.rate_cut`, its finding put in ``fwd``, ``where`` and ``warn``) and trimmed
    again to the shorter chain's own minimum (:func:`chainid.gap.core.verdict.kept_path`); with its last
    candidate (None: no effect kept) and the rate finding (None: none)."""
    ok_path, _ = trusted_path(path)
    _, rate, fwd["rate_checks"] = rate_cut(prob, ok_path)
    if rate is not None:
        fwd["rate_dependence"] = rate
        where.insert(0, rate)
        warn.append(rate["finding"])
    ok_path, bad = kept_path(path, fwd)
    if bad is not None:
        warn.append(overfit_warning(path, bad))
    warn.extend(joint_notes(ok_path))
    return ok_path, (ok_path[-1] if len(ok_path) > 1 else None), rate


def _trust(prob: TimeProblem, records: Sequence[Any], rebuild: Any, fwd: dict[str, Any], ok_path: list[Candidate],
           resamples: int, seed: int, max_effects: int) -> dict[str, Any]:
    """The chain's stability and its parameters' intervals: ``resamples`` resamples of the training blocks
    (:func:`chainid.gap.core.resample.resample`), widened by the time sampling's bias (the records decimated by 2 and
    rebuilt by ``rebuild``: :mod:`.discretisation`) and by the displacement noise's (:mod:`.simex`), with the
    profile-likelihood intervals beside them."""
    stage("resampling", f"{resamples} resamples")
    from chainid.gap.timedomain import discretisation, resampling, simex

    stab = resample(prob, resampling, fwd, ok_path, n=resamples, seed=seed, max_effects=max_effects)
    stage("discretisation bias", "records decimated by 2")
    bounds = [prob.param_bounds(list(c.names)) for c in ok_path]
    shifts, why = discretisation.richardson_shifts(records, prob, ok_path, rebuild)
    widen(stab, shifts, "bias_dt", bounds)
    stab["discretisation"] = {"method": discretisation.METHOD, "skipped": why}
    stage("displacement-noise bias", f"SIMEX, {simex.DRAWS} draws")
    shifts, why = simex.simex_shifts(records, ok_path, rebuild, seed)
    widen(stab, shifts, "bias_x", bounds)
    stab["displacement_noise"] = {"method": simex.METHOD, "skipped": why}
    stage("profile likelihood")
    attach_profiles(stab, ok_path, lambda c: problem_hooks(prob, c))
    return stab


def _left_residual(prob: TimeProblem, left: Candidate, stat: dict[str, Any], chatter: dict[str, Any] | None,
                   left_where: list[dict[str, Any]]) -> dict[str, Any]:
    """What the kept chain ``left`` leaves on the held-out data: its dB over the force noise, its excess [N], the
    kinematic floor [N] (:meth:`TimeProblem.kinematic_floor`, weighted by held-out samples), the drift check and
    where it lies."""
    lev = left._ev  # type: ignore[attr-defined]
    r2l, f2l, dbl = prob.noise_db(lev, "hold")
    kin_floor = math.sqrt(held_out_floor2(prob, left.params))
    return {"db_over_noise": dbl, "nrmse_holdout": left.nrmse_holdout, "excess_rms_N": math.sqrt(max(r2l - f2l, 0.0)),
            "stationary": stat["stationary"], "trend_change_N": stat["trend_change_N"], "trend_z": stat["z"],
            "finding": stat["finding"], "noise_floor_N": math.sqrt(f2l), "kinematic_floor_N": kin_floor,
            "db_over_kinematic_floor": 10.0 * math.log10(r2l / kin_floor**2) if r2l > 0 and kin_floor > 0 else None,
            "at_noise_floor": fw.at_noise_floor(r2l, f2l, math.sqrt(f2l), prob.n_cells("hold"),
                                                prob.floor_rel_sd("hold")),
            "chatter": bool(chatter), "where": left_where}


def held_out_floor2(prob: TimeProblem, params: dict[str, float]) -> float:
    """The kinematic floor [N²] of the model with ``params`` (:meth:`TimeProblem.kinematic_floor`), averaged over the
    held-out samples of every record."""
    hold_n = {d.test: int(np.sum(~prob.train_mask(d.test))) for d in prob.tdata}
    return sum(prob.kinematic_floor(d, params) * hold_n[d.test] for d in prob.tdata) / max(sum(hold_n.values()), 1)


def floor_shrinkage(prob: TimeProblem, base_c: Candidate, final: Candidate, ow: dict[str, Any]) -> float | None:
    """How much of the held-out gap that a model could close the chain closes: 1 − e_after/e_before, with e the
    held-out residual RMS above the kinematic floor K [N], e = √max(r² − K², 0).

    K² is what even the true model leaves on these kinematics (:meth:`TimeProblem.kinematic_floor`: the force noise
    and the estimated ẋ, ẍ and x errors through the base's c, m and k), averaged over the held-out samples, the
    smaller of the baseline's and the chain's (a chain whose fitted dashpot or mass grew to stand in for a missing
    effect cannot raise the floor it is judged against).  On a noisy resonator the inertial force of a noisy ẍ is a
    floor no model lowers, and the plain shrinkage of the held-out NRMSE stops short of the verdict's bar however
    right the chain is.  None (not read) when the model-free check flags a missing effect after the chain (what is
    left is then not all floor) or did not run (too few samples), or when the baseline is at the floor by the rule
    of :func:`kinematic_none` (then a small gain would read as all of it).
    """
    if ow.get("missing_effect") or ow.get("predictable_share") is None:
        return None
    k2_base, k2_final = held_out_floor2(prob, base_c.params), held_out_floor2(prob, final.params)
    r2_base, f2, _ = prob.noise_db(base_c._ev, "hold")  # type: ignore[attr-defined]
    r2_final = prob.noise_db(final._ev, "hold")[0]  # type: ignore[attr-defined]
    if not all(math.isfinite(v) for v in (k2_base, k2_final, r2_base, r2_final, f2)) or f2 <= 0.0:
        return None
    k2 = min(k2_base, k2_final)
    if r2_base <= k2:
        return None
    if fw.at_noise_floor(r2_base, k2, math.sqrt(f2), prob.n_cells("hold"), prob.floor_rel_sd("hold")):
        return None
    return 1.0 - math.sqrt(max(r2_final - k2, 0.0) / (r2_base - k2))


def _noise_method(prob: TimeProblem) -> dict[str, Any]:
    """How the noise floor was made, and each record's force noise, its high-band check and its kinematics."""
    return {"method": "per record: force sigma = 1.4826*MAD(second difference of F)/sqrt(6); the floor adds the "
                      "kinematics' predicted errors through the fitted base (c*e_v, m*e_a, k*e_x); sigma_hf from the "
                      "force spectrum above 4x the excitation band (a check); a record whose motion has content above "
                      "the acceleration's cut and whose force has none is compared below that cut (compared_below_Hz), "
                      "its noise floor the filter's noise_share of sigma^2; where a fitted chain's residual holds "
                      "under half the noise power so read, sigma is capped by the residual (sigma_read_N: before) and "
                      "the diagnosis run again",
            "tests": {d.test: {"sigma_N": d.sigma, "sigma_read_N": d.sigma_read, "sigma_hf_N": d.sigma_hf,
                               "band_Hz": d.f_band,
                               "compared_below_Hz": d.f_res if math.isfinite(d.f_res) else None,
                               "noise_share": d.rho,
                               "kinematics": d.kin.info() if d.kin is not None else None} for d in prob.tdata}}
