"""The diagnosis as a runnable model: build the augmented model of each step, and predict records with one.

* :func:`model_of_step` — the :class:`chainid.augmented.AugmentedModel` of a fitted step (its effects and
  parameters, the re-fitted linear spring of a ``--model linear`` baseline, the damping law re-identified at
  that step with its coefficients and per-test c_e, the delay, the mass).
* :func:`predict` — ``chainid predict``: per-test and pooled NRMSE of a model file's baseline and model.
* :func:`negative_damping` — the diagnosis' warning where the damping resolves to a negative dashpot (a run of
  such a model is refused: :mod:`chainid.model.passivity`).

**Which damping ``predict`` uses.**  For a steady harmonic test (one :func:`chainid.gap.harmonic.prepare.prepare_test`
accepts) the model is evaluated exactly as the diagnosis evaluates a held-out test: on the test's phase
grid, memory operators in their periodic steady state, c_e from the *law* at the test's ω, A and x0 — a
prediction, never a refit, and the same number the diagnosis reports (to round-off).  The per-test c_e the
law was fitted on are in the file but used only with ``fitted=True`` (``--fitted-damping``): test ids of
a new file need not be the same tests.  A record that is not a steady harmonic test is predicted in the
time domain as the diagnosis' time route evaluates it (:func:`time_force`: :meth:`AugmentedModel.force` on the
smooth kinematics of :func:`chainid.gap.core.kinematics.estimate`, at the record's operating conditions, with its
own force offset when the model's offsets are per test; operators from their initial state, a law resolved at the
record's dominant ω and A by the rule of :mod:`chainid.model.timedamping`), NRMSE over its samples: the held-out
number the diagnosis reports.

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
from chainid.model.passivity import OperatingPoint, describe, negative_dashpots, refusal
from chainid.model.timedamping import BOX_KEYS, Damping, dominant, record_features
from chainid.gap.core import noise as nz
from chainid.gap.core.kinematics import Kinematics, estimate
from chainid.gap.harmonic.prepare import Unusable, prepare_test
from chainid.gap.timedomain.data import interior


def model_of_step(prob: Any, cand: Any, info: dict[str, Any] | None = None) -> AugmentedModel:
    """The augmented model of a scored candidate (a diagnosis step) on problem ``prob`` (either route).

    A harmonic-route step's damping is its c_e law with the per-test c_e of the training tests [N·s/mm] and k_e
    [N/mm] the diagnosis baseline's stiffness (a linear baseline's k; a chain's: None, the chain at x0): the k_e
    the law was fitted with, not the step's refitted spring ``spring.k``.
    """
    p = cand.params
    names = [e for e in dict.fromkeys(n.split("@", 1)[0] for n in cand.names) if "." not in e]  # effects of the terms
    effects = [(n, {k.split(".", 1)[1]: float(v) for k, v in p.items() if k.startswith(n + ".") and "@" not in k})
               for n in names if n not in NOT_FORCE]
    delay = float(p.get("sensor_delay.tau", 0.0)) if "sensor_delay" in names else 0.0
    info = dict(info or {})
    if getattr(prob, "hprob", True) is None:  # the time-domain route: viscous c, or c following record features
        if "damping_law" in names or "damping_law.b_w" in p:  # the effect, or the base's law
            damping = Damping("feature", {"c": float(p["damping.c"])} | {
                k: float(p[f"damping_law.{k}"]) for k in ("b_w", "b_A", "w_ref", "A_ref", *BOX_KEYS)
                if f"damping_law.{k}" in p})
        else:
            damping = Damping("viscous", {"c": float(p.get("damping.c", 0.0))})
        terms = {k: float(v) for k, v in p.items() if "@" in k}  # every amplitude's slope over a covariate
        refs = {t.split("@", 1)[1]: float(p[f"covariate.{t.split('@', 1)[1]}.ref"]) for t in terms}
        return AugmentedModel(prob.model_for(p), effects, damping, delay, info=info, offsets=prob.base.offsets,
                              covariate_terms=terms, covariate_refs=refs)
    ev = getattr(cand, "_ev", {})
    train = {d.test for d in prob.train}
    per_test = {t: float(c) for t, c in ev.get("c_e", {}).items() if t in train}
    # the law's k_e is the diagnosis baseline's (Problem.ke, which the law was fitted with), not the refitted spring's
    k_e = None if prob.is_chain else float(prob.model.k)
    damping = Damping("law", law=cand.law, coefficients=[float(v) for v in cand.law_params], k_e=k_e,
                      per_test=per_test)
    return AugmentedModel(prob.model_for(p), effects, damping, delay, info=info)


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
    ``summary["_models"]`` the model of every step (``--save-steps``), ``summary["_model"]`` the verdict's (the
    chain without a step that raised the held-out error: what ``--save-model`` writes).

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
    final = models[summary["trusted_steps"] - 1]  # the verdict's chain (verdict.kept_path): no cut step
    summary["model"] = model_to_dict(final)  # in the model file's keys
    summary["_models"] = models
    summary["_model"] = final
    if hasattr(prob, "tdata"):  # a time-domain problem: its records and its harmonic part's tests
        data = list(prob.tdata) + (list(prob.hprob.data) if prob.hprob is not None else [])
    else:
        data = list(prob.data)
    msgs = negative_damping(final, data)
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
    bad = negative_dashpots(model, [_point(model, d) for d in data], fitted)
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
    time_only = ev.get("route") == "time"  # a time-route model: every record sample by sample, as diagnosed
    base = model.baseline or model
    rows, series = [], {}
    tot = {"b": 0.0, "m": 0.0, "v": 0.0}
    prepared = {r.test: None if time_only else _prepared(r, ev) for r in records}
    kin = {r.test: estimate(r.t, r.x, nz.excitation_band(r.t, r.x)) for r in records if prepared[r.test] is None}
    points: dict[str, OperatingPoint] = {}
    for r in records:
        d = prepared[r.test]
        points[r.test] = _point(model, d) if d is not None else _record_point(model, r, kin[r.test])
    _refuse_negative_dashpots(model, records, points, fitted)
    for r in records:
        d = prepared[r.test]
        if d is not None:
            Fm, Fb = model.cycle_force(d, fitted), base.cycle_force(d, fitted)
            (sm, var), (sb, _) = _sse_var(d.Fbar, Fm, d.counts), _sse_var(d.Fbar, Fb, d.counts)
            mode = "steady-cycle"
            if keep:
                series[r.test] = (d.t + d.t_origin, d.x_meas, d.F, Fm[d.bins], Fb[d.bins])
        else:  # on the diagnosis' smooth kinematics (the estimator chosen by the record's spectrum)
            Fm, Fb = time_force(model, r, kin=kin[r.test]), time_force(base, r, kin=kin[r.test])
            w = compared(model, r, kin[r.test]).astype(float)  # the samples the route compares
            (sm, var), (sb, _) = _sse_var(r.F, Fm, w), _sse_var(r.F, Fb, w)
            mode = "time-domain"
            if keep:
                series[r.test] = (r.t, r.x, r.F, Fm, Fb)
        nb, nm = _nrmse(sb, var), _nrmse(sm, var)
        own = model.damping.form == "law" and fitted and r.test in model.damping.per_test
        rows.append({"test": r.test, "nrmse_baseline": nb, "nrmse_model": nm, "shrinkage": _shrink(nm, nb),
                     "mode": mode, "damping": "fitted c_e" if own else model.damping.form})
        tot["b"] += sb
        tot["m"] += sm
        tot["v"] += var
    pb, pm = _nrmse(tot["b"], tot["v"]), _nrmse(tot["m"], tot["v"])
    used = model.damping.form  # a law: the law, or the per-test c_e it was fitted on (only those tests have one)
    if used == "law" and fitted:
        n_own = sum(row["damping"] == "fitted c_e" for row in rows)
        used = (f"per-test fitted c_e on {n_own} test(s) the law was fitted on; the law on the other "
                f"{len(rows) - n_own}" if n_own < len(rows) else "per-test fitted c_e")
    out = {"tests": rows, "pooled": {"nrmse_baseline": pb, "nrmse_model": pm, "shrinkage": _shrink(pm, pb)},
           "model": model_to_dict(model), "damping_used": used, "warnings": []}
    if keep:
        out["_series"] = series
    return out


def _lag_outside(model: AugmentedModel, t: np.ndarray) -> np.ndarray:
    """Samples whose lagged instant t − τ falls before the record's start or after its end: the motion there is
    unknown (all False without a delay)."""
    ts = t - model.delay_s
    return (ts < t[0]) | (ts > t[-1])


def compared(model: AugmentedModel, rec: Any, kin: Kinematics) -> np.ndarray:
    """The samples of a record the time-domain route compares with a model (bool per sample): the record's interior
    (the ends, where the kinematics rest on the filters' padding, left out:
    :func:`chainid.gap.timedomain.data.interior`) where the model's lagged motion is inside the record."""
    t = np.asarray(rec.t, float)
    a, b = interior(kin, nz.sample_rate(t), t.size)
    keep = np.zeros(t.size, bool)
    keep[a:b] = True
    return keep & ~_lag_outside(model, t)


def time_force(model: AugmentedModel, rec: Any, with_kinematics: bool = False, kin: Kinematics | None = None) -> Any:
    """The model force [N] on a record evaluated as the time-domain route evaluates it: on the record's smooth
    kinematics (:func:`chainid.gap.core.kinematics.estimate`), at the record's operating conditions, and with the
    record's own force offset when the model's offsets are per test (nuisance parameters, averaged over the
    samples :func:`compared`).  Where a delayed model's lagged motion falls outside the record the force is unknown
    and the measured force is returned (no residual there).  With ``with_kinematics`` also the kinematics used
    (``kin``: the record's kinematics when already estimated)."""
    kin = kin if kin is not None else estimate(rec.t, rec.x, nz.excitation_band(rec.t, rec.x))
    m = model.at_conditions(getattr(rec, "covariates", None))
    F = np.asarray(m.force(rec.t, kin.x, xd=kin.xd, xdd=kin.xdd, v_err=kin.v_spread(rec.t)), float)
    Fm = np.asarray(rec.F, float)
    keep = compared(model, rec, kin)
    if model.offsets and keep.any():
        F = F + float(np.mean((Fm - F)[keep]))
    if model.delay_s:
        F = np.where(_lag_outside(model, np.asarray(rec.t, float)), Fm, F)
    return (F, kin) if with_kinematics else F


def _refuse_negative_dashpots(model: AugmentedModel, records: Sequence[Any], points: dict[str, OperatingPoint],
                              fitted: bool) -> None:
    """``predict``'s passivity rule (:mod:`chainid.model.passivity`): the model, then its baseline when it has one
    of its own (else the model is its own baseline), each judged at every record's operating point and conditions
    (a damping may follow a covariate); one error naming all the records where it is a negative dashpot, the
    lowest c [N·s/mm] and where, suggesting ``--tests`` only when some records are passive."""
    for who, pick in (("the model", lambda m: m), ("the model's baseline", lambda m: m.baseline)):
        bad = []
        for r in records:
            m = pick(model.at_conditions(getattr(r, "covariates", None)))
            bad += negative_dashpots(m, [points[r.test]], fitted) if m is not None else []
        if bad:
            raise ValueError(refusal(who, bad, "a run with a negative dashpot is refused; " + (
                "diagnose again with another --damping-law or fewer effects" if len(bad) == len(records)
                else "--tests predicts the other tests")))


def _prepared(r: Any, ev: dict[str, Any]) -> Any:
    """The prepared steady harmonic test of a record (as the diagnosis prepares it), or None (a transient)."""
    try:
        return prepare_test(r, n_bins=int(ev.get("n_bins", 64)), allow_compression=bool(ev.get("allow_compression", True)),
                            steady_tol=ev.get("steady_tol"))
    except Unusable:
        return None


def _point(model: AugmentedModel, d: Any) -> OperatingPoint:
    """The operating point of a prepared test (TestData: ω, A, x0) or of a time record (TimeData: its band centre
    and half range for a ``feature`` damping, else its dominant ω and A)."""
    if model.damping.form == "feature":  # the features the fit read (the whole record's, as predict reads them)
        w, A = getattr(d, "omega_c", d.omega), getattr(d, "A_c", d.A)
        return OperatingPoint(d.test, w, A if math.isfinite(A) else d.A, d.x0, d.test)
    return OperatingPoint(d.test, d.omega, d.A, d.x0, d.test)


def _record_point(model: AugmentedModel, rec: Any, kin: Kinematics) -> OperatingPoint:
    """A transient record's operating point as :meth:`AugmentedModel.force` resolves its damping."""
    if model.damping.form == "feature":
        w, A = record_features(rec.t, kin.x)
        return OperatingPoint(rec.test, w, max(A, 1e-12), float(np.mean(kin.x)), rec.test)
    w, A, x0 = dominant(rec.t, kin.x)
    return OperatingPoint(rec.test, w, max(A, 1e-12), x0, rec.test)




def _nrmse(sse: float, var: float) -> float | None:
    return math.sqrt(sse / var) if var > 0 else None


def _shrink(nm: float | None, nb: float | None) -> float | None:
    return 1.0 - nm / nb if nm is not None and nb else None
