"""The model-free check of a diagnosis (:mod:`chainid.gap.core.openworld`) as the benchmarks read it: a row's
fields, and which of its findings flagged the out-of-library cases.  Shared by both simulated worlds (the
project's grid, :mod:`chainid.gap.benchmark.report`, and the ODE world, :mod:`chainid.gap.benchmark.odescore`),
and independent of either's simulator.
"""

from __future__ import annotations

from typing import Any

__all__ = ["open_world_row", "flagged", "flags_by_kind", "by_kind_text"]

#: the findings of the model-free check: the learner's structure in the state, a trend in time, chatter
KINDS = ("state", "time", "chatter")


def open_world_row(res: dict[str, Any]) -> dict[str, Any]:
    """The model-free check of a diagnosis (``res["open_world"]``) as a benchmark row's fields: whether it flags a
    missing effect, which findings flag it (``kinds``: ``state`` — the learner, which does not count when what is
    left is at the noise floor —, ``time``, ``chatter``), and the held-out share of the residual the learner
    predicts."""
    ow = res.get("open_world") or {}
    kinds = [k for k in (ow.get("kinds") or []) if not (k == "state" and ow.get("at_noise_floor"))]
    return {"missing_effect": bool(ow.get("missing_effect")), "kinds": kinds,
            "predictable_share": ow.get("predictable_share")}


def flagged(row: dict[str, Any]) -> bool:
    """Whether the model-free check flagged a benchmark row's case as missing an effect."""
    return bool((row.get("open_world") or {}).get("missing_effect"))


def flags_by_kind(rows: list[dict[str, Any]]) -> dict[str, int] | None:
    """How many of the flagged ``rows`` each finding of the model-free check flagged (a row may count under more
    than one); None when a flagged row does not record its findings (a row written before they were)."""
    rows = [r for r in rows if flagged(r)]
    if any("kinds" not in (r.get("open_world") or {}) for r in rows):
        return None
    out = {k: 0 for k in KINDS}
    for r in rows:
        for k in r["open_world"]["kinds"]:
            out[k] = out.get(k, 0) + 1
    return out


def by_kind_text(counts: dict[str, int] | None) -> str:
    """" (by finding: state 3, time 5, chatter 1)" for :func:`flags_by_kind`, "" when unknown."""
    return "" if counts is None else " (by finding: " + ", ".join(f"{k} {n}" for k, n in counts.items()) + ")"
