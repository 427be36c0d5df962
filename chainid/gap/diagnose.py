"""`chainid diagnose`: where the model misses, which effect causes it, how much it shrinks."""

from __future__ import annotations

import itertools
import math
import warnings
from typing import Any, Sequence

import numpy as np

from .select import Candidate, Problem, damping_separable, prepare_test
from .where import localise

#: systematic residual below this fraction of the raw noise σ counts as "consistent with the noise"
NONE_FRACTION = 0.5
#: a combination must lower the LOTO NRMSE by this factor over its best part
COMBO_GAIN = 0.85
#: candidates within this relative LOTO NRMSE of the best are "equally good" (confounded)
TIE = 0.05


def fit_linear_model(records: Sequence[Any], holdout: Sequence[str]) -> Any:
    """LinearModel F = k(x − x_ref) fitted on the training records' samples."""
    from ..models import LinearModel

    xs = np.concatenate([r.x for r in records if r.test not in set(holdout)])
    Fs = np.concatenate([r.F for r in records if r.test not in set(holdout)])
    return LinearModel.fit(xs, Fs)


def diagnose(
    records: Sequence[Any],
    holdout: Sequence[str],
    model: Any | None = None,
    *,
    effects: Sequence[str] | None = None,
    max_combo: int = 2,
    n_bins: int = 64,
    uncertainty: bool = True,
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
        Largest combination size (1–3).

    Returns
    -------
    dict
        The JSON contract: baseline, where, ranking, verdict (+ warnings, noise, confounded).

    Raises
    ------
    ValueError
        Unknown holdout id, all tests held out, fewer than 6 training tests.
    """
    holdout = [h.strip() for h in holdout if h.strip()]
    ids = [r.test for r in records]
    bad = [h for h in holdout if h not in ids]
    if bad:
        raise ValueError(f"--holdout: test id(s) {bad} not in the data; valid ids: {', '.join(ids)}")
    if len(set(holdout)) >= len(set(ids)):
        raise ValueError(f"--holdout: all {len(ids)} tests are held out; leave at least 6 for training")
    if model is None:
        model = fit_linear_model(records, holdout)
    data = [prepare_test(r, n_bins=n_bins) for r in records]
    prob = Problem(data, model, holdout)
    warn: list[str] = []
    ok, msg = damping_separable(prob.train)
    if not ok:
        warn.append(msg)
        warnings.warn(msg, stacklevel=2)
    base_c = prob.fit([]) if not prob.is_chain else Candidate("baseline", {}, 0)
    base = prob.evaluate([], base_c.params)
    base_hold = base["nrmse_holdout"]
    where = localise(prob, base)
    # noise consistency on held-out tests
    nbin = sum(d.counts.size for d in prob.hold)
    mean_r2 = sum(float(np.sum(base["res"][d.test] ** 2)) for d in prob.hold) / nbin
    floor2 = sum(float(np.sum(d.sigma**2 / np.maximum(d.counts, 1))) for d in prob.hold) / nbin
    excess = math.sqrt(max(mean_r2 - floor2, 0.0))
    sig_hold = math.sqrt(np.mean([d.sigma**2 for d in prob.hold]))
    chi_ratio = mean_r2 / floor2 if floor2 > 0 else float("inf")
    consistent = excess < NONE_FRACTION * sig_hold or chi_ratio < 1 + 5 * math.sqrt(2.0 / nbin)

    names = [n for n in prob.applicable() if effects is None or n in effects]
    singles: list[Candidate] = []
    fitted: dict[tuple[str, ...], Candidate] = {}
    for n in names:
        c = prob.score(prob.fit([n]), [n], base_hold)
        fitted[(n,)] = c
        singles.append(c)
    singles.sort(key=lambda c: c.nrmse_loto)
    combos: list[Candidate] = []
    if max_combo >= 2 and singles:
        top = [c.name for c in singles[:3]]
        for k in range(2, min(max_combo, 3) + 1):
            for combo in itertools.combinations(top, k):
                cn = list(combo)
                c = prob.score(prob.fit(cn), cn, base_hold)
                fitted[tuple(cn)] = c
                combos.append(c)
    ranking = sorted(singles + combos, key=lambda c: c.nrmse_loto)
    # choose: best single; a combination only if clearly better than its best part
    best = singles[0] if singles else None
    for c in sorted(combos, key=lambda c: c.nrmse_loto):
        parts = [fitted[(p,)] for p in c.name.split("+")]
        if c.nrmse_loto < COMBO_GAIN * min(p.nrmse_loto for p in parts) and best is not None and \
                c.nrmse_loto < COMBO_GAIN * best.nrmse_loto:
            best = c
            break
    confounded = []
    if best is not None:
        for c in singles:
            if c is not best and "+" not in best.name and c.nrmse_loto <= (1 + TIE) * best.nrmse_loto:
                confounded.append({"pair": [best.name, c.name],
                                   "loto": [best.nrmse_loto, c.nrmse_loto],
                                   "separate_by": _separating_test(best.name, c.name)})
        # prefer the simpler among equals (BIC)
        ties = [c for c in singles if c.nrmse_loto <= (1 + TIE) * best.nrmse_loto and "+" not in best.name]
        if ties:
            simplest = min(ties, key=lambda c: (c.n_params, c.bic))
            if simplest.n_params < best.n_params:
                best = simplest
    if best is not None and best.at_bound and best.shrinkage >= 0.5:
        warn.append(f"{best.name}: parameter(s) {', '.join(best.at_bound)} at the bound of their physical range; "
                    "the effect's form may not match the data there (read the value as a limit, not an estimate)")
    if best is not None and uncertainty and best.n_params > 0:
        best.param_sd = _jackknife(prob, best)
    if consistent:
        verdict = "none"
    elif best is None or not (best.shrinkage >= 0.5):
        verdict = "unexplained"
    else:
        verdict = best.name
    drift = [f for f in where if f.get("kind") == "drift"]
    if drift and verdict not in ("none",) and drift[0]["drift_N"] > 0.25 * excess:
        verdict = "unexplained"
    left = best.nrmse_holdout if best is not None else base_hold
    interp = ""
    if best is not None and "hysteresis" in verdict.split("+"):
        xh = best.params.get("hysteresis.x_h", float("nan"))
        amin = min(d.A for d in prob.data)
        if xh < 0.5 * amin:
            interp = (f"Dahl-type hysteresis with transition travel x_h = {xh:.3g} mm << A (>= {amin:.3g} mm): "
                      "rate-independent frictional sliding with smooth pre-sliding (Dahl friction)")
    summary = {
        "mechanism": _mechanism(verdict, interp),
        "baseline": {"nrmse_train": base["nrmse_train"], "nrmse_holdout": base_hold, "model": getattr(model, "name", "?"),
                     "damping_law": "polynomial", "law_params": base["law_params"],
                     "excess_rms_N": excess, "noise_sigma_N": sig_hold, "chi2_ratio": chi_ratio,
                     "db_over_noise": 10 * math.log10(max(mean_r2, 1e-300) / max(floor2, 1e-300))},
        "where": where,
        "ranking": [c.to_dict() for c in ranking],
        "verdict": verdict,
        "best": best.to_dict() if best is not None else None,
        "confounded": confounded,
        "left_nrmse_holdout": left,
        "interpretation": interp,
        "warnings": warn,
        "holdout": list(holdout),
        "tests": [{"test": d.test, "omega": d.omega, "A": d.A, "x0": d.x0, "sigma_N": d.sigma,
                   "split": "holdout" if d in prob.hold else "train",
                   "nrmse_before": base["per_test"][d.test],
                   "nrmse_after": best.per_test.get(d.test) if best is not None else None} for d in prob.data],
    }
    summary["_problem"] = prob
    summary["_best"] = best
    return summary


#: The physical family of each library effect, in an engineer's words (JSON field ``mechanism``).
MECHANISM = {"friction": "friction", "hysteresis": "hysteresis", "backlash": "play",
             "slack": "displacement offset", "machine_compliance": "stiffness", "contact_law": "stiffness",
             "sensor_delay": "instrumentation", "damping_law": "damping form"}


def _mechanism(verdict: str, interpretation: str) -> str:
    """The verdict's physical families joined by ``+`` (Dahl hysteresis with x_h << A counts as friction).

    ``none`` and ``unexplained`` map to themselves.
    """
    if verdict in ("none", "unexplained"):
        return verdict
    fams: list[str] = []
    for name in verdict.split("+"):
        fam = MECHANISM.get(name, name)
        if name == "hysteresis" and "Dahl friction" in interpretation:
            fam = "friction"
        if fam not in fams:
            fams.append(fam)
    return "+".join(fams)


def _separating_test(a: str, b: str) -> str:
    s = {a, b}
    if s == {"friction", "hysteresis"}:
        return "a small-amplitude test (A comparable to the hysteresis travel x_h) separates sliding from smooth hysteresis"
    if "sensor_delay" in s:
        return "tests over a wider frequency range (a delay's phase grows with ω)"
    if "damping_law" in s or "friction" in s:
        return "tests over a wider amplitude range at fixed ω (Coulomb ∝ 1/A, viscous ∝ 1)"
    return "tests over a wider mean-load range x0 (stiffness-side effects scale differently with load)"


def _jackknife(prob: Problem, cand: Candidate) -> dict[str, float]:
    """Parameter standard deviations by leave-one-test-out refits (jackknife over training tests)."""
    names = [n for n in cand.name.split("+")]
    vals = []
    tr = prob.train
    for i in range(len(tr)):
        sub = tr[:i] + tr[i + 1 :]
        c = prob.fit(names, train_only=sub)
        vals.append([c.params.get(k, float("nan")) for k in cand.params if not k.startswith("law.")])
    keys = [k for k in cand.params if not k.startswith("law.")]
    v = np.array(vals)
    n = len(tr)
    sd = np.sqrt((n - 1) / n * np.sum((v - v.mean(axis=0)) ** 2, axis=0))
    return dict(zip(keys, (float(s) for s in sd)))
