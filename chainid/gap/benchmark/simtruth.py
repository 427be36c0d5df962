"""The true parameters of a ``sim``-generator case of ``chainid benchmark-gap`` and the diagnosis' numbers to
score them with.

A sim case builds each in-library effect from an ``--effect`` spec (:func:`chainid.gap.benchmark.nonharmonic.
effect_spec`, e.g. ``friction:F_c=14.7``) read by :func:`chainid.model.effects.parse_effect`; the diagnosis fits
the same library effects (:data:`chainid.model.effects.SPECS`) and reports each parameter as ``effect.param`` (the
harmonic route's ``Problem.bounds``, the time route's design columns).  A row's truth (``true_params``) is therefore:

* **the spec's numbers**, keyed ``effect.param``: every parameter the spec sets, as written.  A parameter the spec
  leaves at its neutral default (friction's ``mu`` and ``x_s``, contact_law's ``beta``, stribeck's ``dF``, ...) is
  not a truth here: the case never sets it.  A parameter the diagnosis does not fit (``fitted=False``:
  hardening's ``x_ref``, which the diagnosis sets to the training data's mean displacement, a choice of
  reference rather than a property of the device) is left out too.  ``damping_law:eta`` is kept, but the harmonic
  route reports the damping law as the coefficients of the law it chose (``law.i``), never ``damping_law.eta``, so
  it is never scored;
* **the base-model mismatch** of a ``mismatch`` / ``mismatch+`` case, where the parameter's definition is
  unambiguous — both are: the true model is ``ChainModel(chain, ea_scale=a, hertz_scale=h)`` and the diagnosis'
  nominal model the same chain at 1, while the library's ``stiffness_level:scale`` and ``contact_law:scale`` (with
  ``beta`` at its Hertz default 2/3) are defined as exactly these factors on the model they act on
  (:func:`chainid.model.effects.compose.modify_model`).  So ``ea_scale`` is ``stiffness_level.scale`` (times a
  simulated ``stiffness_level`` spec's own scale, if a case had both, as the effects compose) and ``hertz_scale``
  is ``contact_law.scale``.  A factor of 1 is no mismatch and no truth.  A verdict naming an effect of the same
  physics under another name (``machine_compliance`` for a softer EA) counts as right, but reports another
  parameter (``machine_compliance.c``), which is then not compared.

Units: each parameter's own (N, mm, s, mm/N, kg, -).
"""

from __future__ import annotations

from typing import Any, Sequence

__all__ = ["spec_truth", "case_truth", "nested", "trusted_fields", "trusted_index", "PARTS",
           "interval_parts"]


def spec_truth(spec: str) -> dict[str, float]:
    """The true parameters an ``--effect`` spec sets, keyed ``effect.param`` as the diagnosis reports them (only
    the parameters written in the spec that the diagnosis fits; see the module docstring).

    Raises
    ------
    ValueError
        An unknown effect or parameter, or a value that is not a number (:func:`chainid.model.effects.parse_spec`).
    """
    from chainid.model.effects import SPECS, parse_spec

    name, params = parse_spec(spec)
    fitted = {p.name for p in SPECS[name].params if p.fitted}
    return {f"{name}.{k}": float(v) for k, v in params.items() if k in fitted}


def case_truth(case: dict[str, Any], specs: Sequence[str]) -> dict[str, float]:
    """The true parameters of a sim case (``effect.param`` → value): the specs' numbers and the base-model
    mismatch (``ea_scale`` → ``stiffness_level.scale``, ``hertz_scale`` → ``contact_law.scale``; see the module
    docstring)."""
    out: dict[str, float] = {}
    for s in specs:
        out.update(spec_truth(s))
    for key, factor in (("stiffness_level.scale", case.get("ea_scale", 1.0)),
                        ("contact_law.scale", case.get("hertz_scale", 1.0))):
        if float(factor) != 1.0:
            out[key] = out.get(key, 1.0) * float(factor)
    return out


def nested(true_params: dict[str, float]) -> dict[str, Any]:
    """``{"effects": {effect: {param: value}}}`` of flat ``effect.param`` truths (the truth form of
    :func:`chainid.gap.benchmark.paramscore.param_scores`)."""
    eff: dict[str, dict[str, float]] = {}
    for key, v in true_params.items():
        e, p = key.split(".", 1)
        eff.setdefault(e, {})[p] = v
    return {"effects": eff}


def trusted_fields(res: dict[str, Any]) -> dict[str, Any]:
    """The diagnosis' numbers of its last trusted step (the verdict's chain, ``res["trusted_steps"]``; steps after
    the held-out minimum are over-fitted and never in the verdict): ``params`` and ``params_ci90`` (the 90 %
    intervals, the resampling's and the profile's merged, :func:`chainid.gap.core.profile.merge`; {} without
    resamples) and ``params_ci90_parts`` (:func:`interval_parts`), each keyed ``effect.param``, and
    ``resample_units`` (the training units the resampling drew; None without one)."""
    i = trusted_index(res)
    units = (res.get("stability") or {}).get("units")
    if i is None:
        return {"params": None, "params_ci90": {}, "params_ci90_parts": {}, "resample_units": units}
    last = res["steps"][i]
    return {"params": last.get("params"), "params_ci90": last.get("params_ci90") or {},
            "params_ci90_parts": interval_parts(res, i), "resample_units": units}


def trusted_index(res: dict[str, Any]) -> int | None:
    """The position in ``res["steps"]`` of the last step of a diagnosis' trusted chain (``res["trusted_steps"]``
    steps, the baseline counted; all of them when it is absent); None without steps."""
    steps = res.get("steps") or []
    if not steps:
        return None
    return max(1, min(int(res.get("trusted_steps", len(steps))), len(steps))) - 1


#: the parts of a reported 90 % interval, by the key of the resampling's step row that holds each
PARTS = {"percentile": "params_ci90_percentile", "resampled": "params_ci90_resampled",
         "profile": "params_ci90_profile"}


def interval_parts(res: dict[str, Any], i: int) -> dict[str, dict[str, list[float]]]:
    """The parts of step ``i``'s reported 90 % intervals, kept apart so the benchmark can score each, from the
    resampling's numbers (``res["stability"]["steps"][i]``): ``percentile`` (the percentiles of the resamples'
    refits, recentred; the time route alone keeps it apart, before :func:`chainid.gap.core.resample.widen`),
    ``resampled`` (those widened by the time sampling's and the displacement noise's biases; the percentiles
    themselves on the harmonic route) and
    ``profile`` (the profile-likelihood intervals); the reported interval merges the last two
    (:func:`chainid.gap.core.profile.merge`).  Each part is ``{effect.param: [lo, hi]}``; a part the step lacks is
    left out ({} without a resampling)."""
    rows = (res.get("stability") or {}).get("steps") or []
    if i >= len(rows):
        return {}
    out: dict[str, dict[str, list[float]]] = {}
    for name, key in PARTS.items():
        for k, v in (rows[i].get(key) or {}).items():
            out.setdefault(name, {})[k] = list(v["ci90"] if isinstance(v, dict) else v)
    return out
