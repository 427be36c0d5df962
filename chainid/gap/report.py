"""Terminal summary and JSON contract of ``chainid diagnose``."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any


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
    from ..fileio import write_json as _write  # strict JSON, temp file + rename

    p = Path(path)
    _write(to_json(result), p, force=overwrite, what="--json")
    return p


def summary(result: dict[str, Any], n_rank: int = 6) -> str:
    """Readable terminal summary: where, which, how much."""
    b = result["baseline"]
    lines = [
        f"Baseline ({b['model']}, damping law: {b['damping_law']}): NRMSE train {b['nrmse_train']:.4g}, "
        f"held-out {b['nrmse_holdout']:.4g} ({b['db_over_noise']:.1f} dB over the noise floor; systematic "
        f"{b['excess_rms_N']:.4g} N vs noise σ {b['noise_sigma_N']:.4g} N)",
        "",
        "WHERE the model misses (largest first):",
    ]
    lines += [f"  - {f['finding']}" for f in result["where"][:8]]
    lines += ["", "WHICH effect (fitted on training tests; scored leave-one-test-out; held-out shown):"]
    lines.append(f"  {'effect':<30} {'LOTO':>8} {'held-out':>9} {'shrink':>7}  params")
    for c in result["ranking"][:n_rank]:
        ab = set(c.get("at_bound", []))
        ps = ", ".join(f"{k}={v:.4g}" + (" (at bound)" if k in ab else "") for k, v in c["params"].items()
                       if v is not None and not k.startswith("law."))
        lines.append(f"  {c['effect']:<30} {c['nrmse_loto']:>8.4g} {c['nrmse_holdout']:>9.4g} {100 * c['shrinkage']:>6.1f}%  {ps}")
    for cf in result.get("confounded", []):
        lines.append(f"  confounded: {cf['pair'][0]} ~ {cf['pair'][1]}; to separate them: {cf['separate_by']}")
    best = result.get("best")
    lines.append("")
    v = result["verdict"]
    if v == "none":
        lines.append("VERDICT: none — the baseline's held-out residual is consistent with the noise.")
    elif v == "unexplained":
        left = result.get("left_nrmse_holdout")
        lines.append(f"VERDICT: unexplained — no library effect shrinks the held-out gap by half "
                     f"(best {best['effect'] if best else '-'}: {100 * (best['shrinkage'] if best else 0):.0f} %; "
                     f"NRMSE left {left:.4g}).")
    else:
        sd = best.get("params_sd", {})
        ps = ", ".join(f"{k}={val:.4g}" + (f"±{sd[k]:.2g}" if k in sd and sd[k] is not None else "")
                       for k, val in best["params"].items() if not k.startswith("law."))
        lines.append(f"VERDICT: {v} ({ps}) — held-out NRMSE {b['nrmse_holdout']:.4g} → {best['nrmse_holdout']:.4g} "
                     f"(shrinkage {100 * best['shrinkage']:.0f} %)")
    if result.get("interpretation"):
        lines.append(f"  meaning: {result['interpretation']}")
    if result.get("mechanism") and result["mechanism"] not in ("none", "unexplained"):
        lines.append(f"  mechanism: {result['mechanism']}")
    for w in result.get("warnings", []):
        lines.append(f"WARNING: {w}")
    return "\n".join(lines)
