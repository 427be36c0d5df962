"""What no library effect explains: a model-free learner on what the chosen chain leaves.

After the explanation chain, a gradient-boosted regression tree ensemble (scikit-learn's
``HistGradientBoostingRegressor``) learns the training residual from the *state* — the displacement x, the
velocity ẋ, the acceleration ẍ, the travel since the last reversal, the direction of motion, x a quarter band-edge
period earlier, the model force (the load), and the operating conditions — and predicts the held-out residual.
What it predicts there is structure in the state the library has no term for (an effect outside the library:
relaxation, an end stop of another shape, a friction law of another form); what it cannot predict is noise, or a
change in time no state variable carries (drift).

The learner's held-out gain is judged by the diagnosis' own step rule (:mod:`.selection`): per held-out unit (a
time block, a harmonic test) g = ½·ln(SSE_before/SSE_after); a missing effect is flagged when the mean g exceeds
``Z`` jack-knife standard errors and the pooled gain is at least ``MIN_GAIN`` — the same bar an effect must clear
to be named — and what is left is above its noise floor.  The learner is fitted once, with fixed hyper-parameters
stated here, never tuned to a data set.

Two changes no state variable carries are found by the diagnosis' own where-analysis and reported here too, so that
the check answers "is something outside the library?" whatever its kind:

* **a change in time** — the residual's trend over the cycles of each test or the blocks of each record
  (:mod:`.stationarity`: a drift, a relaxation, wear, warming);
* **stick-slip chatter** — ringing while the contact slides (:mod:`chainid.gap.timedomain.where`).

``missing_effect`` is then any of the three (``kinds``: ``state``, ``time``, ``chatter``): the learner's finding
above the noise floor only, the other two whatever the floor says (they carry their own tests, and a residual at
its floor per phase bin or per sample can still trend over the cycles).

Units: the residual in N; the features in mm, mm/s, mm/s², N and the covariates' units.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from chainid.gap.core.selection import MIN_GAIN, Z

__all__ = ["FEATURES", "open_world", "LEARNER"]

#: the state features every route provides (covariates are appended by name)
FEATURES = ("x", "xd", "xdd", "travel", "direction", "x_lag", "load")
#: the learner's fixed hyper-parameters
LEARNER = {"max_iter": 100, "learning_rate": 0.1, "max_leaf_nodes": 15, "min_samples_leaf": 40,
           "l2_regularization": 1.0, "early_stopping": True, "validation_fraction": 0.15, "n_iter_no_change": 10,
           "random_state": 0}
#: most training samples the learner sees (a regular sub-sample beyond)
MAX_TRAIN = 10000


def open_world(table: dict[str, Any], at_floor: bool, keep_model: bool = False, stat: dict[str, Any] | None = None,
               chatter: dict[str, Any] | None = None) -> dict[str, Any]:
    """Whether something outside the library is left: the learner on the state (its training rows of ``table``,
    scored on the held-out rows), a change in time (``stat``) and chatter (``chatter``).

    Parameters
    ----------
    table : dict
        ``X_train``, ``r_train``, ``X_hold``, ``r_hold`` (features and residuals [N]), ``unit_hold`` (the held-out
        unit of each held-out row), ``names`` (feature names), from the route's problem (``state_table``).
    at_floor : bool
        Whether what is left is at its noise floor (the diagnosis' own rule).
    keep_model : bool
        Keep the fitted learner under the private key ``_model`` (partial-dependence plots).
    stat : dict, optional
        The stationarity check of what is left (``stationary`` False: it changes in time; ``finding``).
    chatter : dict, optional
        The chatter finding of what is left (``frequency_Hz``, ``rms_N``), when there is one.

    Returns
    -------
    dict
        ``predictable_share`` (held-out: 1 − SSE_after/SSE_before), ``significant`` (the step rule's test),
        ``kinds`` (of ``state``, ``time``, ``chatter``: what was found), ``missing_effect`` (any; ``state`` above
        the floor),
        ``at_noise_floor``, ``z``, ``features``, ``message``.
    """
    out = _learner(table, at_floor, keep_model)
    kinds = (["state"] if out["significant"] else []) + (["time"] if stat and stat.get("stationary") is False
                                                          else []) + (["chatter"] if chatter else [])
    out["kinds"] = kinds
    # the learner's gain must clear the noise floor; a trend and chatter come with their own tests, and a phase bin
    # (a cycle average) or a per-sample floor does not carry a trend over the cycles
    out["missing_effect"] = bool(kinds) and not (at_floor and kinds == ["state"])
    if not kinds or kinds == ["state"]:
        return out
    parts = [out["message"]] if "state" in kinds and not at_floor else []
    if "time" in kinds:
        parts.append("what is left changes in time, which no state variable carries (a drift, a relaxation, wear): "
                     "an effect outside the library")
    if "chatter" in kinds:
        parts.append(f"stick-slip chatter while sliding ({chatter['frequency_Hz']:.3g} Hz, RMS {chatter['rms_N']:.3g}"
                     " N): an effect outside the library")
    out["message"] = "; ".join(parts)
    return out


def _learner(table: dict[str, Any], at_floor: bool, keep_model: bool) -> dict[str, Any]:
    """The learner's part of :func:`open_world` (its return keys but ``kinds``)."""
    from sklearn.ensemble import HistGradientBoostingRegressor

    Xt, rt = np.asarray(table["X_train"], float), np.asarray(table["r_train"], float)
    Xh, rh = np.asarray(table["X_hold"], float), np.asarray(table["r_hold"], float)
    units = np.asarray(table["unit_hold"])
    names = list(table["names"])
    out: dict[str, Any] = {"features": names, "at_noise_floor": bool(at_floor), "learner": "HistGradientBoostingRegressor"}
    if rt.size < 50 or rh.size < 10:
        return out | {"predictable_share": None, "significant": False, "missing_effect": False, "z": None,
                      "message": "too few samples for the model-free check"}
    if rt.size > MAX_TRAIN:
        step = int(math.ceil(rt.size / MAX_TRAIN))
        Xt, rt = Xt[::step], rt[::step]
    model = HistGradientBoostingRegressor(**LEARNER).fit(Xt, rt)
    pred = model.predict(Xh)
    before = float(np.sum(rh**2))
    after = float(np.sum((rh - pred) ** 2))
    share = 1.0 - after / before if before > 0 else 0.0
    g = []
    for u in np.unique(units):
        m = units == u
        b, a = float(np.sum(rh[m] ** 2)), float(np.sum((rh[m] - pred[m]) ** 2))
        g.append(0.5 * math.log(max(b, 1e-300) / max(a, 1e-300)))
    g = np.array(g)
    mean = float(g.mean())
    se = float(g.std(ddof=1) / math.sqrt(g.size)) if g.size >= 2 else float("inf")
    z = mean / se if se > 0 else (float("inf") if mean > 0 else 0.0)
    gain = 1.0 - math.sqrt(after / before) if before > 0 else 0.0  # the NRMSE's relative drop, as the step rule
    significant = bool(mean > Z * se and gain >= MIN_GAIN)
    missing = significant and not at_floor
    if missing:
        msg = (f"{100 * share:.0f} % of what is left (held-out) is predictable from the state: an effect outside the "
               "library")
    elif at_floor:
        msg = "what is left is at the noise floor: nothing more to explain"
    else:
        msg = (f"what is left is above the noise floor but not predictable from the state ({100 * share:.0f} % of it "
               f"on the held-out data, not significant): a change in time, or noise the floor underestimates")
    out |= {"predictable_share": share, "significant": significant, "missing_effect": bool(missing),
            "z": z if math.isfinite(z) else None, "relative_gain": gain, "message": msg}
    if keep_model:
        out["_model"] = model
        out["_X"] = Xt
    return out
