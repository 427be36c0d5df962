"""Terminal summary and JSON contract of ``chainid diagnose``."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from chainid.gap.core.verdict import none_text


def _clean(o: Any) -> Any:
    if isinstance(o, dict):
        return {k: _clean(v) for k, v in o.items() if not str(k).startswith("_")}
    if isinstance(o, (list, tuple)):
        return [_clean(v) for v in o]
    if isinstance(o, float):
        return o if math.isfinite(o) else None
    if hasattr(o, "item"):
        return _clean(o.item())
    return o


def to_json(result: dict[str, Any]) -> dict[str, Any]:
    """The JSON contract: baseline, where, ranking (best first), verdict (+ extras); private keys dropped."""
    return _clean(result)


def write_json(result: dict[str, Any], path: str | Path, overwrite: bool = False) -> Path:
    """Write the JSON contract; refuses to overwrite an existing file unless asked."""
    from chainid.infra.fileio import write_json as _write  # strict JSON, temp file + rename

    p = Path(path)
    _write(to_json(result), p, force=overwrite, what="--json")
    return p


def _params(p: dict[str, Any], sd: dict[str, Any] | None = None, bound: Any = (),
            ci: dict[str, Any] | None = None) -> str:
    """``name=value`` of each parameter with its spread: the resampled 90 % interval ``[lo, hi]`` where ``ci`` has
    one (a resampled diagnosis), else ``±`` the jack-knife standard deviation ``sd``; "(at bound)" on a bound;
    "(sd not resolved)" where ``sd`` holds None for it (the refits did not move it:
    :func:`chainid.gap.core.candidate.jackknife_sd`)."""
    sd, ci = sd or {}, ci or {}
    out = []
    for k, v in p.items():
        if v is None or k.startswith("law.") or k.startswith("spring."):
            continue
        s = f"{k}={v:.4g}"
        unmoved = k in sd and (sd[k] is None or sd[k] == 0 or not math.isfinite(sd[k]))
        at_bound = k in bound or (v == 0 and unmoved)  # a zero estimate that no refit moves sits on a bound
        if ci.get(k) is not None and not at_bound:
            s += f" [{ci[k][0]:.4g}, {ci[k][1]:.4g}]"
        elif unmoved and not at_bound:
            s += " (sd not resolved)"
        elif sd.get(k) is not None and not at_bound:
            s += f"±{sd[k]:.2g}"
        if at_bound:
            s += " (at bound)"
        out.append(s)
    return ", ".join(out)


def _g(v: Any, spec: str) -> str:
    """``v`` formatted by ``spec`` (e.g. ``">9.4g"``), or "n/a" at the same width where it is None or not finite
    (a held-out score that could not be computed)."""
    ok = isinstance(v, (int, float)) and math.isfinite(v)
    width = "".join(ch for ch in spec.split(".")[0] if ch.isdigit() or ch in "<>")
    return format(v, spec) if ok else format("n/a", width)


def waterfall(result: dict[str, Any]) -> list[str]:
    """The explanation chain as table lines: step, effect, held-out NRMSE, held-out fit % ("n/a" for a step
    without one), shrinkage, dB over noise, params.  A resampled result gives each parameter of the steps it
    resampled (the kept chain) its 90 % interval over the resamples, and each step its share of them; a step
    outside the kept chain keeps ± its jack-knife standard deviation, and says so."""
    steps = result.get("steps", [])
    resampled = "stability" in result
    lines = [f"  {'step':<5} {'+ effect':<20} {'LOTO':>8} {'held-out':>9} {'fit %':>6} {'shrink':>7} {'dB/noise':>8}"
             "  parameters" + (" [90 % interval over the resamples]; the share of resamples that choose the step"
                               if resampled else " ± jack-knife standard deviation")]
    kept = result.get("trusted_steps", len(steps))
    for i, st in enumerate(steps):
        mark = ("" if not st.get("worsened_holdout") else "  << raised the held-out error: over-fitted" if i >= kept
                else "  << raised the held-out error alone (kept: the next step(s) take it lower)")
        if st.get("rate_cut"):
            mark = ("  << changes with the speed: rate-dependent, not kept (see where)" if st.get("rate_dependent")
                    else "  << after a rate-dependent step: not kept")
        if resampled and i > 0 and not st.get("params_ci90") and st.get("params_sd"):
            mark = " (± jack-knife: not resampled)" + mark
        lines.append(f"  {i:<5} {st['effect']:<20} {_g(st['nrmse_loto'], '>8.4g')} {_g(st['nrmse_holdout'], '>9.4g')} "
                     f"{_g(st.get('fit_holdout_pct'), '>6.1f')} {100 * (st['shrinkage'] or 0):>6.1f}% "
                     f"{_g(st['db_over_noise'], '>8.1f')}  "
                     f"{_params(st['params'], st.get('params_sd'), st.get('at_bound', ()), st.get('params_ci90'))}"
                     f"{_chosen(st)}{mark}")
    r = result.get("residual") or {}
    if r:
        stat = {True: "stationary", False: "NOT stationary", None: "stationarity not checked"}[r.get("stationary")]
        lines.append(f"  left: {r['db_over_noise']:.1f} dB over the noise floor"
                     f"{' (at the floor)' if r.get('at_noise_floor') else ''}; {stat}")
    return lines


def _chosen(step: dict[str, Any]) -> str:
    """How often the resamples choose a step (:mod:`chainid.gap.core.resample`), "" when not resampled."""
    share = step.get("stability")
    return f"; chosen in {100 * share:.0f} % of resamples" if share is not None else ""


def _left(result: dict[str, Any]) -> str:
    """What is left in absolute terms: the held-out fit % = 100·(1 − NRMSE) and the residual in noise σ."""
    left = result.get("left_nrmse_holdout")
    r = result.get("residual") or {}
    db = r.get("db_over_noise")
    ratio = f"{10 ** (db / 20):.2f}× the noise floor" if db is not None and math.isfinite(db) else "unknown vs noise"
    return (f"fit left {100 * (1 - left):.1f} % (held-out NRMSE {left:.4g}), residual {ratio}"
            if left is not None and math.isfinite(left) else "no held-out fit")


def summary(result: dict[str, Any], n_rank: int = 6) -> str:
    """Readable terminal summary: where, which (the explanation chain), how much, what is left.

    How much is the kept chain's held-out NRMSE (``left_nrmse_holdout``, dimensionless) against the baseline's; a
    result without that number (or with None) prints "n/a" for it and its shrinkage.
    """
    b = result["baseline"]
    lines = [
        f"Baseline ({b['model']}, damping law: {b['damping_law']}): NRMSE train {b['nrmse_train']:.4g}, "
        f"held-out {b['nrmse_holdout']:.4g} ({b['db_over_noise']:.1f} dB over the noise floor; systematic "
        f"{b['excess_rms_N']:.4g} N vs noise σ {b['noise_sigma_N']:.4g} N)",
    ]
    if b.get("damping_law_reason") and b["damping_law_reason"] != "given":
        lines.append(f"  damping law: {b['damping_law_reason']}")
    for e in result.get("excluded", []):
        lines.append(f"  excluded test {e['test']}: {e['reason']}")
    lines += ["", "WHERE the model misses (largest first):"]
    lines += [f"  - {f['finding']}" for f in result["where"][:8]]
    unit = "leave-one-block/test-out" if result.get("route") in ("time", "mixed") else "leave-one-test-out"
    lines += ["", f"WHICH effects, in order (each fitted on top of the previous ones; scored {unit}):"]
    lines += waterfall(result)
    if result.get("stop"):
        lines.append(f"  the chain stops: {result['stop']}")
    lines += ["", "Each effect alone on the baseline (ranking):"]
    lines.append(f"  {'effect':<30} {'LOTO':>8} {'held-out':>9} {'shrink':>7}  params")
    for c in result["ranking"][:n_rank]:
        shrink = 100 * c["shrinkage"] if isinstance(c.get("shrinkage"), (int, float)) else None
        lines.append(f"  {c['effect']:<30} {_g(c['nrmse_loto'], '>8.4g')} {_g(c['nrmse_holdout'], '>9.4g')} "
                     f"{_g(shrink, '>6.1f')}%  {_params(c['params'], None, c.get('at_bound', ()))}")
    for cf in result.get("confounded", []):
        lines.append(f"  confounded: {cf['pair'][0]} ~ {cf['pair'][1]}; to separate them: {cf['separate_by']}")
    lines.append("")
    v = result["verdict"]
    if v == "none":
        lines.append(f"VERDICT: none — {none_text(result)}.")
    elif v == "unexplained":
        lines.append(f"VERDICT: unexplained — {_unexplained_why(result)}; {_left(result)}.")
    else:
        lines += _named_lines(result)
    for cd in result.get("covariate_dependence") or []:
        lines.append(f"  operating condition: {cd['text']}")
    ow = result.get("open_world") or {}
    if ow.get("message"):
        lines.append(f"  model-free check: {ow['message']}")
    if result.get("interpretation"):
        lines.append(f"  meaning: {result['interpretation']}")
    if result.get("mechanism") and result["mechanism"] not in ("none", "unexplained"):
        lines.append(f"  mechanism: {result['mechanism']}")
    for w in result.get("warnings", []):
        lines.append(f"WARNING: {w}")
    return "\n".join(lines)


def _unexplained_why(result: dict[str, Any]) -> str:
    """Why an ``unexplained`` verdict names nothing: a drift in time, a part of the gap, a rate-dependent loop, an
    over-fitted step, or no effect passing the rule or shrinking the gap by half."""
    part = result.get("partial")
    if (result.get("residual") or {}).get("stationary") is False:
        return "what is left changes with time within the tests (no static effect explains that)"
    if part:
        return (f"{part['effects']} passed the step rule and holds on the held-out data (held-out NRMSE "
                f"{part['nrmse_holdout_before']:.4g} → {part['nrmse_holdout']:.4g}, {100 * part['shrinkage']:.0f} %), "
                f"but closes less than {100 * part['min_shrink']:.0f} % of the held-out gap: a part of it, not its "
                "cause")
    if (result.get("rate_dependence") or {}).get("step") == 1:
        rd = result["rate_dependence"]
        return (f"{rd['effect']} passed the step rule, but its {rd['parameter']} changes with the speed (∝ v^"
                f"{rd['exponent']:.2f}) where its form is rate-independent: it stands in for a rate-dependent "
                "mechanism outside the library")
    if result.get("overfitted") and result.get("trusted_steps", 1) <= 1:
        cut = result["steps"][1]
        before, after = result["baseline"]["nrmse_holdout"], cut["nrmse_holdout"]
        return (f"{cut['effect']} passed the step rule on the training data but did not hold on the held-out "
                f"data (held-out NRMSE {_g(before, '.4g')} → {_g(after, '.4g')}): over-fitted, not kept")
    floor = "(or its part above the kinematic floor) " if result.get("route") in ("time", "mixed") else ""
    return f"no library effect passed the step rule or shrinks the held-out gap {floor}by half"


def _named_lines(result: dict[str, Any]) -> list[str]:
    """The verdict lines of a named chain: the chain, the held-out NRMSE before and after with the shrinkage (and,
    on the time route, the share of the gap above the kinematic floor), what is left."""
    b = result["baseline"]
    left = result.get("left_nrmse_holdout")  # absent from a result made before it was in the contract
    known = left is not None and math.isfinite(left)
    shrink = (f"{100 * (1.0 - left / b['nrmse_holdout']):.0f} %" if known and b["nrmse_holdout"] else "n/a")
    above = (result.get("residual") or {}).get("shrinkage_above_kinematic_floor")
    above = (f"; {100 * above:.0f} % of the gap above the kinematic floor, the part a model could close"
             if isinstance(above, (int, float)) and math.isfinite(above) else "")
    return [f"VERDICT: {result['verdict']} — {result.get('chain_text', '')}",
            f"  held-out NRMSE {b['nrmse_holdout']:.4g} → {f'{left:.4g}' if known else 'n/a'} "
            f"(shrinkage {shrink}{above}); {_left(result)}"]
