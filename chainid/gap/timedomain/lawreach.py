"""Whether a held-out gap is the base's damping law read beyond the training records.

The time route's base may carry the dashpot law c_r = c + b_w·(ω_r − w_ref) + b_A·(A_r − A_ref) (the paper's
c_e(ω, A), Eq. 21–28, over a record's band centre and amplitude: :meth:`.problem.TimeProblem.record_c`), fitted on
the training records.  A held-out record whose features lie outside the training records' range reads the law by
extrapolation; with few training records (three records fix the law's three coefficients exactly) the extrapolated
c can be far from the record's own while the law's form is right, and the baseline then leaves a held-out residual
that no effect of the library explains.

:func:`own_damping` refits one dashpot on each wholly held-out record that lies *beyond* the training range (one
linear parameter per such record, every other parameter of the fitted model kept); every other held-out sample (a
record inside the range, a held-out block of a training record) keeps the law's c.  :func:`law_extrapolation` reads
it: the gap is the law's extrapolation when (1) the base carries the law, (2) at least one wholly held-out record
lies beyond the training range in a feature the law follows, by more than ``MARGIN`` of the training span (nearer,
extrapolation and interpolation differ by less than the law's own form can), (3) every refitted dashpot is passive
(c ≥ 0), and (4) every held-out record, and all of them pooled, is then at its floor by the rule of
:func:`chainid.gap.core.steprule.at_noise_floor` — the force noise plus the kinematics' predicted errors through the
record's dashpot (:meth:`.problem.TimeProblem.kinematic_floor`), one degree of freedom less per refitted dashpot.
The route then reads the baseline as ``none`` with a warning naming the records, the law's c and their own: nothing
beyond the damping level of the records the law could not reach differs, and training records spanning the
held-out conditions would fix the law.  A record inside the range that the law misses is the law's form, and stops
the reading.

Units: ω rad/s, A mm, c N·s/mm, forces N.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from chainid.gap.core.steprule import at_noise_floor
from chainid.gap.timedomain.design import amplitude_names
from chainid.gap.timedomain.passivity import LAW_FEATURES, law_box
from chainid.gap.timedomain.problem import SIGMA2_REL_SD, TimeProblem

__all__ = ["MARGIN", "law_extrapolation", "own_damping", "train_range"]

#: a held-out record reads the law by extrapolation when a feature lies this fraction of the training span beyond it
MARGIN = 0.1


def train_range(prob: TimeProblem) -> dict[str, tuple[float, float]]:
    """The training records' range of each feature the law follows (:func:`.passivity.law_box` over them), by the
    record attribute (``omega_c`` [rad/s], ``A_c`` [mm])."""
    box = law_box(prob.train, prob.base.law_features, prob.base.refs)
    return {attr: (box[f"{k}_lo"], box[f"{k}_hi"]) for k, attr in LAW_FEATURES if k in prob.base.law_features}


def beyond(rng: dict[str, tuple[float, float]], d: Any) -> list[str]:
    """The features in ``rng`` (:func:`train_range`) in which record ``d`` lies beyond the range by more than
    ``MARGIN`` of its span."""
    out = []
    for attr, (lo, hi) in rng.items():
        v, pad = float(getattr(d, attr)), MARGIN * (hi - lo)
        if v < lo - pad or v > hi + pad:
            out.append(attr)
    return out


def own_damping(prob: TimeProblem, names: list[str], params: dict[str, float]) -> dict[str, Any]:
    """The held-out residual with each wholly held-out record beyond the training range on its own dashpot.

    Returns ``records`` (per record with held-out samples: ``test``, ``omega_c`` [rad/s], ``A_c`` [mm], ``outside``
    (the features beyond the range), ``refit`` (its own dashpot fitted), ``c_law`` and ``c_own`` [N·s/mm], ``r2``,
    ``f2_force``, ``f2_kin`` [N² per held-out sample], ``n_cells``, ``n_record`` (the record's samples)), the same
    four numbers pooled over every held-out sample, and the training ``range`` (:func:`train_range`); no records
    when the model has no dashpot column.
    """
    amps = amplitude_names(prob.base, names)
    rng = train_range(prob)
    out: dict[str, Any] = {"records": [], "r2": math.nan, "f2_force": math.nan, "f2_kin": math.nan, "n_cells": 0,
                           "range": rng}
    if "damping.c" not in amps:
        return out
    j = amps.index("damping.c")
    a = np.array([params[k] for k in amps])
    tot = np.zeros(3)
    n = 0
    for d, (f, Phi, y) in zip(prob.tdata, prob.columns(names, params)):
        hold = ~prob.train_mask(d.test)
        if not hold.any():
            continue
        r, v = (y - f - Phi @ a)[hold], Phi[hold, j]
        outside = beyond(rng, d) if hold.all() else []
        vv = float(v @ v)
        dc = float(r @ v) / vv if outside and vv > 0 else 0.0
        c_law = prob.record_c(d, params)
        own = params | {"damping.c": c_law + dc, "damping_law.b_w": 0.0, "damping_law.b_A": 0.0}
        row = np.array([np.sum((r - dc * v) ** 2), prob.noise_floor(d, params) * r.size,
                        prob.kinematic_floor(d, own) * r.size])
        tot += row
        n += r.size
        cells = int(d.rho * r.size) - (1 if outside else 0)
        out["records"].append({"test": d.test, "omega_c": float(d.omega_c), "A_c": float(d.A_c), "outside": outside,
                               "refit": bool(outside), "c_law": float(c_law), "c_own": float(c_law + dc),
                               "r2": row[0] / r.size, "f2_force": row[1] / r.size, "f2_kin": row[2] / r.size,
                               "n_cells": max(cells, 1), "n_record": int(d.t.size)})
        out["n_cells"] += cells
    if n:
        out |= {"r2": tot[0] / n, "f2_force": tot[1] / n, "f2_kin": tot[2] / n}
    return out


def _at_floor(r2: float, f2_kin: float, f2_force: float, n_cells: int, rel_sd: float) -> bool:
    """The step rule's floor test on a residual r2 against the kinematic floor f2_kin [N²]."""
    return at_noise_floor(r2, f2_kin, math.sqrt(f2_force), max(n_cells, 1), rel_sd)


def law_extrapolation(prob: TimeProblem, names: list[str], params: dict[str, float]) -> dict[str, Any] | None:
    """The finding that the held-out gap of the model ``names``/``params`` is its dashpot law extrapolated (see the
    module docstring), or None when any of the four conditions fails.

    The finding has the ``where`` keys (``finding``, ``kind`` = ``damping_extrapolation``, ``score``) plus
    ``records`` (the refitted ones), the training ``range`` and the pooled RMS left [N] and floor [N].
    """
    if not prob.base.law:
        return None
    own = own_damping(prob, names, params)
    recs = own["records"]
    refit = [r for r in recs if r["refit"]]
    if not refit or not all(r["c_own"] >= 0.0 for r in refit):  # (a NaN c fails >= as well)
        return None
    if not all(_at_floor(r["r2"], r["f2_kin"], r["f2_force"], r["n_cells"], SIGMA2_REL_SD / math.sqrt(r["n_record"]))
               for r in recs):
        return None
    if not _at_floor(own["r2"], own["f2_kin"], own["f2_force"], own["n_cells"], prob.floor_rel_sd("hold")):
        return None
    rng = own["range"]
    text = "; ".join(f"{r['test']} (ω_c {r['omega_c']:.3g} rad/s, A {r['A_c']:.3g} mm): the law's c "
                     f"{r['c_law']:.3g} N·s/mm, its own {r['c_own']:.3g}" for r in refit)
    span = ", ".join(f"{a} {lo:.3g}–{hi:.3g}" for a, (lo, hi) in rng.items())
    finding = (f"the held-out gap is the damping law extrapolated beyond the {len(prob.train)} training records "
               f"({span}): {text}; with their own dashpots every held-out record is at its noise floor")
    rms = math.sqrt(max(own["r2"], 0.0))
    return {"finding": finding, "kind": "damping_extrapolation", "score": rms, "records": refit, "range": rng,
            "rms_own_N": rms, "floor_N": math.sqrt(max(own["f2_kin"], 0.0))}
