"""`chainid diagnose`: where the model misses, which effects cause it (in order), how much each shrinks it.

Pipeline: prepare every test (tests that cannot be analysed are excluded with
their reason) → baseline (paper Eq. 1 with the chosen damping law) → where it
misses (:mod:`.where`) → the explanation chain by forward selection conditional
on what is already explained (:mod:`.selection`) → what is left: dB over noise and
stationarity (:mod:`.stationarity`) → verdict (:mod:`.verdict`).  Records that are not steady harmonic tests
take the time-domain route (:mod:`.diagnose_time`); ``validate`` scores the chain on another set
(:mod:`.transfer`).
"""

from __future__ import annotations

import math
import sys
import warnings
from typing import Any, Sequence

import numpy as np

from chainid.gap import selection as fw
from chainid.gap.interpret import interpretation, separating_test
from chainid.gap.modelio import attach_models
from chainid.gap.prepare import Unusable, prepare_test
from chainid.gap.problem import MIN_TRAIN, Candidate, Problem, damping_separable, jackknife_sd
from chainid.gap.stationarity import check as stationarity_check
from chainid.gap.verdict import MIN_SHRINK, NONSTAT_FRACTION, contract, decide  # noqa: F401  (the verdict rule, one place)
from chainid.gap.where import localise
# the one rule for records no analysis can work on (magnitudes, a dead force or displacement channel) is the
# records' validation: identify, audit, predict and the diagnosis use it alike
from chainid.records.validate import MAX_ABS_F_N, MAX_ABS_X_MM  # noqa: F401  (re-exported)
from chainid.records.validate import check_channels as check_magnitudes


def fit_linear_model(records: Sequence[Any], holdout: Sequence[str]) -> Any:
    """LinearModel F = k(x − x_ref) [N/mm, mm] fitted on the training records' samples."""
    from chainid.model.base import LinearModel

    xs = np.concatenate([r.x for r in records if r.test not in set(holdout)])
    Fs = np.concatenate([r.F for r in records if r.test not in set(holdout)])
    return LinearModel.fit(xs, Fs)


def _prepare(records: Sequence[Any], n_bins: int, allow_compression: bool, steady_tol: float | None,
             strict: bool) -> tuple[list[Any], list[dict[str, str]]]:
    from chainid.gap.noise import is_broadband

    data, excluded = [], []
    for r in records:
        if r.t.size >= 64 and is_broadband(r.t, r.x):  # clearly not one sine: no harmonic estimate to try
            excluded.append({"test": r.test, "reason": "not a harmonic test (broadband displacement)"})
            continue
        try:
            data.append(prepare_test(r, n_bins=n_bins, allow_compression=allow_compression, steady_tol=steady_tol))
        except Unusable as exc:
            if strict:
                raise ValueError(f"test {r.test!r} cannot be used (--strict): {exc}") from None
            excluded.append({"test": r.test, "reason": str(exc)})
    return data, excluded


def diagnose(
    records: Sequence[Any],
    holdout: Sequence[str],
    model: Any | None = None,
    *,
    effects: Sequence[str] | None = None,
    max_combo: int = 3,
    n_bins: int = 64,
    uncertainty: bool = True,
    damping_law: str = "auto",
    allow_compression: bool = False,
    steady_tol: float | None = None,
    strict: bool = False,
    quiet: bool = False,
    holdout_blocks: int = 0,
    validate: Sequence[Any] | None = None,
) -> dict[str, Any]:
    """Diagnose the sim-to-real gap of a test series.

    Parameters
    ----------
    records : sequence of Record
        Measured tests (t s, x mm, F N).
    holdout : sequence of str
        Held-out test ids (whole tests).
    model : StiffnessModel, optional
        Baseline stiffness; None: linear spring fitted on the training tests.
    effects : sequence of str, optional
        Restrict the library (default: all applicable).
    max_combo : int
        Most effects in the explanation chain (1–3).
    n_bins : int
        Phase bins per cycle.
    uncertainty : bool
        Jack-knife standard deviations of every step's parameters (harmonic route: leave-one-test-out refits;
        time route: the larger of the linearised block jack-knife and leave-one-unit-out refits). Without it the
        time route reports the linearised one only.
    damping_law : str
        Baseline damping law: ``auto`` (default; the paper's Eq. 21 when the plan separates it, else the
        leave-one-out best simple law), ``polynomial``, ``viscous``, ``coulomb``, ``viscous+coulomb``,
        ``hysteretic``.
    allow_compression : bool
        Accept compressive (negative) forces with a chain model, which carries none.
    steady_tol : float, optional
        Steady-cycle tolerance (None: adaptive, from each record's cycle-to-cycle scatter).
    strict : bool
        A test that cannot be analysed is an error instead of being excluded.
    quiet : bool
        No line on stderr per excluded test.
    holdout_blocks : int
        K > 0: every record is cut into K contiguous time blocks and the last block of each is held out
        (time-domain route for every record; whole tests in ``holdout`` are held out as well).
    validate : sequence of Record, optional
        Another set (another excitation): the chain fitted here is evaluated on it (key ``transfer``,
        :func:`chainid.gap.transfer.transfer`).

    A record that is not a steady harmonic test (a transient, sweep, random or seismic record) is analysed
    in the time domain (:mod:`chainid.gap.diagnose_time`); harmonic tests keep the phase-bin route, and a set
    of both kinds is diagnosed as one problem.

    Returns
    -------
    dict
        The JSON contract: baseline, where, ranking, verdict, plus steps (the explanation chain), excluded,
        residual, mechanism, best, confounded, interpretation, warnings, tests.

    Raises
    ------
    ValueError
        Unknown holdout id, all tests held out, fewer than 3 usable training tests, compressive records with a
        chain model without ``allow_compression``, |F| > 1e12 N or |x| > 1e9 mm, a constant force or displacement
        (:func:`check_magnitudes`, i.e. :func:`chainid.records.validate.check_channels`).
    """
    if not 1 <= int(max_combo) <= 3:
        raise ValueError(f"max_combo = {max_combo!r} is out of range; valid range 1 to 3")
    check_magnitudes(records)
    if validate is not None:
        check_magnitudes(validate)
    holdout = [h.strip() for h in holdout if h.strip()]
    ids = [r.test for r in records]
    bad = [h for h in holdout if h not in ids]
    if bad:
        raise ValueError(f"--holdout: test id(s) {bad} not in the data; valid ids: {', '.join(ids)}")
    holdout_blocks = int(holdout_blocks)
    if holdout_blocks < 0 or holdout_blocks == 1:
        raise ValueError(f"--holdout-blocks = {holdout_blocks!r} is out of range; valid: 0 (off) or >= 2")
    if not holdout and holdout_blocks == 0:
        raise ValueError("--holdout: no test held out; give test ids or --holdout-blocks K")
    if len(set(holdout)) >= len(set(ids)):
        raise ValueError(f"--holdout: all {len(ids)} tests are held out; leave at least {MIN_TRAIN} for training")
    is_chain = model is not None and hasattr(model, "hertz_scale")
    # how predict evaluates a harmonic test of the set, stored in the model file
    evaluation = {"n_bins": int(n_bins), "steady_tol": steady_tol,
                  "allow_compression": bool(allow_compression or not is_chain)}
    data, excluded = _prepare(records, n_bins, allow_compression or not is_chain, steady_tol, False)
    # records that are not steady harmonic tests go to the time-domain route when long enough for it
    from chainid.gap.timedomain import MIN_SAMPLES

    time_ids = {r.test for r in records if r.t.size >= MIN_SAMPLES} & {e["test"] for e in excluded}
    excluded = [e for e in excluded if e["test"] not in time_ids]
    if strict and excluded:
        e = excluded[0]
        raise ValueError(f"test {e['test']!r} cannot be used (--strict): {e['reason']}")
    if time_ids or holdout_blocks:
        from chainid.gap.diagnose_time import diagnose_any

        for e in excluded:
            if not quiet:
                print(f"chainid diagnose: test {e['test']} excluded: {e['reason']}", file=sys.stderr)
        time_recs = [r for r in records if r.test in time_ids]
        records = [r for r in records if r.test not in {e["test"] for e in excluded}]
        holdout = [h for h in holdout if h in {r.test for r in records}]
        if model is None:
            model = fit_linear_model(records, holdout)
        res = diagnose_any(records, data, time_recs, holdout, model, holdout_blocks=holdout_blocks, effects=effects,
                           max_combo=max_combo, damping_law=damping_law, excluded=excluded, quiet=quiet,
                           uncertainty=uncertainty)
        for msg in attach_models(res, evaluation):  # the model found, runnable and savable on any excitation
            warnings.warn(msg, stacklevel=2)
        if validate is not None:
            from chainid.gap.transfer import transfer

            res["transfer"] = transfer(res, validate, n_bins=n_bins, steady_tol=steady_tol)
        return res
    for e in excluded:
        if not quiet:
            print(f"chainid diagnose: test {e['test']} excluded: {e['reason']}", file=sys.stderr)
    ex_ids = {e["test"] for e in excluded}
    hold_ok = [h for h in holdout if h not in ex_ids]
    if not hold_ok:
        raise ValueError(f"--holdout: every held-out test was excluded ({', '.join(holdout)}); "
                         f"reasons: {'; '.join(e['reason'] for e in excluded if e['test'] in holdout)}")
    if model is None:
        model = fit_linear_model([r for r in records if r.test not in ex_ids], hold_ok)
    prob = Problem(data, model, hold_ok, damping_law)
    warn: list[str] = [f"test {e['test']} excluded: {e['reason']}" for e in excluded]
    if prob.law == "polynomial" and damping_law == "polynomial":
        ok, msg = damping_separable(prob.train)
        if not ok:
            warn.append(msg)
            warnings.warn(msg, stacklevel=2)
    base_c = fw.baseline_candidate(prob)
    base_hold = base_c.nrmse_holdout
    base = base_c._ev  # type: ignore[attr-defined]
    where = localise(prob, base)
    r2, f2, db0 = prob.noise_db(base, "hold")
    nbin = sum(d.counts.size for d in prob.hold)
    sig_hold = math.sqrt(np.mean([d.sigma**2 for d in prob.hold]))
    excess = math.sqrt(max(r2 - f2, 0.0))
    consistent = fw.at_noise_floor(r2, f2, sig_hold, nbin)

    fwd = fw.forward_select(prob, fw.library(prob, effects), base_c, base_hold, max_effects=int(max_combo))
    path: list[Candidate] = fwd["path"]
    singles: list[Candidate] = sorted(fwd["singles"], key=lambda c: c.nrmse_loto)
    final = path[-1] if len(path) > 1 else None
    best = final if final is not None else (singles[0] if singles else None)
    if uncertainty:
        for c in path[1:]:
            c.param_sd = _jackknife(prob, c)
        if final is None and best is not None and best.n_params:
            best.param_sd = _jackknife(prob, best)
    stat = stationarity_check(prob.data)
    left = final if final is not None else base_c
    r2l, f2l, dbl = prob.noise_db(left._ev, "hold")  # type: ignore[attr-defined]
    residual = {"db_over_noise": dbl, "nrmse_holdout": left.nrmse_holdout,
                "excess_rms_N": math.sqrt(max(r2l - f2l, 0.0)), "stationary": stat["stationary"],
                "trend_change_N": stat["trend_change_N"], "trend_z": stat["z"], "finding": stat["finding"],
                "at_noise_floor": fw.at_noise_floor(r2l, f2l, sig_hold, nbin)}
    verdict = decide(consistent, final, stat, excess, path, fwd, where, warn, best)
    confounded = []
    for cf in fwd["confounded"]:
        confounded.append(cf | {"separate_by": separating_test(*cf["pair"])})
    interp = interpretation(path, prob, verdict)
    tests = [{"test": d.test, "omega": d.omega, "A": d.A, "x0": d.x0, "sigma_N": d.sigma, "window": d.window,
              "split": "holdout" if d in prob.hold else "train", "nrmse_before": base_c.per_test[d.test],
              "nrmse_after": best.per_test.get(d.test) if best is not None else None} for d in prob.data]
    noise = {"excess_rms_N": excess, "noise_sigma_N": sig_hold, "chi2_ratio": r2 / f2 if f2 > 0 else None,
             "db_over_noise": db0}
    summary = contract(prob, model, base_c, noise, fwd, verdict, interp, residual, where, excluded, confounded, warn,
                       list(hold_ok), tests)
    for msg in attach_models(summary, evaluation):
        warnings.warn(msg, stacklevel=2)
    if validate is not None:
        from chainid.gap.transfer import transfer

        summary["transfer"] = transfer(summary, validate, n_bins=n_bins, steady_tol=steady_tol)
    return summary


def _jackknife(prob: Problem, cand: Candidate) -> dict[str, float]:
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
