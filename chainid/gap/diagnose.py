"""`chainid diagnose`: where the model misses, which effects cause it (in order), how much each shrinks it.

Pipeline: prepare every test (tests that cannot be analysed are excluded with
their reason) → baseline (paper Eq. 1 with the chosen damping law) → where it
misses (:mod:`.where`) → the explanation chain by forward selection conditional
on what is already explained (:mod:`.forward`) → what is left: dB over noise and
stationarity (:mod:`.stationarity`) → verdict.
"""

from __future__ import annotations

import math
import sys
import warnings
from typing import Any, Sequence

import numpy as np

from chainid.gap import selection as fw
from chainid.gap.modelio import step_fields, step_models
from chainid.model.modelfile import model_to_dict
from chainid.gap.interpret import interpretation, mechanism, separating_test, step_text
from chainid.gap.prepare import Unusable, prepare_test
from chainid.gap.problem import MIN_TRAIN, Candidate, Problem, damping_separable
from chainid.gap.stationarity import check as stationarity_check
from chainid.gap.where import localise

#: the verdict names an effect only when the chain shrinks the held-out gap by at least this fraction
MIN_SHRINK = 0.5
#: a trend whose change over the window is this large against the baseline's systematic residual: `unexplained`
NONSTAT_FRACTION = 0.25


def fit_linear_model(records: Sequence[Any], holdout: Sequence[str]) -> Any:
    """LinearModel F = k(x − x_ref) [N/mm, mm] fitted on the training records' samples."""
    from chainid.model.base import LinearModel

    xs = np.concatenate([r.x for r in records if r.test not in set(holdout)])
    Fs = np.concatenate([r.F for r in records if r.test not in set(holdout)])
    return LinearModel.fit(xs, Fs)


def _prepare(records: Sequence[Any], n_bins: int, allow_compression: bool, steady_tol: float | None,
             strict: bool) -> tuple[list[Any], list[dict[str, str]]]:
    data, excluded = [], []
    for r in records:
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
        Jack-knife standard deviations of every step's parameters.
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

    Returns
    -------
    dict
        The JSON contract: baseline, where, ranking, verdict, plus steps (the explanation chain), excluded,
        residual, mechanism, best, confounded, interpretation, warnings, tests.

    Raises
    ------
    ValueError
        Unknown holdout id, all tests held out, fewer than 3 usable training tests, compressive records with a
        chain model without ``allow_compression``.
    """
    if not 1 <= int(max_combo) <= 3:
        raise ValueError(f"max_combo = {max_combo!r} is out of range; valid range 1 to 3")
    holdout = [h.strip() for h in holdout if h.strip()]
    ids = [r.test for r in records]
    bad = [h for h in holdout if h not in ids]
    if bad:
        raise ValueError(f"--holdout: test id(s) {bad} not in the data; valid ids: {', '.join(ids)}")
    if len(set(holdout)) >= len(set(ids)):
        raise ValueError(f"--holdout: all {len(ids)} tests are held out; leave at least {MIN_TRAIN} for training")
    is_chain = model is not None and hasattr(model, "hertz_scale")
    data, excluded = _prepare(records, n_bins, allow_compression or not is_chain, steady_tol, strict)
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
    base_c = prob.fit([]) if not prob.is_chain else Candidate("baseline", {}, 0)
    base_c.name = "baseline"
    prob.score(base_c, [], 1.0)
    base_hold = base_c.nrmse_holdout
    base_c.shrinkage = 0.0
    base = base_c._ev  # type: ignore[attr-defined]
    where = localise(prob, base)
    r2, f2, db0 = prob.noise_db(base, "hold")
    nbin = sum(d.counts.size for d in prob.hold)
    sig_hold = math.sqrt(np.mean([d.sigma**2 for d in prob.hold]))
    excess = math.sqrt(max(r2 - f2, 0.0))
    consistent = fw.at_noise_floor(r2, f2, sig_hold, nbin)

    names = [n for n in prob.applicable() if effects is None or n in effects]
    for alias, canon in fw.ALIASES.items():
        if alias in names and canon in names:
            names.remove(alias)
    fwd = fw.forward_select(prob, names, base_c, base_hold, max_effects=int(max_combo))
    path: list[Candidate] = fwd["path"]
    singles: list[Candidate] = sorted(fwd["singles"], key=lambda c: c.nrmse_loto)
    ranking = sorted(singles + [c for c in path[1:] if len(c.names) >= 2], key=lambda c: c.nrmse_loto)
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
    nonstat_material = stat["stationary"] is False and stat["trend_change_N"] >= NONSTAT_FRACTION * max(excess, 1e-300)
    if stat["stationary"] is False:
        where.insert(0, {"finding": stat["finding"], "kind": "nonstationary", "trend_change_N": stat["trend_change_N"],
                         "score": stat["trend_change_N"]})
    if consistent:
        verdict = "none"
    elif final is None or not (final.shrinkage >= MIN_SHRINK):
        verdict = "unexplained"
    else:
        verdict = "+".join(final.names)
    if verdict not in ("none",) and stat["stationary"] is False:
        named = "+".join(final.names) if final is not None else ""
        msg = (f"{stat['finding']}; " + (f"the static effects {named} absorb part of it, but what is left drifts "
               "with time" if named else "no static effect can explain it"))
        if nonstat_material:
            verdict = "unexplained"
            msg += f" (trend change {stat['trend_change_N']:.3g} N over the window vs systematic residual {excess:.3g} N: no confident name)"
        warn.append(msg)
    for c in path[1:]:
        if c.at_bound:
            warn.append(f"{c.name}: parameter(s) {', '.join(c.at_bound)} at the bound of their physical range; "
                        "the effect's form may not match the data there (read the value as a limit, not an estimate)")
    confounded = []
    for cf in fwd["confounded"]:
        confounded.append(cf | {"separate_by": separating_test(*cf["pair"])})
    if final is None and verdict == "unexplained" and best is not None:
        warn.append(f"no effect passed the step rule ({fwd['stop']})")
    interp = interpretation(path, prob, verdict)
    steps = [_step_dict(c, i) | step_fields(prob, c) for i, c in enumerate(path)]
    evaluation = {"n_bins": int(n_bins), "steady_tol": steady_tol, "allow_compression": bool(allow_compression or not is_chain)}
    models = step_models({"_problem": prob, "_path": path}, {"evaluation": evaluation})
    summary = {
        "mechanism": mechanism(verdict, interp),
        "baseline": {"nrmse_train": base_c.nrmse_train, "nrmse_holdout": base_hold, "model": getattr(model, "name", "?"),
                     "damping_law": prob.law, "damping_law_reason": prob.law_reason, "law_params": base_c.law_params,
                     "excess_rms_N": excess, "noise_sigma_N": sig_hold, "chi2_ratio": r2 / f2 if f2 > 0 else None,
                     "db_over_noise": db0, "nrmse_loto": base_c.nrmse_loto},
        "where": where,
        "ranking": [c.to_dict() for c in ranking],
        "steps": steps,
        "stop": fwd["stop"],
        "dropped": fwd["dropped"],
        "verdict": verdict,
        "best": best.to_dict() if best is not None else None,
        "residual": residual,
        "excluded": excluded,
        "confounded": confounded,
        "left_nrmse_holdout": left.nrmse_holdout,
        "interpretation": interp,
        "chain_text": " → ".join(step_text(s) for s in steps) + f" → residual {dbl:.1f} dB over noise",
        "warnings": warn,
        "holdout": list(hold_ok),
        "tests": [{"test": d.test, "omega": d.omega, "A": d.A, "x0": d.x0, "sigma_N": d.sigma, "window": d.window,
                   "split": "holdout" if d in prob.hold else "train",
                   "nrmse_before": base_c.per_test[d.test],
                   "nrmse_after": best.per_test.get(d.test) if best is not None else None} for d in prob.data],
    }
    summary["model"] = model_to_dict(models[-1])  # every fitted parameter of the last step (the model file's keys)
    summary["_problem"] = prob
    summary["_models"] = models
    summary["_best"] = final if final is not None else best
    summary["_path"] = path
    return summary


def _step_dict(c: Candidate, i: int) -> dict[str, Any]:
    f = lambda v: None if isinstance(v, float) and not math.isfinite(v) else v  # noqa: E731
    st = getattr(c, "step_test", {})
    return {
        "effect": "baseline" if i == 0 else c.names[-1],
        "effects": c.names,
        "params": {k: f(float(v)) for k, v in c.params.items() if not k.startswith("spring.")},
        "params_sd": {k: f(float(v)) for k, v in c.param_sd.items() if not k.startswith("spring.")},
        "damping_law": c.law,
        "nrmse_loto": f(c.nrmse_loto),
        "nrmse_holdout": f(c.nrmse_holdout),
        "shrinkage": f(c.shrinkage),
        "db_over_noise": f(c.db_holdout),
        "z_loto": f(float(st["z"])) if st else None,
        "relative_gain_loto": f(float(st["relative_gain"])) if st else None,
        "at_bound": list(c.at_bound),
    }


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
    v = np.array(vals)
    n = len(tr)
    sd = np.sqrt((n - 1) / n * np.sum((v - v.mean(axis=0)) ** 2, axis=0))
    return dict(zip(keys, (float(s) for s in sd)))
