"""The gap report section with ``--data``: diagnosis of the user's records (last ~25 % of the tests held out),
with a check that the chain model describes them (else a linear spring is the baseline).

Units: x mm, F N, t s, ω rad/s.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from chainid.report.common import dump_json
from chainid.gap.core.summary import to_json
from chainid.report.diagnosis import MAX_COMBO, Progress, diagnosis_markdown, run_diagnosis, write_plots

#: Fraction of the user's tests held out with ``--data``.
DATA_HOLDOUT_FRACTION = 0.25
#: A chain model whose force at the records' median x is off by more than this factor is "not a chain".
CHAIN_FORCE_FACTOR = 3.0


# -- user's data -----------------------------------------------------------------

def choose_holdout(ids: Sequence[str], fraction: float = DATA_HOLDOUT_FRACTION, min_train: int = 6) -> list[str]:
    """The last ``fraction`` of the tests (at least 1, leaving at least ``min_train`` for training).

    Raises
    ------
    ValueError
        Fewer than ``min_train + 1`` tests.
    """
    n = len(ids)
    if n < min_train + 1:
        raise ValueError(f"{n} tests: the diagnosis needs at least {min_train + 1} ({min_train} training + 1 held out)")
    k = min(max(1, int(round(fraction * n))), n - min_train)
    return list(ids[-k:])


def chain_check(records: Sequence[Any], model: Any) -> dict[str, Any]:
    """Is the chain model plausible for these records?  Compares the median force with F_k at the median x.

    Returns
    -------
    dict
        ``median_x_mm``, ``median_F_N``, ``F_k_at_median_x_N``, ``ratio`` (F_k/F), ``is_chain``.
    """
    x = np.concatenate([np.asarray(r.x, float) for r in records])
    F = np.concatenate([np.asarray(r.F, float) for r in records])
    mx, mF = float(np.median(x)), float(np.median(F))
    try:
        Fk = float(np.asarray(model.force(np.array([mx])), dtype=float)[0])
    except (ValueError, TypeError):
        Fk = float("nan")
    ratio = Fk / mF if mF > 0 and math.isfinite(Fk) else float("nan")
    ok = math.isfinite(ratio) and 1.0 / CHAIN_FORCE_FACTOR <= ratio <= CHAIN_FORCE_FACTOR
    return {"median_x_mm": mx, "median_F_N": mF, "F_k_at_median_x_N": Fk, "ratio": ratio, "is_chain": ok,
            "min_F_N": float(F.min())}


def data_section(folder: Path, model: Any, data: Path, say: Progress, spec: Any = None) -> str:
    """Diagnosis of the user's records (``--data``, read with the reader ``spec``): last ~25 % of the tests held
    out."""
    from chainid.records.files import read_records

    head = f"## 4. Gap diagnosis of `{data.name}`\n"
    try:
        recs = read_records(data, allow_compression=True, spec=spec)
    except ValueError as exc:
        return head + f"\nThe records could not be read, no diagnosis: {exc}\n"
    ids = [r.test for r in recs]
    try:
        holdout = choose_holdout(ids)
    except ValueError as exc:
        dump_json(folder, "gap_data.json", {"skipped": str(exc), "tests": ids})
        return head + (f"\nSkipped: {exc}. Record more tests (different ω and A) to diagnose the gap; the per-test "
                       "identification is in step 3.\n")
    chk = chain_check(recs, model)
    use = model if chk["is_chain"] else None
    reason = ("the median measured force is ≤ 0 N, and a chain carries only tension" if chk["median_F_N"] <= 0
              else f"outside a factor {CHAIN_FORCE_FACTOR:g}")
    why = (f"the chain model ({getattr(model, 'name', 'model')}; F_k at the median x = {chk['median_x_mm']:.4g} mm is "
           f"{chk['F_k_at_median_x_N']:.4g} N against a median measured force of {chk['median_F_N']:.4g} N)"
           if use is not None else
           f"a linear spring fitted on the training tests — the chain model does not describe these records (F_k at the "
           f"median x = {chk['median_x_mm']:.4g} mm is {chk['F_k_at_median_x_N']:.4g} N against a median measured force "
           f"of {chk['median_F_N']:.4g} N: {reason})")
    say(f"gap: diagnosis of {len(ids)} tests from {data.name} (held out: {', '.join(holdout)})")
    try:
        res, secs = run_diagnosis(recs, holdout, use)
    except ValueError as exc:
        dump_json(folder, "gap_data.json", {"skipped": str(exc), "tests": ids, "holdout": holdout})
        return head + f"\nThe diagnosis could not run: {exc}\n"
    figs = write_plots(res, folder, "gap_data")
    doc = to_json(res)
    doc["data"] = {"file": str(data), "tests": ids, "holdout_rule": f"last {DATA_HOLDOUT_FRACTION:.0%} of the tests",
                   "chain_check": chk, "baseline_model": "chain" if use is not None else "linear",
                   "max_combo": MAX_COMBO, "diagnosis_seconds": secs}
    doc["figures"] = figs
    j = dump_json(folder, "gap_data.json", to_json(doc))
    intro = (f"\n{len(ids)} tests; the last {len(holdout)} ({', '.join(holdout)}) are held out whole, the other "
             f"{len(ids) - len(holdout)} train. Baseline stiffness: {why}. Diagnosis time {secs:.1f} s.\n")
    return head + intro + "\n" + diagnosis_markdown(res, "figures/gap_data", j)
