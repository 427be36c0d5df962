"""Scores of the ODE world (:mod:`chainid.gap.benchmark.odeworld`): verdict right per family, parameters against
the truth, rates per family, base, drive and excitation.

Right verdict per family:

* ``single`` and ``covariate`` — the truth's effect is named alone or first;
* ``pair`` — both effects are named (in any order, others may be named too);
* ``control`` — the verdict is ``none``;
* a truth with ``damping_law`` on a base that carries a dashpot law over the records' ω and A
  (:data:`BASE_LAWS_OVER_FEATURES`: the time route's law over record features, ``base_law == "feature"``, and the
  harmonic route's Eq. 21, ``"polynomial"``, chosen when the plan separates ω and A): the law is the base's, so
  ``damping_law`` alone is right as ``none`` and a pair by its other effect (on the harmonic route the effect
  ``damping_law`` means another law's form than Eq. 21's).  A world law of another form than the base's
  (``law_form = "table1"``, a power law in ω and A, which neither Eq. 21 nor the time route's linear law is)
  may leave a residual the base cannot fit: ``damping_law`` alone is then right as any verdict that names no
  other effect (``none``, ``unexplained``, ``damping_law``);
* ``outside`` — nothing is named with confidence: ``none`` or ``unexplained``, or a named effect whose held-out
  shrinkage is below :data:`OUTSIDE_SHRINK` (a weak verdict).

For every named effect of the truth, each of its parameters that the diagnosis estimates (``effect.param`` in the
last step's ``params``) is compared with the truth: the relative error |est − true|/|true|, and whether the
reported interval covers the truth — ``params_ci90`` [lo, hi] when given, else est ± 1.645·``params_sd`` (a 90 %
normal interval); no interval, no coverage.  A covariate's parameter is compared with its law at the mean operating
condition of the records.  Effects the verdict shares a physics with count by their canonical name
(:data:`chainid.gap.benchmark.paramscore.CANONICAL`).  Coverage is also pooled per effect (every parameter of that
effect), the calibration table of the resampled intervals (:mod:`chainid.gap.benchmark.paramscore`, shared with the
``sim`` generator).

The model-free check (``open_world``, :mod:`chainid.gap.core.openworld`) is scored apart: it should flag a missing
effect on ``outside`` cases and stay silent on controls and on cases whose verdict is right (the library explains
them): :func:`open_world_rates`.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from chainid.gap.benchmark.openworldscore import by_kind_text, flagged, flags_by_kind
from chainid.gap.benchmark.paramscore import (CANONICAL, Z90, coverage_by_effect, param_scores,  # noqa: F401  (API)
                                              param_table, pct, pool_scores, range_text)

__all__ = ["FAMILIES", "OUTSIDE_SHRINK", "SNR_MIN", "score_row", "verdict_names", "summarise", "format_table", "coverage_by_effect", "open_world_rates",
           "markdown_table"]

FAMILIES = ("control", "single", "pair", "outside", "covariate")
#: the baseline damping laws that follow a record's ω and A (the paper's c_e(ω, A) in the base): with one of these a
#: world's ``damping_law`` is the base's own (module docstring)
BASE_LAWS_OVER_FEATURES = ("feature", "polynomial")
#: a named effect with less held-out shrinkage than this is a weak verdict (right for an ``outside`` case)
OUTSIDE_SHRINK = 0.5
#: the "detectable" subset: the baseline's held-out residual is at least this many noise σ
SNR_MIN = 3.0


def verdict_names(verdict: str) -> list[str]:
    """The effects a verdict names, in its order, by canonical name (none, unexplained, an error: [])."""
    if verdict in ("none", "unexplained") or verdict.startswith("error"):
        return []
    return [CANONICAL.get(n, n) for n in verdict.split("+") if n]


def score_row(row: dict[str, Any]) -> dict[str, Any]:
    """Whether the verdict is right for the row's family, the names, and the parameter scores."""
    fam, verdict = row["family"], str(row["verdict"])
    named = verdict_names(verdict)
    truth = [CANONICAL.get(n, n) for n in row.get("effects", {})]
    error = verdict.startswith("error")
    named_rest = named
    if row.get("base_law") in BASE_LAWS_OVER_FEATURES and "damping_law" in truth:
        # the time route's base carries the dashpot's law over record features (the paper's c_e(ω, A) on any
        # excitation): that law is the base's, and what is left must be named (nothing, for damping_law alone)
        truth = [n for n in truth if n != "damping_law"]
        named_rest = [n for n in named if n != "damping_law"]
        named = ["damping_law"] + named_rest
        if not truth:
            fam = "control"
    curved_law = fam == "control" and row.get("law_form", "linear") != "linear"
    if curved_law:  # the world's law is not the base's form: what is left may show (module docstring)
        right = not error and not named_rest
    elif fam in ("single", "covariate"):
        right = bool(named_rest) and named_rest[0] == truth[0]
    elif fam == "pair":
        right = set(truth) <= set(named_rest)
    elif fam == "control":
        right = verdict == "none"
    elif fam == "outside":
        sh = row.get("shrinkage")
        right = not error and (not named or sh is None or sh < OUTSIDE_SHRINK)
    else:
        raise ValueError(f"family = {fam!r} is unknown; valid: {', '.join(FAMILIES)}")
    return {"right": bool(right), "named": named, "error": error, "params": param_scores(row, named)}


def _rate(rows: list[dict[str, Any]]) -> dict[str, Any]:
    n = len(rows)
    k = sum(r["score"]["right"] for r in rows)
    return {"n": n, "right": k, "rate": k / n if n else None}


def summarise(rows: list[dict[str, Any]]) -> dict[str, Any]:
    """Rates per family (all cases, and the cases with residual >= :data:`SNR_MIN` noise σ), per family × base,
    drive and excitation, the verdicts per family, the parameter errors and coverage, and the errors."""
    out: dict[str, Any] = {"n_cases": len(rows), "families": {}}
    for f in FAMILIES:
        rr = [r for r in rows if r["family"] == f]
        if not rr:
            continue
        strong = [r for r in rr if np.isfinite(r.get("snr", np.nan)) and r["snr"] >= SNR_MIN]
        verdicts: dict[str, int] = {}
        for r in rr:
            verdicts[r["verdict"] if not r["score"]["error"] else "error"] = verdicts.get(
                r["verdict"] if not r["score"]["error"] else "error", 0) + 1
        out["families"][f] = {
            **_rate(rr), "strong": _rate(strong),
            "by_base": {b: _rate([r for r in rr if r["base"] == b]) for b in sorted({r["base"] for r in rr})},
            "by_excitation": {e: _rate([r for r in rr if r["excitation"] == e])
                              for e in sorted({r["excitation"] for r in rr})},
            "verdicts": dict(sorted(verdicts.items(), key=lambda kv: -kv[1])),
        }
    ps = pool_scores(r["score"]["params"] for r in rows)
    out["params"] = param_table(ps)
    out["coverage_by_effect"] = coverage_by_effect(ps)
    out["open_world"] = open_world_rates(rows)
    out["errors"] = [{"label": r.get("label"), "error": r["verdict"]} for r in rows if r["score"]["error"]]
    out["misses"] = [{"label": r.get("label"), "family": r["family"], "verdict": r["verdict"],
                      "snr": r.get("snr"), "shrinkage": r.get("shrinkage")} for r in rows if not r["score"]["right"]]
    out["median_seconds"] = float(np.median([r["seconds"] for r in rows])) if rows else None
    out["median_sim_seconds"] = float(np.median([r["sim_seconds"] for r in rows])) if rows else None
    return out


def open_world_rates(rows: list[dict[str, Any]]) -> dict[str, Any]:
    """How often the model-free check flags a missing effect: on ``outside`` cases (it should, >= 90 %; also on
    those whose baseline residual is at least :data:`SNR_MIN` noise σ, where there is something to flag), on
    controls and on cases with a right verdict in the other families (it should not, >= 90 % silent)."""
    ok = [r for r in rows if not r["score"]["error"]]
    outside = [r for r in ok if r["family"] == "outside"]
    control = [r for r in ok if r["family"] == "control"]
    explained = [r for r in ok if r["family"] in ("single", "pair", "covariate") and r["score"]["right"]]
    rate = lambda rr, f: (sum(f(r) for r in rr) / len(rr)) if rr else None  # noqa: E731
    strong = [r for r in outside if np.isfinite(r.get("snr", np.nan)) and r["snr"] >= SNR_MIN]
    return {"outside_flagged": rate(outside, flagged), "outside_n": len(outside),
            "outside_flagged_strong": rate(strong, flagged), "outside_strong_n": len(strong),
            "outside_by_kind": flags_by_kind(outside),
            "control_silent": rate(control, lambda r: not flagged(r)), "control_n": len(control),
            "explained_silent": rate(explained, lambda r: not flagged(r)), "explained_n": len(explained)}


def _cases_text(v: dict[str, Any]) -> str:
    """``6 cases, 10-70 %``: an effect's cases and the 95 % range of its coverage over them (the range when known)."""
    return ", ".join(filter(None, (f"{v.get('n_cases', '?')} cases", range_text(v))))


def format_table(s: dict[str, Any]) -> str:
    """Terminal text: one line per family (all, strong), its breakdown by base and the parameter errors."""
    lines = [f"ODE world: {s['n_cases']} cases" + (f"; wall {s['wall_seconds']:.0f} s" if "wall_seconds" in s else ""),
             f"{'family':<11}{'right (all)':>16}{'right (snr>=3)':>18}   verdicts"]
    for f, r in s["families"].items():
        v = ", ".join(f"{k} {n}" for k, n in list(r["verdicts"].items())[:6])
        a = f"{pct(r['rate'])} ({r['right']}/{r['n']})"
        b = f"{pct(r['strong']['rate'])} ({r['strong']['right']}/{r['strong']['n']})"
        lines.append(f"{f:<11}{a:>16}{b:>18}   {v}")
    lines.append("by base (right/n): " + "; ".join(
        f"{f}: " + ", ".join(f"{b} {x['right']}/{x['n']}" for b, x in r["by_base"].items())
        for f, r in s["families"].items()))
    lines.append("by excitation (right/n): " + "; ".join(
        f"{f}: " + ", ".join(f"{e} {x['right']}/{x['n']}" for e, x in r["by_excitation"].items())
        for f, r in s["families"].items()))
    if s["params"]:
        lines.append("parameters of named true effects: " + "; ".join(
            f"{k} n={v['n']} median rel. error {pct(v['median_rel_error'], 1)}, 90 % interval covers "
            f"{pct(v['coverage'])} of {v['n_interval']}" for k, v in s["params"].items()))
    if s.get("coverage_by_effect"):
        lines.append("90 % intervals cover the truth, per effect: " + "; ".join(
            f"{k} {pct(v['coverage'])} of {v['n_interval']} ({_cases_text(v)})"
            for k, v in s["coverage_by_effect"].items()))
    ow = s.get("open_world")
    if ow:
        lines.append(f"model-free check: flags outside cases {pct(ow['outside_flagged'])} of {ow['outside_n']}"
                     f"{by_kind_text(ow.get('outside_by_kind'))} ({pct(ow.get('outside_flagged_strong'))} of "
                     f"{ow.get('outside_strong_n', 0)} with residual >= {SNR_MIN:g} σ); "
                     f"silent on controls {pct(ow['control_silent'])} of {ow['control_n']}, on right verdicts "
                     f"{pct(ow['explained_silent'])} of {ow['explained_n']}")
    if s["errors"]:
        lines.append(f"{len(s['errors'])} case(s) raised an error, e.g. {s['errors'][0]['error']}")
    lines.append(f"median diagnosis {s['median_seconds']:.1f} s, median simulation {s['median_sim_seconds']:.1f} s"
                 if s.get("median_seconds") is not None else "")
    return "\n".join(lines)


def markdown_table(s: dict[str, Any]) -> str:
    """Markdown tables (for ``benchmarks/RESULTS_ode.md``): the family rates, right/n per family × base, and the
    parameters of named true effects."""
    lines = ["| family | right (all) | right (residual >= 3 σ) | verdicts |", "|---|---|---|---|"]
    for f, r in s["families"].items():
        v = ", ".join(f"`{k}` {n}" for k, n in r["verdicts"].items())
        lines.append(f"| {f} | {pct(r['rate'])} ({r['right']}/{r['n']}) | {pct(r['strong']['rate'])} "
                     f"({r['strong']['right']}/{r['strong']['n']}) | {v} |")
    bases = sorted({b for r in s["families"].values() for b in r["by_base"]})
    lines += ["", "| family | " + " | ".join(bases) + " |", "|---|" + "---|" * len(bases)]
    for f, r in s["families"].items():
        cells = [f"{r['by_base'][b]['right']}/{r['by_base'][b]['n']}" if b in r["by_base"] else "–" for b in bases]
        lines.append(f"| {f} | " + " | ".join(cells) + " |")
    if s.get("params"):
        lines += ["", "| parameter | n | median relative error | 90 % interval covers the truth |", "|---|---|---|---|"]
        for k, v in s["params"].items():
            lines.append(f"| `{k}` | {v['n']} | {pct(v['median_rel_error'], 1)} | {pct(v['coverage'])} of "
                         f"{v['n_interval']} |")
    if s.get("coverage_by_effect"):
        lines += ["", "| effect | intervals | cases | 90 % interval covers the truth | its 95 % range over the cases |",
                  "|---|---|---|---|---|"]
        lines += [f"| `{k}` | {v['n_interval']} | {v.get('n_cases', '?')} | {pct(v['coverage'])} |"
                  f" {range_text(v) or 'n/a'} |" for k, v in s["coverage_by_effect"].items()]
    ow = s.get("open_world")
    if ow:
        lines += ["", "| model-free check | rate | cases |", "|---|---|---|",
                  f"| flags a missing effect on `outside` cases{by_kind_text(ow.get('outside_by_kind'))} | "
                  f"{pct(ow['outside_flagged'])} | {ow['outside_n']} |",
                  f"| ... where the baseline's residual is >= {SNR_MIN:g} σ | "
                  f"{pct(ow.get('outside_flagged_strong'))} | {ow.get('outside_strong_n', 0)} |",
                  f"| silent on controls | {pct(ow['control_silent'])} | {ow['control_n']} |",
                  f"| silent on right verdicts (single, pair, covariate) | {pct(ow['explained_silent'])} | "
                  f"{ow['explained_n']} |"]
    return "\n".join(lines)
