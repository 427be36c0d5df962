"""Whether a held-out gap is the base's damping law read beyond the training records.

The time route's base may carry the dashpot law c_r = c + b_w·(ω_r − w_ref) + b_A·(A_r − A_ref) (the paper's
c_e(ω, A), Eq. 21–28, over a record's band centre and amplitude: :func:`chainid.model.timedamping.feature_c`), fitted
on the training records.  A held-out record whose features lie outside the training records' range reads the law by
extrapolation; with few training records (three records fix the law's three coefficients exactly) the extrapolated
c can be far from the record's own while the law's form is right, and the baseline then leaves a held-out residual
that no effect of the library explains.

:func:`own_damping` refits one dashpot per held-out record on that record alone (one linear parameter per record,
every other parameter of the fitted model kept) and returns what that leaves.  :func:`law_extrapolation` reads it:
the gap is the law's extrapolation when (1) the base carries the law and whole records are held out, (2) at least
one held-out record lies outside the training records' range in a feature the law follows, (3) every refitted
dashpot is passive (c ≥ 0), and (4) with their own dashpots the held-out records are at their floor by the rule of
:func:`chainid.gap.core.steprule.at_noise_floor` — the force noise plus the kinematics' predicted errors through the
record's own dashpot (:meth:`.problem.TimeProblem.kinematic_floor`), the degrees of freedom reduced by the refitted
dashpots.  The route then reads the baseline as ``none`` with a warning naming the records, the law's c and their
own: nothing beyond a damping level differs, and the law needs training records spanning the held-out conditions.

Units: ω rad/s, A mm, c N·s/mm, forces N.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from chainid.gap.core.steprule import at_noise_floor
from chainid.gap.timedomain.design import amplitude_names
from chainid.model.timedamping import feature_c

__all__ = ["law_extrapolation", "own_damping"]

#: the record features the base's dashpot law reads, by the law's feature key (:func:`.design.law_features`)
FEATURES = (("w", "omega_c"), ("A", "A_c"))


def _record_c(prob: Any, params: dict[str, float], d: Any) -> float:
    """The dashpot [N·s/mm] the fitted law gives record ``d``."""
    refs = prob.base.refs
    return feature_c(params.get("damping.c", 0.0), params.get("damping_law.b_w", 0.0),
                     params.get("damping_law.b_A", 0.0), d.omega_c, d.A_c, refs["w_ref"], refs["A_ref"])


def own_damping(prob: Any, names: list[str], params: dict[str, float]) -> dict[str, Any]:
    """Each wholly held-out record's own dashpot and the held-out residual it leaves.

    Returns ``records`` (per record: ``test``, ``omega_c`` [rad/s], ``A_c`` [mm], ``c_law`` and ``c_own``
    [N·s/mm]), ``r2`` (mean squared residual per held-out sample [N²]), ``f2_force`` (the force-noise floor [N²])
    and ``f2_kin`` (the floor with the kinematics' errors through each record's own dashpot [N²]); ``records``
    empty when no record is held out whole or the model has no dashpot column.
    """
    amps = amplitude_names(prob.base, names)
    out: dict[str, Any] = {"records": [], "r2": math.nan, "f2_force": math.nan, "f2_kin": math.nan}
    if "damping.c" not in amps:
        return out
    j = amps.index("damping.c")
    a = np.array([params[k] for k in amps])
    r2 = f2 = fk = 0.0
    n = 0
    for d, (f, Phi, y) in zip(prob.tdata, prob.columns(names, params)):
        if prob.train_mask(d.test).any():
            continue
        r, v = y - f - Phi @ a, Phi[:, j]
        vv = float(v @ v)
        dc = float(r @ v) / vv if vv > 0 else 0.0
        c_law = _record_c(prob, params, d)
        own = params | {"damping.c": c_law + dc, "damping_law.b_w": 0.0, "damping_law.b_A": 0.0}
        r2 += float(np.sum((r - dc * v) ** 2))
        f2 += prob.noise_floor(d, params) * r.size
        fk += prob.kinematic_floor(d, own) * r.size
        n += r.size
        out["records"].append({"test": d.test, "omega_c": float(d.omega_c), "A_c": float(d.A_c),
                               "c_law": float(c_law), "c_own": float(c_law + dc)})
    if n:
        out |= {"r2": r2 / n, "f2_force": f2 / n, "f2_kin": fk / n}
    return out


def _outside(prob: Any, rec: dict[str, Any]) -> list[str]:
    """The law's features in which held-out record ``rec`` lies outside the training records' range."""
    out = []
    for key, attr in FEATURES:
        if key not in prob.base.law_features:
            continue
        vals = [float(getattr(d, attr)) for d in prob.tdata if prob.train_mask(d.test).any()]
        if not min(vals) <= rec[attr] <= max(vals):
            out.append(attr)
    return out


def law_extrapolation(prob: Any, names: list[str], params: dict[str, float]) -> dict[str, Any] | None:
    """The finding that the held-out gap of the model ``names``/``params`` is its dashpot law extrapolated (see the
    module docstring), or None when any of the four conditions fails.

    The finding has the ``where`` keys (``finding``, ``kind`` = ``damping_extrapolation``, ``score``) plus
    ``records`` (those outside the training range, with ``outside``: the features) and the training ``range``.
    """
    if not prob.base.law:
        return None
    own = own_damping(prob, names, params)
    recs = own["records"]
    beyond = [r | {"outside": _outside(prob, r)} for r in recs]
    beyond = [r for r in beyond if r["outside"]]
    if not beyond or any(r["c_own"] < 0.0 for r in recs):
        return None
    n_cells = max(prob.n_cells("hold") - len(recs), 1)
    if not at_noise_floor(own["r2"], own["f2_kin"], math.sqrt(own["f2_force"]), n_cells, prob.floor_rel_sd("hold")):
        return None
    train = [d for d in prob.tdata if prob.train_mask(d.test).any()]
    rng = {attr: [min(float(getattr(d, attr)) for d in train), max(float(getattr(d, attr)) for d in train)]
           for key, attr in FEATURES if key in prob.base.law_features}
    text = "; ".join(f"{r['test']} (ω_c {r['omega_c']:.3g} rad/s, A {r['A_c']:.3g} mm): the law's c "
                     f"{r['c_law']:.3g} N·s/mm, its own {r['c_own']:.3g}" for r in beyond)
    span = ", ".join(f"{a} {lo:.3g}–{hi:.3g}" for a, (lo, hi) in rng.items())
    finding = (f"the held-out gap is the damping law extrapolated beyond the {len(train)} training records ({span}): "
               f"{text}; with its own dashpot every held-out record is at its noise floor")
    return {"finding": finding, "kind": "damping_extrapolation", "score": math.sqrt(max(own["r2"], 0.0)),
            "records": beyond, "range": rng, "rms_own_N": math.sqrt(max(own["r2"], 0.0)),
            "floor_N": math.sqrt(max(own["f2_kin"], 0.0))}
