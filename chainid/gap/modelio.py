"""The diagnosis as a runnable model: build the augmented model of each step, and predict records with one.

* :func:`model_of_step` — the :class:`chainid.augmented.AugmentedModel` of a fitted step (its effects and
  parameters, the re-fitted linear spring of a ``--model linear`` baseline, the damping law re-identified at
  that step with its coefficients and per-test c_e, the delay, the mass).
* :func:`predict` — ``chainid predict``: per-test and pooled NRMSE of a model file's baseline and model.
* :func:`negative_damping` — the diagnosis' warning where the damping resolves to a negative dashpot (a run of
  such a model is refused: :mod:`chainid.model.passivity`).

**Which damping ``predict`` uses.**  For a steady harmonic test (one :func:`chainid.gap.prepare.prepare_test`
accepts) the model is evaluated exactly as the diagnosis evaluates a held-out test: on the test's phase
grid, memory operators in their periodic steady state, c_e from the *law* at the test's ω, A and x0 — a
prediction, never a refit, and the same number the diagnosis reports (to round-off).  The per-test c_e the
law was fitted on are in the file but used only with ``fitted=True`` (``--fitted-damping``): test ids of
a new file need not be the same tests.  A record that is not a steady harmonic test is predicted in the
time domain as the diagnosis' time route evaluates it (:meth:`AugmentedModel.force` on the smooth
kinematics of :func:`chainid.gap.noise.kinematics` — a zero-phase low-pass above the record's excitation
band, so the noise of x is not differentiated into a friction sign or the dashpot; operators from their initial
state, the law resolved at the record's dominant ω and A by the rule of :mod:`chainid.timedamping`), NRMSE
over its samples: the held-out number the diagnosis reports.

Units: mm, N, s; NRMSE = RMS(residual)/RMS(F − mean F).
"""

from __future__ import annotations

import datetime as _dt
import hashlib
import math
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from chainid.model.augmented import NOT_FORCE, AugmentedModel
from chainid.model.modelfile import model_to_dict
from chainid.model.passivity import OperatingPoint, check_passive, describe, negative_dashpots
from chainid.model.timedamping import Damping, dominant
from chainid.gap import noise as nz
from chainid.gap.prepare import Unusable, prepare_test


def model_of_step(prob: Any, cand: Any, info: dict[str, Any] | None = None) -> AugmentedModel:
    """The augmented model of a scored candidate (a diagnosis step) on problem ``prob``."""
    p = cand.params
    names = cand.names
    effects = [(n, {k.split(".", 1)[1]: float(v) for k, v in p.items() if k.startswith(n + ".")})
               for n in names if n not in NOT_FORCE]
    delay = float(p.get("sensor_delay.tau", 0.0)) if "sensor_delay" in names else 0.0
    ev = getattr(cand, "_ev", {})
    train = {d.test for d in prob.train}
    per_test = {t: float(c) for t, c in ev.get("c_e", {}).items() if t in train}
    k_e = None if prob.is_chain else float(prob.model.k)  # the law's k_e is the diagnosis baseline's
    if getattr(prob, "hprob", True) is None:  # time domain only: one viscous c for the set, no c_e(ω, A) law
        damping = Damping("viscous", {"c": float(cand.law_params[0])})
    else:
        damping = Damping("law", law=cand.law, coefficients=[float(v) for v in cand.law_params], k_e=k_e,
                          per_test=per_test)
    return AugmentedModel(prob.model_for(p), effects, damping, delay, info=dict(info or {}))


def step_models(result: dict[str, Any], info: dict[str, Any] | None = None) -> list[AugmentedModel]:
    """One model per step of a diagnosis result (its ``_problem``/``_path``), each with step 0 as baseline."""
    prob, path = result["_problem"], result["_path"]
    models = [model_of_step(prob, c, info) for c in path]
    for m in models[1:]:
        m.baseline = models[0]
    models[0].baseline = models[0].__class__(models[0].base, [], models[0].damping, 0.0)
    return models


def step_fields(prob: Any, cand: Any, model: AugmentedModel | None = None) -> dict[str, Any]:
    """Fitted parameters of a step that the step's dict does not carry: base, law coefficients, mass, delay
    (``model``: the step's model when already built, :func:`model_of_step`)."""
    d = model_to_dict(model if model is not None else model_of_step(prob, cand))
    return {"law_params": [float(v) for v in cand.law_params], "base": d["base"], "mass_kg": d["mass_kg"],
            "delay_s": d["delay_s"]}


def attach_models(summary: dict[str, Any], evaluation: dict[str, Any]) -> list[str]:
    """Make a diagnosis result runnable, on either route: every step gets its fitted parameters
    (:func:`step_fields`), ``summary["model"]`` the last step's model in the model file's keys and
    ``summary["_models"]`` the model of every step (what ``--save-model`` / ``--save-steps`` write).

    Parameters
    ----------
    summary : the result of :func:`chainid.gap.diagnose` (its ``_problem`` and ``_path``)
    evaluation : how ``predict`` evaluates a steady harmonic test (``n_bins``, ``steady_tol``,
        ``allow_compression``), stored in the model file

    Returns
    -------
    list of str
        Warnings (appended to ``summary["warnings"]`` too): the tests at which the model's damping is a
        negative dashpot (:func:`negative_damping`).
    """
    prob = summary["_problem"]
    models = step_models(summary, {"evaluation": evaluation})
    for st, cand, m in zip(summary["steps"], summary["_path"], models):
        st.update(step_fields(prob, cand, m))  # every fitted parameter: base, law coefficients, mass, delay
    summary["model"] = model_to_dict(models[-1])  # the last step's model, in the model file's keys
    summary["_models"] = models
    if hasattr(prob, "tdata"):  # a time-domain problem: its records and its harmonic part's tests
        data = list(prob.tdata) + (list(prob.hprob.data) if prob.hprob is not None else [])
    else:
        data = list(prob.data)
    msgs = negative_damping(models[-1], data)
    summary["warnings"].extend(msgs)
    return msgs


def provenance(data_file: str | Path | None, command: str) -> dict[str, Any]:
    """Data file SHA-256, the command, chainid's version and the UTC date of a model file."""
    from chainid import __version__

    sha = None
    if data_file is not None and Path(data_file).is_file():
        h = hashlib.sha256()
        with open(data_file, "rb") as fh:
            for chunk in iter(lambda: fh.read(1 << 20), b""):
                h.update(chunk)
        sha = h.hexdigest()
    return {"data_file": None if data_file is None else str(data_file), "data_sha256": sha, "command": command,
            "chainid_version": __version__, "date": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds")}


def _sse_var(F: np.ndarray, Fm: np.ndarray, w: np.ndarray) -> tuple[float, float]:
    mean = float(np.sum(w * F) / np.sum(w))
    return float(np.sum(w * (F - Fm) ** 2)), float(np.sum(w * (F - mean) ** 2))


def negative_damping(model: AugmentedModel, data: Sequence[Any], fitted: bool = False) -> list[str]:
    """Warnings for the prepared harmonic tests ``data`` (TestData) at which the model's damping resolves to a
    viscous c < 0 [N·s/mm]: a negative dashpot feeds energy in, which no passive device does — the named effects
    over-explain the dissipation there, or the law is extrapolated (Eq. 21 is a fitted surface).  One message
    naming the tests, the most negative c and its ω [rad/s], A [mm]; empty when none (the test of
    :func:`chainid.model.passivity.negative_dashpots`; a run of such a model is refused by
    :func:`chainid.model.passivity.check_passive`)."""
    bad = negative_dashpots(model, [OperatingPoint(d.test, d.omega, d.A, d.x0, d.test) for d in data], fitted)
    return [describe(bad)] if bad else []


def predict(model: AugmentedModel, records: Sequence[Any], tests: Sequence[str] | None = None,
            fitted: bool = False, keep: bool = False) -> dict[str, Any]:
    """Per-test and pooled NRMSE of the model file's baseline and of the model on ``records``.

    Parameters
    ----------
    model : AugmentedModel
        With ``baseline`` (else the model is its own baseline) and ``info["evaluation"]`` (n_bins,
        steady_tol, allow_compression of the diagnosis; defaults 64, adaptive, True).
    records : sequence of Record
    tests : sequence of str, optional
        Only these test ids (each must be in the records).
    fitted : bool
        Use the per-test c_e stored for tests the law was fitted on (see the module docstring).
    keep : bool
        Also return per-test series for plots under the private key ``_series``.

    Returns
    -------
    dict
        ``{"tests": [{"test", "nrmse_baseline", "nrmse_model", "shrinkage", "mode"}], "pooled": {...},
        "model": {...}, "warnings": [...]}`` (the list stays in the contract; the run's warnings are added to it).

    Raises
    ------
    ValueError
        A test id not in the records, no records, or a damping (of the model or its baseline) that is a
        negative dashpot at a record's operating point (:func:`chainid.model.passivity.check_passive`).
    """
    ids = [r.test for r in records]
    if tests:
        bad = [t for t in tests if t not in ids]
        if bad:
            raise ValueError(f"--tests: test id(s) {bad} not in the data; valid ids: {', '.join(ids)}")
        records = [r for r in records if r.test in set(tests)]
    if not records:
        raise ValueError("no records to predict")
    ev = dict(model.info.get("evaluation", {}))
    base = model.baseline or model
    rows, series = [], {}
    tot = {"b": 0.0, "m": 0.0, "v": 0.0}
    prepared = {r.test: _prepared(r, ev) for r in records}
    kin = {r.test: nz.record_kinematics(r.t, r.x) for r in records if prepared[r.test] is None}
    points = [OperatingPoint(d.test, d.omega, d.A, d.x0, d.test) for d in prepared.values() if d is not None]
    for test, (_, xs, _, _) in kin.items():  # a transient: its dominant ω and A, as AugmentedModel.force resolves
        r = next(r for r in records if r.test == test)
        w, A, x0 = dominant(r.t, xs)
        points.append(OperatingPoint(test, w, max(A, 1e-12), x0, test))
    everywhere = len(negative_dashpots(model, points, fitted)) == len(points)
    check_passive(model, points, fitted=fitted, what="the model", with_baseline=True,
                  hint="a run with a negative dashpot is refused; " + (
                      "diagnose again with another --damping-law or fewer effects" if everywhere
                      else "--tests predicts the other tests"))
    for r in records:
        d = prepared[r.test]
        if d is not None:
            Fm, Fb = model.cycle_force(d, fitted), base.cycle_force(d, fitted)
            (sm, var), (sb, _) = _sse_var(d.Fbar, Fm, d.counts), _sse_var(d.Fbar, Fb, d.counts)
            mode = "steady-cycle"
            if keep:
                series[r.test] = (d.t + d.t_origin, d.x_meas, d.F, Fm[d.bins], Fb[d.bins])
        else:  # on the diagnosis' smooth kinematics (zero-phase low-pass above the excitation band)
            _, xs, xd, xdd = kin[r.test]
            Fm, Fb = model.force(r.t, xs, xd=xd, xdd=xdd), base.force(r.t, xs, xd=xd, xdd=xdd)
            w = np.ones_like(r.F)
            (sm, var), (sb, _) = _sse_var(r.F, Fm, w), _sse_var(r.F, Fb, w)
            mode = "time-domain"
            if keep:
                series[r.test] = (r.t, r.x, r.F, Fm, Fb)
        nb, nm = _nrmse(sb, var), _nrmse(sm, var)
        rows.append({"test": r.test, "nrmse_baseline": nb, "nrmse_model": nm, "shrinkage": _shrink(nm, nb),
                     "mode": mode})
        tot["b"] += sb
        tot["m"] += sm
        tot["v"] += var
    pb, pm = _nrmse(tot["b"], tot["v"]), _nrmse(tot["m"], tot["v"])
    used = model.damping.form  # a law: the law, or the per-test c_e it was fitted on
    if used == "law":
        used = "per-test fitted c_e" if fitted else "law"
    out = {"tests": rows, "pooled": {"nrmse_baseline": pb, "nrmse_model": pm, "shrinkage": _shrink(pm, pb)},
           "model": model_to_dict(model), "damping_used": used, "warnings": []}
    if keep:
        out["_series"] = series
    return out


def _prepared(r: Any, ev: dict[str, Any]) -> Any:
    """The prepared steady harmonic test of a record (as the diagnosis prepares it), or None (a transient)."""
    try:
        return prepare_test(r, n_bins=int(ev.get("n_bins", 64)), allow_compression=bool(ev.get("allow_compression", True)),
                            steady_tol=ev.get("steady_tol"))
    except Unusable:
        return None


def _nrmse(sse: float, var: float) -> float | None:
    return math.sqrt(sse / var) if var > 0 else None


def _shrink(nm: float | None, nb: float | None) -> float | None:
    return 1.0 - nm / nb if nm is not None and nb else None
