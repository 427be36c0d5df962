"""The verdict rule of the diagnosis, one for both routes (phase bins and time domain).

* ``none`` — the baseline's held-out residual is consistent with the noise (on the time route also when no
  effect passes, the model-free check is silent and the route reads the residual as the kinematic floor or as
  the base's damping law extrapolated: ``chainid.gap.timedomain.route.read_as_none``, passed in as
  ``consistent``);
* the chain's effects — the chain shrinks the held-out gap by at least ``MIN_SHRINK``, or (time route) closes at
  least ``MIN_SHRINK`` of the gap above the kinematic floor, the part a model could close (:func:`floor_shrunk`);
* ``unexplained`` — otherwise, or when what is left drifts with time by at least
  ``NONSTAT_FRACTION`` of the baseline's systematic residual (no static effect explains a drift).
"""

from __future__ import annotations

import math
from typing import Any

#: the verdict names an effect only when the chain shrinks the held-out gap by at least this fraction
MIN_SHRINK = 0.5
#: a trend whose change over the window is this large against the baseline's systematic residual: `unexplained`
NONSTAT_FRACTION = 0.25


def floor_shrunk(final: Any) -> bool:
    """Whether the chain closes at least ``MIN_SHRINK`` of the held-out gap that a model could close: the gap above
    the kinematic floor (``shrinkage_floor``, set by the time route:
    :func:`chainid.gap.timedomain.route.floor_shrinkage`; absent or None elsewhere)."""
    s = getattr(final, "shrinkage_floor", None)
    return s is not None and math.isfinite(s) and s >= MIN_SHRINK


def trusted_path(path: list[Any]) -> tuple[list[Any], int | None]:
    """The explanation chain up to its step with the lowest held-out NRMSE (the last of equal ones), and the
    index of the step after it (None when the chain ends there).

    The steps after the held-out minimum were chosen by the training data and refuted by the held-out data:
    over-fitting, never in the verdict.  A step inside the kept chain that raised the held-out error on its own
    is kept: the steps after it take the held-out error below every shorter chain's, so the held-out data support
    the chain as a whole (:func:`joint_notes` says so).  With a non-finite held-out score anywhere the chain is
    cut at its first rise instead.
    """
    h = [c.nrmse_holdout for c in path]
    if not all(isinstance(v, (int, float)) and math.isfinite(v) for v in h):
        for i in range(1, len(path)):
            if not (path[i].nrmse_holdout <= path[i - 1].nrmse_holdout):
                return path[:i], i
        return list(path), None
    lowest = min(h)
    j = max(i for i, v in enumerate(h) if v <= lowest)
    return list(path[: j + 1]), (j + 1 if j + 1 < len(path) else None)


def kept_path(path: list[Any], fwd: dict[str, Any]) -> tuple[list[Any], int | None]:
    """The verdict's chain and its first over-fitted step (:func:`trusted_path`), of the whole explanation chain or,
    where a route cut it (the time route's rate check: ``fwd["rate_dependence"]["step"]``), of the steps before
    the cut: the shorter chain is trimmed to its own held-out minimum, as the whole one is."""
    rate = fwd.get("rate_dependence")
    return trusted_path(list(path)[: rate["step"]] if rate else list(path))


def fallback_best(singles: list[Any], fwd: dict[str, Any]) -> Any:
    """The best single effect to report when no chain is kept (``singles`` sorted by LOTO), leaving out an effect
    the route cut as rate-dependent; None when there is none."""
    cut = (fwd.get("rate_dependence") or {}).get("name")
    return next((c for c in singles if cut not in c.names), None)


def overfit_warning(path: list[Any], k: int) -> str:
    """The warning for a chain whose step ``k`` (the first after the held-out minimum) raised the held-out error."""
    a, b = path[k - 1].nrmse_holdout, path[k].nrmse_holdout
    return (f"over-fitted: step {k} ({path[k].names[-1]}) raised the held-out NRMSE from {a:.4g} to {b:.4g} "
            f"({100 * (b / a - 1):+.1f} %); the verdict and what is left are those of the chain before it")


def partial_explanation(verdict: str, final: Any, base: Any) -> dict[str, Any] | None:
    """What an ``unexplained`` verdict still explains: the kept chain's effects when they passed the step rule
    and lower the held-out error, but by less than ``MIN_SHRINK`` of the baseline's (a part of the gap, not its
    cause); None otherwise."""
    if verdict != "unexplained" or final is None or not (final.shrinkage and final.shrinkage > 0):
        return None
    return {"effects": verdict_name(final.names), "terms": list(final.names), "shrinkage": float(final.shrinkage),
            "nrmse_holdout_before": float(base.nrmse_holdout), "nrmse_holdout": float(final.nrmse_holdout),
            "min_shrink": MIN_SHRINK}


def joint_notes(ok_path: list[Any]) -> list[str]:
    """Notes on the steps of the kept chain that raised the held-out error on their own (see :func:`trusted_path`):
    the held-out data support those effects only together with the steps after them."""
    out = []
    for k in range(1, len(ok_path) - 1):
        a, b = ok_path[k - 1].nrmse_holdout, ok_path[k].nrmse_holdout
        if b > a:
            out.append(f"step {k} ({ok_path[k].names[-1]}) alone raised the held-out NRMSE from {a:.4g} to {b:.4g}; "
                       f"with the step(s) after it the chain reaches {ok_path[-1].nrmse_holdout:.4g}: the held-out "
                       "data support these effects together, not one by one")
    return out


def verdict_name(names: list[str]) -> str:
    """The verdict of an explanation chain's terms: its library effects joined by ``+``; a covariate term
    (``effect.param@cov``) names its effect, the base's damping following a covariate names ``damping_law`` and the
    base's spring ``stiffness_level``."""
    out: list[str] = []
    for n in names:
        if "@" in n:
            head = n.split("@", 1)[0].split(".", 1)[0]
            n = {"damping": "damping_law", "spring": "stiffness_level", "mass": "fixture_mass"}.get(head, head)
        if n not in out:
            out.append(n)
    return "+".join(out)


def decide(consistent: bool, final: Any, stat: dict[str, Any], excess: float, path: list[Any], fwd: dict[str, Any],
           where: list[dict[str, Any]], warn: list[str], best: Any = None) -> str:
    """The verdict; adds the non-stationarity finding to ``where`` and the warnings to ``warn``.

    Parameters
    ----------
    consistent : the baseline's held-out residual is at the noise floor
    final : the last candidate of the chain (None: no effect passed the step rule)
    stat : stationarity result (``stationary``, ``trend_change_N``, ``finding``)
    excess : the baseline's systematic held-out residual RMS [N]
    path, fwd : the explanation chain and the forward selection's result
    """
    nonstat_material = stat["stationary"] is False and stat["trend_change_N"] >= NONSTAT_FRACTION * max(excess, 1e-300)
    if stat["stationary"] is False:
        where.insert(0, {"finding": stat["finding"], "kind": "nonstationary", "trend_change_N": stat["trend_change_N"],
                         "score": stat["trend_change_N"]})
    if consistent:
        verdict = "none"
    elif final is None or not (final.shrinkage >= MIN_SHRINK or floor_shrunk(final)):
        verdict = "unexplained"
    else:
        verdict = verdict_name(final.names)
    if verdict != "none" and stat["stationary"] is False:
        named = "+".join(final.names) if final is not None else ""
        msg = (f"{stat['finding']}; " + (f"the static effects {named} absorb part of it, but what is left drifts "
               "with time" if named else "no static effect can explain it"))
        if nonstat_material:
            verdict = "unexplained"
            msg += (f" (trend change {stat['trend_change_N']:.3g} N over the window vs systematic residual "
                    f"{excess:.3g} N: no confident name)")
        warn.append(msg)
    for c in path[1:]:
        if c.at_bound:
            warn.append(f"{c.name}: parameter(s) {', '.join(c.at_bound)} at the bound of their physical range; "
                        "the effect's form may not match the data there (read the value as a limit, not an estimate)")
    if final is None and verdict == "unexplained" and best is not None and len(path) <= 1:
        # (steps that passed it and were cut as over-fitted have their own warning: overfit_warning)
        warn.append(f"no effect passed the step rule ({fwd['stop']})")
    return verdict


def contract(prob: Any, model: Any, base_c: Any, noise: dict[str, Any], fwd: dict[str, Any], verdict: str,
             interp: str, residual: dict[str, Any], where: list[dict[str, Any]], excluded: list[dict[str, str]],
             confounded: list[dict[str, Any]], warn: list[str], holdout: list[str], tests: list[dict[str, Any]]
             ) -> dict[str, Any]:
    """The JSON contract of ``chainid diagnose`` (both routes): baseline, where, ranking, steps, verdict, …

    ``noise`` holds the baseline's excess_rms_N, noise_sigma_N, chi2_ratio and db_over_noise.  The private
    keys ``_problem``, ``_best`` and ``_path`` carry the fitted objects (plots, transfer).
    """
    from chainid.gap.core.interpret import covariate_dependence, mechanism, step_dict

    path = fwd["path"]
    singles = sorted(fwd["singles"], key=lambda c: c.nrmse_loto)
    ranking = sorted(singles + [c for c in path[1:] if len(c.names) >= 2], key=lambda c: c.nrmse_loto)
    ok_path, bad = kept_path(path, fwd)
    final = ok_path[-1] if len(ok_path) > 1 else None
    best = final if final is not None else fallback_best(singles, fwd)
    left = final if final is not None else base_c
    steps = [step_dict(c, i, path[i - 1] if i else None) for i, c in enumerate(path)]
    rate = fwd.get("rate_dependence")
    for st in steps[rate["step"]:] if rate is not None else []:
        st["rate_cut"] = True  # the rate-dependent step and those after it: not kept
    if rate is not None:
        steps[rate["step"]]["rate_dependent"] = True
    return {
        "mechanism": mechanism(verdict, interp),
        "baseline": {"nrmse_train": base_c.nrmse_train, "nrmse_holdout": base_c.nrmse_holdout,
                     "model": getattr(model, "name", "?"), "damping_law": prob.law,
                     "damping_law_reason": prob.law_reason, "law_params": base_c.law_params, **noise,
                     "nrmse_loto": base_c.nrmse_loto},
        "where": where,
        "ranking": [c.to_dict() for c in ranking],
        "steps": steps,
        "stop": fwd["stop"],
        "dropped": fwd["dropped"],
        "verdict": verdict,
        "none_reading": "noise" if verdict == "none" else None,
        "best": best.to_dict() if best is not None else None,
        "residual": residual,
        "trusted_steps": len(ok_path),
        "partial": partial_explanation(verdict, final, base_c),
        "excluded": excluded,
        "confounded": confounded,
        "left_nrmse_holdout": left.nrmse_holdout,
        "fit_holdout_pct": 100.0 * (1.0 - left.nrmse_holdout),
        "covariate_dependence": covariate_dependence(left.params),
        "overfitted": bad is not None,
        "rate_dependence": rate,
        "rate_checks": fwd.get("rate_checks"),
        "rejected": fwd.get("rejected", [])[:6],
        "interpretation": interp,
        "chain_text": chain_text(steps, len(ok_path), residual),
        "warnings": warn,
        "holdout": holdout,
        "tests": tests,
        "_problem": prob,
        "_best": best,
        "_path": path,
    }


#: what a ``none`` verdict says, by how the baseline's held-out residual was read (the result's ``none_reading``)
NONE_TEXT = {
    "noise": "the baseline's held-out residual is consistent with the noise",
    "kinematic_floor": ("the baseline's held-out residual is at the kinematic floor (the force noise and the "
                        "displacement noise through the estimated ẋ, ẍ); no effect passes the step rule and no state "
                        "variable predicts what is left"),
    "damping_extrapolation": ("no effect differs: the held-out gap is the base's damping law read beyond the training "
                              "records, and on their own dashpots the held-out records are at their noise floor (see "
                              "the finding `damping_extrapolation`)"),
}


def none_text(result: dict[str, Any]) -> str:
    """The sentence a ``none`` verdict ends with, by its ``none_reading`` (:data:`NONE_TEXT`; ``noise`` when absent)."""
    return NONE_TEXT.get(result.get("none_reading") or "noise", NONE_TEXT["noise"])


def chain_text(steps: list[dict[str, Any]], kept: int, residual: dict[str, Any]) -> str:
    """The explanation chain in one line: each step's text (:func:`chainid.gap.core.interpret.step_text`; the
    first ``kept`` steps are the kept chain), then the residual over the noise and the kinematic floor."""
    from chainid.gap.core.interpret import step_text

    return (" → ".join(step_text(s, i < kept) for i, s in enumerate(steps))
            + f" → residual {residual['db_over_noise']:.1f} dB over noise" + kinematic_floor_text(residual))


def kinematic_floor_text(residual: dict[str, Any]) -> str:
    """The residual over the kinematic floor (what even the true model leaves on the estimated ẋ, ẍ), where it
    tells more than the force noise alone: the floor ≥ 1 dB above the noise."""
    kf, nf = residual.get("kinematic_floor_N"), residual.get("noise_floor_N")
    db = residual.get("db_over_kinematic_floor")
    if kf is None or nf is None or db is None or nf <= 0 or 20.0 * math.log10(max(kf, 1e-300) / nf) < 1.0:
        return ""
    if db < 0:  # the bound from the kinematics' predicted errors is loose here: the fit beats it
        return (f" (below the kinematic floor {kf:.3g} N by {-db:.1f} dB: the kinematics' predicted error is an upper "
                "bound here)")
    return f" ({db:+.1f} dB over the kinematic floor {kf:.3g} N)"
