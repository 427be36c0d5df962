"""Scores of ``chainid benchmark-gap``: per case family, in the issue's terms, and the confusion matrix."""

from __future__ import annotations

from typing import Any

import numpy as np


#: a case counts for the right-verdict rates when the baseline's residual is at least this many noise σ
SNR_MIN = 3.0


#: effects that are the same physics for the diagnosis (the canonical name is what a right verdict says)
CANONICAL = {"machine_compliance": "stiffness_level"}


def canon(names: Any) -> set[str]:
    """Canonical effect names of a verdict string or list."""
    if isinstance(names, str):
        names = [] if names in ("none", "unexplained") else names.split("+")
    return {CANONICAL.get(n, n) for n in names}


def _rate(rows: list[dict[str, Any]], ok: Any) -> float | None:
    return sum(bool(ok(r)) for r in rows) / len(rows) if rows else None


def summarise(rows: list[dict[str, Any]]) -> dict[str, Any]:
    """Rates per family: single right, compound both named (and exactly), control none, outside not named."""
    fam = {f: [r for r in rows if r["family"] == f] for f in ("single", "mismatch", "mismatch+", "pair",
                                                                 "control", "outside")}
    strong = {f: [r for r in v if r["snr"] >= SNR_MIN] for f, v in fam.items()}
    right = lambda r: canon(r["verdict"]) == canon(r["truth"])  # noqa: E731
    both = lambda r: canon(r["truth"]) <= canon(r["verdict"])  # noqa: E731
    shr = [r["shrinkage"] for r in rows if r["family"] in ("single", "mismatch", "mismatch+", "pair")
           and right(r) and r["shrinkage"] is not None]
    compound = strong["mismatch+"] + strong["pair"]

    def both_or_confound(r: dict[str, Any]) -> bool:
        """Both causes named, or the verdict's effect reported as confounded with exactly the true set."""
        if both(r):
            return True
        for a, b in r.get("confounded", []):
            alt = (canon(r["verdict"]) - {a}) | canon(b.split("+"))
            if a in canon(r["verdict"]) and alt == canon(r["truth"]):
                return True
        return False
    labels = sorted({v for r in rows for v in ([r["verdict"]] if "+" not in r["verdict"] else ["(combination)"])})
    truths = sorted({"+".join(r["truth"]) or "none" for r in fam["single"] + fam["control"] + fam["mismatch"]})
    conf = {t: {v: 0 for v in labels} for t in truths}
    for r in fam["single"] + fam["control"] + fam["mismatch"]:
        v = r["verdict"] if "+" not in r["verdict"] else "(combination)"
        conf["+".join(r["truth"]) or "none"][v] += 1
    return {
        "n_cases": len(rows),
        "single_right_rate": _rate(strong["single"], right),
        "single_n": len(strong["single"]),
        "mismatch_right_rate": _rate(strong["mismatch"], right),
        "mismatch_n": len(strong["mismatch"]),
        "compound_both_named_rate": _rate(compound, both),
        "compound_exact_rate": _rate(compound, right),
        "compound_named_or_confounded_rate": _rate(compound, both_or_confound),
        "compound_n": len(compound),
        "mismatch_plus_both_named_rate": _rate(strong["mismatch+"], both),
        "pair_both_named_rate": _rate(strong["pair"], both),
        "control_none_rate": _rate(fam["control"], lambda r: r["verdict"] == "none"),
        "control_n": len(fam["control"]),
        "outside_not_named_rate": _rate(fam["outside"], lambda r: r["verdict"] in ("none", "unexplained")),
        "outside_n": len(fam["outside"]),
        "outside_verdicts": {v: sum(r["verdict"] == v for r in fam["outside"])
                             for v in sorted({r["verdict"] for r in fam["outside"]})},
        "errors": [{"case": {k: r[k] for k in ("family", "truth", "chain", "plan", "noise", "seed")},
                    "error": r["verdict"]} for r in rows if r["verdict"].startswith("error:")],
        "median_shrinkage_when_right": float(np.median(shr)) if shr else None,
        "median_seconds": float(np.median([r["seconds"] for r in rows])) if rows else None,
        "confusion": conf,
        "misses": [{k: r[k] for k in ("family", "truth", "verdict", "snr", "chain", "plan", "noise", "levels")}
                   for r in rows if r["family"] != "outside" and r["snr"] >= SNR_MIN and not right(r)
                   or r["family"] == "control" and r["verdict"] != "none"],
        "rows": rows,
    }


TARGETS = {"single_right_rate": 0.92, "compound_both_named_rate": 0.85, "control_none_rate": 0.95}


def format_summary(s: dict[str, Any]) -> str:
    """Terminal text: the rates with their targets, then the confusion matrix of single effects."""
    f = lambda v: "n/a" if v is None else f"{100 * v:.1f} %"  # noqa: E731
    lines = [
        f"single effects, right verdict (residual >= {SNR_MIN:g}x noise): {f(s['single_right_rate'])} of "
        f"{s['single_n']} (target >= 92 %)",
        f"base-model mismatch alone, right: {f(s['mismatch_right_rate'])} of {s['mismatch_n']}",
        f"compound cases, both causes named: {f(s['compound_both_named_rate'])} of {s['compound_n']} "
        f"(target >= 85 %; mismatch+effect {f(s['mismatch_plus_both_named_rate'])}, two effects "
        f"{f(s['pair_both_named_rate'])}; exactly the two: {f(s['compound_exact_rate'])}; named or reported as "
        f"a confound of the verdict: {f(s['compound_named_or_confounded_rate'])})",
        f"control gives none: {f(s['control_none_rate'])} of {s['control_n']} (target >= 95 %)",
        f"outside the library not named: {f(s['outside_not_named_rate'])} of {s['outside_n']} "
        f"{s['outside_verdicts']}",
        f"median held-out shrinkage when right: {f(s['median_shrinkage_when_right'])}",
        f"median diagnosis time {s['median_seconds']:.2f} s over {s['n_cases']} cases"
        + (f"; wall {s['wall_seconds']:.0f} s" if "wall_seconds" in s else ""),
    ]
    for k, t in TARGETS.items():
        v = s.get(k)
        lines.append(f"  {'PASS' if v is not None and v >= t else 'MISS'}: {k} = {f(v)} (target >= {100 * t:.0f} %)")
    conf = s["confusion"]
    if conf:
        cols = sorted({c for row in conf.values() for c, n in row.items() if n})
        w = max(8, max(len(c) for c in cols) + 1)
        lines += ["", "confusion (rows: truth of single / mismatch / control cases; columns: verdict)",
                  " " * 22 + "".join(f"{c[:w - 1]:>{w}}" for c in cols)]
        for t, row in conf.items():
            lines.append(f"{t[:21]:<22}" + "".join(f"{row.get(c, 0):>{w}}" for c in cols))
    if s.get("errors"):
        lines.append(f"\n{len(s['errors'])} case(s) raised an error (counted as misses), e.g. {s['errors'][0]['error']}")
    if s.get("misses"):
        lines.append(f"\n{len(s['misses'])} miss(es), e.g.:")
        for m in s["misses"][:10]:
            lines.append(f"  {m['family']}: truth {'+'.join(m['truth']) or 'none'} -> {m['verdict']} "
                         f"(snr {m['snr']:.1f}, {m['chain']}, {m['plan']}, noise {m['noise']})")
    return "\n".join(lines)
