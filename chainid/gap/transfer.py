"""Transfer: the chain fitted on one excitation, scored on another (``chainid diagnose --validate OTHER.csv``).

The model of each step of the diagnosis (:mod:`.modelio`: its base with the fitted spring and
mass, its effects with their parameters, its damping) is evaluated unchanged on every record of
the other set, exactly as ``chainid predict`` evaluates it:

* a model of the harmonic route on a steady harmonic test: its phase bins
  (:mod:`chainid.gap.harmonic.prepare`), the damping c_e from the fitted law at the test's ω and A;
* any other record, and every record under a model of the time-domain route: in the time domain
  (causal operators from the first sample; the damping the fitted c, a law resolved at the record's
  features; the record's own force offset where the model's offsets are per test).

The baseline of the comparison is the diagnosis' own baseline (no effect) carried over the
same way, so ``shrinkage = 1 − NRMSE_model/NRMSE_baseline`` on the other set says how much
of the gap the chain closes there.  A second pair of numbers refits only the linear part on
each record (offset, stiffness correction and viscous term: a least-squares fit of the
residual on 1, x and ẋ) with the effects frozen — what a user refitting a spring and a
dashpot would see.  The chain *transfers* when the frozen pooled shrinkage reaches ``MIN_SHRINK`` (the
bar a diagnosis needs to name an effect) and either the one after the linear refit does too (else what
the chain gains on the other set is no more than a refitted spring and dashpot would give) or the frozen
model leaves the other set at its noise floor (the diagnosis' own `none` rule on the records' σ: nothing
is left for a refit to find — a right stiffness-side effect is largely absorbed by a refitted spring).

Units: mm, N, s; NRMSE = RMS(residual)/RMS(F − mean F).
"""

from __future__ import annotations

import math
from typing import Any, Sequence

import numpy as np

from chainid.gap.core.noise import force_noise, sample_rate
from chainid.gap.core.selection import at_noise_floor
from chainid.gap.core.verdict import MIN_SHRINK, trusted_path
from chainid.gap.harmonic.prepare import Unusable, prepare_test
from chainid.gap.modelio import compared, time_force
from chainid.gap.timedomain import noisecheck
from chainid.gap.timedomain.data import MIN_SAMPLES
from chainid.model.augmented import AugmentedModel



def _refit(F: np.ndarray, Fm: np.ndarray, x: np.ndarray, v: np.ndarray, w: np.ndarray | None = None) -> np.ndarray:
    """Residual after a least-squares refit of offset, stiffness and viscous corrections (weights w)."""
    X = np.column_stack([np.ones_like(x), x, v])
    r = F - Fm
    sw = np.sqrt(w) if w is not None else np.ones_like(x)
    coef, *_ = np.linalg.lstsq(X * sw[:, None], r * sw, rcond=None)
    return r - X @ coef


def _score(model: AugmentedModel, rec: Any, n_bins: int, steady_tol: float | None, time_only: bool
           ) -> dict[str, Any]:
    """One record's errors under a step's model, evaluated as ``predict`` evaluates it (:mod:`.modelio`)."""
    d = None
    if not time_only:
        try:
            d = prepare_test(rec, n_bins=n_bins, allow_compression=True, steady_tol=steady_tol)
        except Unusable:
            d = None
    if d is not None:
        Fm = model.cycle_force(d)
        xb, v = d.gridmean(d.grid["x"]), d.gridmean(d.grid["xd"])
        w = d.counts
        var = float(np.sum(w * (d.Fbar - np.sum(w * d.Fbar) / np.sum(w)) ** 2))
        r, rr = d.Fbar - Fm, _refit(d.Fbar, Fm, xb, v, w)
        return {"route": "harmonic", "sse": float(np.sum(w * r**2)), "sse_refit": float(np.sum(w * rr**2)), "var": var,
                "r2": float(np.sum(r**2)), "f2": float(np.sum(d.sigma**2 / np.maximum(w, 1))), "n": int(r.size),
                "sigma": float(d.sigma)}
    if rec.t.size < MIN_SAMPLES:
        raise ValueError(f"--validate: test {rec.test!r} has {rec.t.size} samples; need >= {MIN_SAMPLES}")
    Fm, kin = time_force(model, rec, with_kinematics=True)
    keep = compared(model, rec, kin)  # the samples the time route compares
    F = np.asarray(rec.F, float)
    sigma = max(force_noise(F), 1e-6 * float(np.std(F)) + 1e-9)
    F, Fm = F[keep], Fm[keep]
    var = float(np.sum((F - F.mean()) ** 2))
    r, rr = F - Fm, _refit(F, Fm, kin.x[keep], kin.xd[keep])
    # the noise read from the force, read again from the model's residual where that refutes it (a force that
    # switches every few samples: chainid.gap.timedomain.noisecheck, as the diagnosis does)
    sigma = noisecheck.refuting(sigma, r, sample_rate(np.asarray(rec.t, float)), float("nan")) or sigma
    return {"route": "time", "sse": float(np.sum(r**2)), "sse_refit": float(np.sum(rr**2)), "var": var,
            "r2": float(np.sum(r**2)), "f2": float(sigma**2 * r.size), "n": int(r.size), "sigma": float(sigma)}


def transfer(result: dict[str, Any], other: Sequence[Any], n_bins: int = 64,
             steady_tol: float | None = None) -> dict[str, Any]:
    """Score the diagnosis' baseline and final chain on another set of records.

    Parameters
    ----------
    result : dict
        The result of :func:`chainid.gap.diagnose.diagnose` (its private ``_path``, the steps, and ``_models``,
        the runnable model of each step that :func:`chainid.gap.modelio.attach_models` adds; ``route``).
    other : sequence of Record
        The other excitation's records (t s, x mm, F N).

    Returns
    -------
    dict
        ``tests`` (per record: route, nrmse_baseline, nrmse_model, shrinkage and the same after the linear
        refit), ``pooled``, ``chain``, ``transfers`` (bool) and ``verdict_text``.
    """
    path, models = result["_path"], result["_models"]
    ok = trusted_path(path)[0]  # the verdict's chain: no over-fitted step
    base, final = path[0], ok[-1]
    time_only = result.get("route") == "time"
    if not other:
        raise ValueError("--validate: the other set has no records")
    rows = []
    tot = {k: 0.0 for k in ("b", "m", "br", "mr", "v", "r2", "f2", "n", "s2")}
    for rec in other:
        sb = _score(models[0], rec, n_bins, steady_tol, time_only)
        sm = _score(models[len(ok) - 1], rec, n_bins, steady_tol, time_only) if final is not base else sb
        v = sb["var"]
        nr = lambda s: math.sqrt(s / v) if v > 0 else float("nan")  # noqa: E731
        row = {"test": rec.test, "route": sb["route"], "nrmse_baseline": nr(sb["sse"]), "nrmse_model": nr(sm["sse"]),
               "nrmse_baseline_refit": nr(sb["sse_refit"]), "nrmse_model_refit": nr(sm["sse_refit"])}
        row["shrinkage"] = 1 - row["nrmse_model"] / row["nrmse_baseline"] if row["nrmse_baseline"] > 0 else float("nan")
        row["shrinkage_refit"] = (1 - row["nrmse_model_refit"] / row["nrmse_baseline_refit"]
                                  if row["nrmse_baseline_refit"] > 0 else float("nan"))
        rows.append(row)
        for k, s in (("b", sb["sse"]), ("m", sm["sse"]), ("br", sb["sse_refit"]), ("mr", sm["sse_refit"]), ("v", v),
                     ("r2", sm["r2"]), ("f2", sm["f2"]), ("n", sm["n"]), ("s2", sm["sigma"] ** 2 * sm["n"])):
            tot[k] += s
    f = lambda k: math.sqrt(tot[k] / tot["v"]) if tot["v"] > 0 else float("nan")  # noqa: E731
    pooled = {"nrmse_baseline": f("b"), "nrmse_model": f("m"), "nrmse_baseline_refit": f("br"),
              "nrmse_model_refit": f("mr")}
    pooled["shrinkage"] = 1 - pooled["nrmse_model"] / pooled["nrmse_baseline"] if pooled["nrmse_baseline"] > 0 else float("nan")
    pooled["shrinkage_refit"] = (1 - pooled["nrmse_model_refit"] / pooled["nrmse_baseline_refit"]
                                 if pooled["nrmse_baseline_refit"] > 0 else float("nan"))
    chain = "+".join(final.names) or "baseline"
    # the frozen model on the other set against its noise floor (the records' own σ: time samples σ², harmonic bins
    # σ²/n), the rule of the diagnosis' own `none`
    n = max(int(tot["n"]), 1)
    r2, f2 = tot["r2"] / n, tot["f2"] / n
    floor = at_noise_floor(r2, f2, math.sqrt(tot["s2"] / n), n)
    pooled["model_db_over_noise"] = 10 * math.log10(max(r2, 1e-300) / max(f2, 1e-300))
    pooled["model_at_noise_floor"] = bool(floor)
    # the chain must close half the gap against the carried-over baseline, and either leave the other set at its
    # noise floor or close half the gap against a spring and a dashpot refitted on each record (else the gain is
    # only what a refit of the linear part would give)
    ok = bool(final is not base and pooled["shrinkage"] >= MIN_SHRINK
              and (floor or pooled["shrinkage_refit"] >= MIN_SHRINK))
    kinds = sorted({r["route"] for r in rows})
    txt = (f"the chain {chain} {'TRANSFERS' if ok else 'does NOT transfer'} to the other set ({len(rows)} "
           f"{'/'.join(kinds)} record(s)): pooled NRMSE baseline {pooled['nrmse_baseline']:.3g} → model "
           f"{pooled['nrmse_model']:.3g} (shrinkage {100 * pooled['shrinkage']:.0f} %); with offset, "
           f"stiffness and viscous term refitted per record {pooled['nrmse_baseline_refit']:.3g} → "
           f"{pooled['nrmse_model_refit']:.3g} (shrinkage {100 * pooled['shrinkage_refit']:.0f} %); the model "
           f"leaves {pooled['model_db_over_noise']:.1f} dB over the other set's noise"
           f"{' (at its noise floor)' if floor else ''}; it transfers when the first reaches {100 * MIN_SHRINK:.0f} % "
           f"and the second does too or the model is at the noise floor")
    if final is base:
        txt = (f"no effect was named on the fitting set; on the other set the baseline leaves NRMSE "
               f"{pooled['nrmse_baseline']:.3g} ({pooled['nrmse_baseline_refit']:.3g} after the linear refit)")
    return {"chain": chain, "tests": rows, "pooled": pooled, "transfers": ok, "verdict_text": txt}
