"""The case families of the ODE world (:mod:`chainid.gap.benchmark.odeworld`): which base, excitation, effects and
strengths each case has.

* ``control`` — no effect, on every base and several excitations (the 14×50 chain, the 18×64 preset, the linear
  resonant device under a force, the damping-dominated device, the stiff spring), some with per-test force
  offsets on a linear base;
* ``single`` — each library effect alone at strengths 0.5, 1, 2 (× the typical strength of
  :func:`chainid.gap.benchmark.odecases.effect_params`) on the bases it applies to: chain-only effects
  (stiffness_level, contact_law, slack) on chains, hardening and deadband on linear bases, sensor_delay with the
  force lagging and with the displacement lagging, damping_law (c varying ±20 % over the records by a c(ω, A) law
  linear in the record features) on displacement-driven bases; and damping_law shaped as the paper's Table 1
  (``law_form = "table1"``: a power law in ω and A, curved, so a law linear in the features is a local fit;
  :data:`TABLE1_CASES`);
* ``pair`` — two effects together;
* ``outside`` — relaxation (a Maxwell branch), drift, stick-slip chatter: outside the library;
* ``covariate`` — 3–5 operating conditions with an amplitude parameter linear in the covariate (friction F_c in a
  coil current i, hysteresis F_h in a temperature T, stribeck F_c in a pressure p); the records carry no
  covariate (:class:`chainid.records.record.Record` has none), the truth does.

The excitation of a case cycles through the shapes its base runs; at ``--seed S`` every case's seed is
``S·10⁷ + 200000 + crc32(label) mod 10⁶`` (:mod:`chainid.gap.benchmark.seeds`; its label names family, base,
excitation, effects and levels), so a case of the small set is the same case in the full one.  ``small``: 12
cases, one or two per family, under ~3 minutes on 2 cores.
"""

from __future__ import annotations

import zlib
from typing import Any

from chainid.gap.benchmark.seeds import run_base

__all__ = ["world_cases", "SINGLE_EFFECTS"]

#: effects alone, per base
SINGLE_EFFECTS = {
    "chain14": ("friction", "stribeck", "hysteresis", "bouc_wen", "backlash", "slack", "stiffness_level",
                "contact_law", "sensor_delay", "sensor_delay-", "damping_law"),
    "chain18": ("friction", "hysteresis", "stiffness_level", "slack", "contact_law"),
    "resonant": ("friction", "stribeck", "hysteresis", "bouc_wen", "backlash", "deadband", "hardening",
                 "sensor_delay", "sensor_delay-"),
    "damper": ("friction", "stribeck", "hysteresis", "sensor_delay-", "damping_law"),
    "stiff": ("deadband", "hardening", "backlash", "bouc_wen", "sensor_delay", "damping_law"),
}
#: the excitations each base runs, in the order the cases cycle through them
BASE_EXCITATIONS = {"chain14": ("multisine", "noise", "chirp", "harmonic"), "chain18": ("noise", "harmonic", "multisine"),
                    "resonant": ("multisine", "noise", "chirp", "harmonic"), "damper": ("multisine", "chirp", "noise"),
                    "stiff": ("noise", "multisine", "chirp", "harmonic")}
PAIRS = (("chain14", "friction", "sensor_delay"), ("chain14", "hysteresis", "slack"),
         ("chain14", "backlash", "damping_law"), ("chain18", "friction", "stiffness_level"),
         ("resonant", "stribeck", "hardening"), ("resonant", "hysteresis", "sensor_delay-"),
         ("damper", "bouc_wen", "sensor_delay"), ("stiff", "deadband", "friction"))
OUTSIDE = (("chain14", "relaxation", "chirp"), ("stiff", "relaxation", "chirp"), ("damper", "relaxation", "noise"),
           ("chain14", "drift", "multisine"), ("resonant", "drift", "noise"), ("chain14", "chatter", "multisine"),
           ("stiff", "chatter", "noise"), ("chain18", "chatter", "chirp"))
#: damping_law in the paper's Table 1 shape (base, excitation, level), and one pair with it
TABLE1_CASES = (("chain14", "harmonic", 1.0), ("chain14", "multisine", 1.0), ("chain14", "noise", 2.0),
                ("stiff", "noise", 1.0), ("stiff", "chirp", 2.0), ("damper", "multisine", 1.0),
                ("damper", "chirp", 2.0))
TABLE1_PAIR = ("chain14", "backlash", "chirp", 1.0)
COVARIATES = (("damper", "friction", "F_c", "i", "A", 0.0, 2.0, 5, "multisine"),
              ("chain14", "hysteresis", "F_h", "T", "degC", 20.0, 60.0, 3, "noise"),
              ("stiff", "friction", "F_c", "i", "A", 0.0, 1.5, 4, "chirp"),
              ("resonant", "stribeck", "F_c", "p", "bar", 2.0, 8.0, 4, "multisine"))


def _effect(name: str) -> tuple[str, float]:
    """A plan name and the lag's sign: ``sensor_delay-`` is the displacement lagging."""
    return (name[:-1], -1.0) if name.endswith("-") else (name, 1.0)


def _case(family: str, base: str, excitation: str, effects: dict[str, float], **kw: Any) -> dict[str, Any]:
    eff, sign = {}, 1.0
    for n, lv in effects.items():
        name, sg = _effect(n)
        eff[name] = lv
        sign = sg if name == "sensor_delay" else sign
    label = "+".join(effects) or "+".join(kw.get("outside", {})) or "none"
    lv = "/".join(f"{v:g}" for v in (list(effects.values()) or list(kw.get("outside", {}).values())))
    return {"world": "ode", "family": family, "base": base, "excitation": excitation, "effects": eff,
            "outside": {}, "covariate": None, "sign": sign, "offsets": False,
            "label": f"{family}/{base}/{excitation}/{label}" + (f"@{lv}" if lv else "")
            + ("+offsets" if kw.get("offsets") else "")
            + (f"~{kw['law_form']}" if kw.get("law_form", "linear") != "linear" else ""), **kw}


def _full() -> list[dict[str, Any]]:
    cases: list[dict[str, Any]] = []
    for base, excs in BASE_EXCITATIONS.items():
        for e in excs:
            cases.append(_case("control", base, e, {}))
    cases.append(_case("control", "resonant", "multisine", {}, offsets=True))
    cases.append(_case("control", "stiff", "noise", {}, offsets=True))
    for base, effs in SINGLE_EFFECTS.items():
        excs = BASE_EXCITATIONS[base]
        i = 0
        for eff in effs:
            for lv in (0.5, 1.0, 2.0):
                exc = "harmonic" if eff == "damping_law" and lv != 1.0 and "harmonic" in excs else excs[i % len(excs)]
                if eff == "damping_law" and base == "damper":
                    exc = excs[i % len(excs)]
                cases.append(_case("single", base, exc, {eff: lv}))
                i += 1
    for base, exc, lv in TABLE1_CASES:
        cases.append(_case("single", base, exc, {"damping_law": lv}, law_form="table1"))
    for j, (base, a, b) in enumerate(PAIRS):
        excs = BASE_EXCITATIONS[base]
        for k, lv in enumerate((1.0, 2.0)):
            cases.append(_case("pair", base, excs[(j + k) % len(excs)], {a: lv, b: lv}))
    base, eff, exc, lv = TABLE1_PAIR
    cases.append(_case("pair", base, exc, {eff: lv, "damping_law": lv}, law_form="table1"))
    for base, kind, exc in OUTSIDE:
        for lv in (1.0, 2.0):
            cases.append(_case("outside", base, exc, {}, outside={kind: lv}))
    for base, eff, p, name, unit, lo, hi, n, exc in COVARIATES:
        cases.append(_case("covariate", base, exc, {eff: 1.0}, covariate={
            "name": name, "unit": unit, "effect": eff, "param": p, "lo": lo, "hi": hi, "levels": n,
            "slope_rel": 1.0}))
    return cases


def _small() -> list[dict[str, Any]]:
    cov = COVARIATES[0]
    return [
        _case("control", "chain14", "multisine", {}),
        _case("control", "resonant", "multisine", {}),
        _case("single", "chain14", "noise", {"friction": 1.0}),
        _case("single", "resonant", "multisine", {"hysteresis": 1.0}),
        _case("single", "resonant", "noise", {"hardening": 1.0}),
        _case("single", "chain14", "chirp", {"backlash": 1.0}),
        _case("single", "damper", "multisine", {"sensor_delay-": 1.0}),
        _case("single", "chain14", "harmonic", {"damping_law": 1.0}),
        _case("single", "chain18", "multisine", {"stiffness_level": 1.0}),
        _case("pair", "chain14", "multisine", {"friction": 1.0, "sensor_delay": 1.0}),
        _case("outside", "chain14", "chirp", {}, outside={"relaxation": 1.0}),
        _case("covariate", cov[0], cov[8], {cov[1]: 1.0}, covariate={
            "name": cov[3], "unit": cov[4], "effect": cov[1], "param": cov[2], "lo": cov[5], "hi": cov[6],
            "levels": cov[7], "slope_rel": 1.0}),
    ]


def world_cases(small: bool = False, seed: int = 0) -> list[dict[str, Any]]:
    """The ODE world's cases (``small``: the 12-case subset); every case gets its seed (module docstring).

    Parameters
    ----------
    small : bool
        The small subset.
    seed : int
        First seed of the world (>= 0).

    Returns
    -------
    list of dict
        Cases for :func:`chainid.gap.benchmark.odeworld.run_case`.
    """
    base = run_base(seed)
    cases = _small() if small else _full()
    return [{**c, "seed": base + 200000 + zlib.crc32(c["label"].encode()) % 1_000_000} for c in cases]
