"""The diagnosis in an engineer's words: mechanisms, step texts, how to separate confounded effects."""

from __future__ import annotations

import math
from typing import Any, Sequence

from chainid.gap.core.steprule import SIMPLER

#: The physical family of each library effect (JSON field ``mechanism``).
MECHANISM = {"friction": "friction", "hysteresis": "hysteresis", "backlash": "play",
             "slack": "displacement offset", "machine_compliance": "stiffness", "contact_law": "stiffness",
             "stiffness_level": "stiffness", "sensor_delay": "instrumentation", "damping_law": "damping form",
             "stribeck": "friction", "bouc_wen": "hysteresis", "deadband": "play", "hardening": "stiffness",
             "fixture_mass": "inertia"}


#: the phrase of :func:`interpretation` that reads an effect of the hysteresis family as friction
READS_AS_FRICTION = {"hysteresis": "Dahl friction", "bouc_wen": "Jenkins friction"}


def mechanism(verdict: str, interpretation: str) -> str:
    """The verdict's physical families joined by ``+`` (Dahl hysteresis with x_h << A, and Bouc–Wen read as a
    rounded Jenkins slider, count as friction: :func:`interpretation`).

    ``none`` and ``unexplained`` map to themselves.
    """
    if verdict in ("none", "unexplained"):
        return verdict
    fams: list[str] = []
    for name in verdict.split("+"):
        fam = MECHANISM.get(name, name)
        if name in READS_AS_FRICTION and READS_AS_FRICTION[name] in interpretation:
            fam = "friction"
        if fam not in fams:
            fams.append(fam)
    return "+".join(fams)


#: what shows a richer effect's own shape against its simpler member (the final chain's split)
RICHER_SHAPE = {"stribeck": "tests that slide slowly (speeds near the Stribeck velocity v_s) show a static peak and a "
                            "direction asymmetry that Coulomb friction lacks",
                "bouc_wen": "small-amplitude tests (A near the yield travel x_y) show the Bouc–Wen loop's shape that "
                            "Dahl hysteresis lacks"}


def separating_test(a: str, b: str) -> str:
    """A test that would separate two near-tied explanations: two effects, or an effect and a pair (a richer
    effect against its simpler member plus a second cause, ``stribeck`` ~ ``friction+slack``; two chains that differ
    by one effect each, ``friction+slack`` ~ ``hysteresis+slack``, by what separates those two)."""
    if "+" in a or "+" in b:
        diff = set(a.split("+")) ^ set(b.split("+"))
        rich = next((n for n in sorted(diff) if n in RICHER_SHAPE), None)
        if rich is not None:
            rest = sorted(diff - {rich, SIMPLER[rich]})
            return RICHER_SHAPE[rich] + (f"; then {separating_test(rich, rest[0])} for {rest[0]}" if rest else "")
        one_each = all(len(set(c.split("+")) & diff) == 1 for c in (a, b))
        if len(diff) == 2 and one_each:  # two chains that differ by one effect each: what separates those two
            return separating_test(*sorted(diff))
    s = {a, b}
    if s == {"friction", "hysteresis"}:
        return ("a small-amplitude test (A comparable to the hysteresis travel x_h) separates sliding from smooth "
                "hysteresis")
    if "sensor_delay" in s:
        return "tests over a wider frequency range (a delay's phase grows with ω)"
    if "damping_law" in s or "friction" in s:
        return "tests over a wider amplitude range at fixed ω (Coulomb ∝ 1/A, viscous ∝ 1)"
    return "tests over a wider mean-load range x0 (stiffness-side effects scale differently with load)"


def _fmt(v: float | None, sd: float | None = None, ci: Any = None) -> str:
    """A value with its spread: the resampled 90 % interval ``ci`` [lo, hi] when given, else ± ``sd``; an ``sd`` of
    NaN is one the refits did not resolve (:func:`chainid.gap.core.candidate.jackknife_sd`) and says so."""
    if v is None:
        return "?"
    s = f"{v:.4g}"
    if ci is not None and len(ci) == 2 and all(math.isfinite(b) for b in ci):
        s += f" [{ci[0]:.4g}, {ci[1]:.4g}]"
    elif sd is not None and math.isfinite(sd) and sd > 0:
        s += f" ± {sd:.2g}"
    elif sd is not None and math.isnan(sd):
        s += " (sd not resolved)"
    return s


#: units of the parameters as the texts print them
_UNITS = {"F_c": "N", "mu": "", "x_s": "mm", "F_h": "N", "x_h": "mm", "b": "mm", "s": "mm", "c": "N·s/mm",
          "tau": "s", "eta": "", "F_f": "N", "F_y": "N", "x_y": "mm", "dF_s": "N", "dF": "N", "v_s": "mm/s",
          "k_d": "N/mm^p", "g": "mm", "x_c": "mm", "k3": "N/mm³", "k2": "N/mm²", "m_f": "kg", "k": "N/mm", "m": "kg"}


def step_text(step: dict[str, Any], kept: bool = False) -> str:
    """One link of the explanation chain, e.g. ``stiffness level −21 % (EA × 0.79 ± 0.01)``; ``kept``: the step is
    in the kept chain (:func:`chainid.gap.core.verdict.trusted_path`), so a rise of the held-out error it made alone
    is marked as recovered by the steps after it, not as over-fitting."""
    e = step["effect"]
    p, sd = step["params"], step.get("params_sd", {})
    tail = f" [held-out NRMSE {step['nrmse_holdout']:.3g}]" if step.get("nrmse_holdout") is not None else ""
    if step.get("rate_dependent"):
        tail += " [changes with the speed: rate-dependent, not kept]"
    elif step.get("rate_cut"):
        tail += " [after a rate-dependent step: not kept]"
    elif step.get("worsened_holdout"):
        tail += (" [raised the held-out error alone; kept: the step(s) after it take it lower]" if kept else
                 " [raised the held-out error: over-fitted, not in the verdict]")
    if e == "baseline":
        return f"baseline{tail}"
    head = e.split("@", 1)[0]  # an effect with its amplitudes following a covariate: the effect's parameters
    pre = head + "." if "." not in head else head
    mine = {k[len(pre):]: v for k, v in p.items() if k.startswith(pre)}
    msd = {k[len(pre):]: (math.nan if v is None else v) for k, v in sd.items() if k.startswith(pre)}
    mci = {k[len(pre):]: v for k, v in (step.get("params_ci90") or {}).items() if k.startswith(pre)}
    if e == "stiffness_level" and mine.get("scale") is not None:
        sc = mine["scale"]
        return f"stiffness level {100 * (sc - 1):+.0f} % (EA × {_fmt(sc, msd.get('scale'), mci.get('scale'))}){tail}"
    if e == "contact_law":
        return (f"contact law: Hertz compliance × {_fmt(mine.get('scale'), msd.get('scale'), mci.get('scale'))}, "
                f"exponent {_fmt(mine.get('beta'), msd.get('beta'), mci.get('beta'))} (Hertz 0.667){tail}")
    ps = ", ".join(f"{k} = {_fmt(v, msd.get(k), mci.get(k))}{(' ' + _UNITS.get(k, '')) if _UNITS.get(k) else ''}"
                   for k, v in mine.items())
    return f"{e} {ps}{tail}".rstrip()


def covariate_dependence(params: dict[str, float]) -> list[dict[str, Any]]:
    """Every parameter that follows an operating condition, in words: ``{"param", "covariate", "value_at_ref",
    "slope", "ref", "text"}`` with text like ``friction.F_c = 210 N + 1180 N per unit I_A · (I_A − 0.5)``."""
    out = []
    for k, slope in params.items():
        if "@" not in k:
            continue
        head, cov = k.split("@", 1)
        base = params.get(head)
        ref = params.get(f"covariate.{cov}.ref", 0.0)
        if base is None:
            continue
        unit = _UNITS.get(head.split(".", 1)[-1], "")
        u = f" {unit}" if unit else ""
        out.append({"param": head, "covariate": cov, "value_at_ref": base, "slope": slope, "ref": ref,
                    "text": f"{head} = {base:.4g}{u} {'+' if slope >= 0 else '−'} {abs(slope):.4g}{u} per unit "
                            f"{cov} · ({cov} − {ref:.4g})"})
    return out


#: Bouc–Wen unloads along its elastic line when |1 − 2r| is at most this (r = 1/2 exactly: unloading stiffness
#: within 20 % of the loading's elastic F_y/x_y)
ELASTIC_UNLOADING = 0.2
#: a Bouc–Wen knee this sharp or sharper (|z|^n: at z = 0.8 the slope has fallen by 41 %) reads as a slip corner
SHARP_KNEE = 4.0


def _jenkins_reading(p: dict[str, float], amin: float) -> list[str]:
    """A Bouc–Wen fit that unloads elastically, with a sharp knee and a yield travel well below the amplitudes, is an
    elastic–plastic (Jenkins) slider whose slip corner is rounded: Coulomb friction with elastic stick."""
    r, n = p.get("bouc_wen.r", float("nan")), p.get("bouc_wen.n", float("nan"))
    Fy, xy = p.get("bouc_wen.F_y", float("nan")), p.get("bouc_wen.x_y", float("nan"))
    if not (abs(1 - 2 * r) <= ELASTIC_UNLOADING and n >= SHARP_KNEE and xy < 0.5 * amin):
        return []
    return [f"Bouc–Wen with elastic unloading (r = {r:.2g}) and a sharp knee (n = {n:.2g}), yield travel "
            f"x_y = {xy:.3g} mm << A (>= {amin:.3g} mm): an elastic–plastic slider, Coulomb friction F_y = {Fy:.4g} N "
            f"with stick stiffness F_y/x_y = {Fy / xy:.4g} N/mm, its slip corner rounded (Jenkins friction)"]


def interpretation(path: Sequence[Any], prob: Any, verdict: str) -> str:
    """Readable meaning of the last step of ``path``, the kept chain (Dahl friction, stiffness level, equivalent
    series compliance)."""
    if len(path) < 2:
        return ""
    final = path[-1]
    out = []
    if "hysteresis" in final.names:
        xh = final.params.get("hysteresis.x_h", float("nan"))
        amin = min(d.A for d in prob.data)
        if xh < 0.5 * amin:
            out.append(f"Dahl-type hysteresis with transition travel x_h = {xh:.3g} mm << A (>= {amin:.3g} mm): "
                       "rate-independent frictional sliding with smooth pre-sliding (Dahl friction)")
    if "bouc_wen" in final.names:
        out += _jenkins_reading(final.params, min(d.A for d in prob.data))
    if "stiffness_level" in final.names and getattr(prob.model, "coefficients", None) is not None:
        sc = final.params.get("stiffness_level.scale", 1.0)
        c_lin = prob.model.coefficients[0]
        extra = c_lin * (1.0 / sc - 1.0)
        kind = "softer" if sc < 1 else "stiffer"
        out.append(f"the chain is {abs(100 * (sc - 1)):.0f} % {kind} in its linear (bar) term than the derivation; "
                   f"equivalently a series compliance of {extra:+.3g} mm/N (test machine, fixtures, a larger "
                   "contact flattening)")
    return "; ".join(out)


def step_dict(c: Any, i: int, prev: Any = None) -> dict[str, Any]:
    """One step of the explanation chain as the JSON contract writes it (step 0 is the baseline; ``prev`` the step
    before, for ``worsened_holdout``)."""
    f = lambda v: None if isinstance(v, float) and not math.isfinite(v) else v  # noqa: E731
    st = getattr(c, "step_test", {})
    fit = 100.0 * (1.0 - c.nrmse_holdout) if math.isfinite(c.nrmse_holdout) else float("nan")
    ratio = 10 ** (c.db_holdout / 20.0) if math.isfinite(c.db_holdout) else float("nan")
    return {
        "fit_holdout_pct": f(fit),
        "residual_over_noise": f(ratio),
        "worsened_holdout": bool(prev is not None and c.nrmse_holdout > prev.nrmse_holdout),
        "effect": "baseline" if i == 0 else c.names[-1],
        "effects": c.names,
        "params": {k: f(float(v)) for k, v in c.params.items() if not k.startswith("spring.")},
        "params_sd": {k: f(float(v)) for k, v in c.param_sd.items() if not k.startswith("spring.")},
        "damping_law": c.law,
        "c_e_tied_to_law": bool(getattr(c, "tied_law", "")),
        "nrmse_loto": f(c.nrmse_loto),
        "nrmse_holdout": f(c.nrmse_holdout),
        "shrinkage": f(c.shrinkage),
        "db_over_noise": f(c.db_holdout),
        "z_loto": f(float(st["z"])) if st else None,
        "relative_gain_loto": f(float(st["relative_gain"])) if st else None,
        "at_bound": list(c.at_bound),
    }
