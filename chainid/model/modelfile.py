"""The augmented model file: versioned TOML (or JSON by the ``.json`` suffix), with units and provenance.

Layout (``format_version = 1``; keys of /work/shared/design/architecture.md "Augmented model file")::

    format_version = 1
    kind = "chainid-augmented-model"
    mass_kg = 1.0                 # moving mass [kg]
    delay_s = 0.0                 # force channel lag τ [s]
    [units]                       # length = "mm", force = "N", time = "s", mass = "kg"
    [base]                        # model = "chain" (variant, [base.chain] spec, kernel modifiers) or
                                  # model = "linear" (k [N/mm], x_ref [mm], mass [kg]); offsets = "per-test" when
                                  # each test's force offset is a nuisance parameter (tests at different preloads)
    [covariates]                  # operating conditions: [covariates.refs] name = reference value,
                                  # [covariates.terms] "effect.param@name" = slope (p = p0 + slope·(cov − ref))
    [[effects]]                   # ordered; name = "friction", [effects.params] F_c = …, mu = …, x_s = …
    [damping]                     # form = "law" (law, coefficients, rule, k_e, [damping.per_test]) or a
                                  # time-domain form with [damping.params] (chainid.timedamping)
    [baseline]                    # the model predict compares with (same keys, no provenance)
    [evaluation]                  # how harmonic tests are prepared: n_bins, steady_tol, allow_compression
    [provenance]                  # data_sha256, data_file, command, chainid_version, date

Loading checks the version and every key and names what is wrong; writing is atomic
(:func:`chainid.fileio.atomic_write_text`).
"""

from __future__ import annotations

import json
import math
import tomllib
from pathlib import Path
from typing import Any

from chainid.model.augmented import AugmentedModel
from chainid.model.timedamping import Damping

FORMAT_VERSION = 1
KIND = "chainid-augmented-model"
UNITS = {"length": "mm", "force": "N", "time": "s", "mass": "kg"}
_TOP = {"format_version", "kind", "units", "base", "mass_kg", "effects", "damping", "delay_s", "baseline",
        "evaluation", "provenance", "covariates"}
_MODEL_KEYS = ("base", "mass_kg", "delay_s", "effects", "damping", "covariates")
_CHAIN_MODS = ("slack", "compliance", "hertz_scale", "contact_exponent", "contact_ref_force", "ea_scale")


# ---------------------------------------------------------------------- dict form
def _base_dict(base: Any) -> dict[str, Any]:
    if hasattr(base, "hertz_scale"):
        d: dict[str, Any] = {"model": "chain", "variant": base.variant, "chain": base.chain.to_dict()}
        for k in _CHAIN_MODS:
            v = getattr(base, k)
            if v is not None:
                d[k] = float(v)
        return d
    if hasattr(base, "k") and hasattr(base, "x_ref"):
        return {"model": "linear", "k": float(base.k), "x_ref": float(base.x_ref), "mass": float(base.mass)}
    raise ValueError(f"base model {getattr(base, 'name', base)!r} cannot be written: chain or linear only")


def _base_from(d: dict[str, Any], where: str) -> Any:
    from chainid.model.base import ChainModel, LinearModel
    from chainid.chain.spec import chain_from_mapping

    kind = d.get("model")
    if kind == "chain":
        known = {"model", "variant", "chain"} | set(_CHAIN_MODS)
        _unknown(d, known, where)
        mods = {k: d[k] for k in _CHAIN_MODS if k in d}
        return ChainModel(chain_from_mapping(dict(d.get("chain", {})), source=f"{where}.chain"),
                          str(d.get("variant", "paper")), **mods)
    if kind == "linear":
        _unknown(d, {"model", "k", "x_ref", "mass", "offsets"}, where)
        if d.get("offsets", "none") not in ("none", "per-test"):
            raise ValueError(f"{where}.offsets = {d.get('offsets')!r} is unknown; valid: none, per-test")
        if "k" not in d:
            raise ValueError(f"{where}: a linear base needs k [N/mm]")
        return LinearModel(float(d["k"]), float(d.get("x_ref", 0.0)), mass=float(d.get("mass", 0.0)))
    raise ValueError(f"{where}.model = {kind!r} is unknown; valid: chain, linear")


def _unknown(d: dict[str, Any], known: set[str], where: str) -> None:
    bad = set(d) - known
    if bad:
        raise ValueError(f"{where}: unknown key(s) {sorted(bad)}; valid: {sorted(known)}")


def model_to_dict(m: AugmentedModel) -> dict[str, Any]:
    """The model as the file's dict (format_version 1), provenance and evaluation from ``m.info``."""
    d: dict[str, Any] = {
        "format_version": FORMAT_VERSION,
        "kind": KIND,
        "units": dict(UNITS),
        "base": _base_dict(m.base),
        "mass_kg": m.mass,
        "delay_s": float(m.delay_s),
        "effects": [{"name": n, "params": {k: float(v) for k, v in p.items()}} for n, p in m.effects],
        "damping": m.damping.to_dict(),
    }
    if m.offsets:
        d["base"]["offsets"] = "per-test"
    if m.covariate_terms:
        d["covariates"] = {"refs": {k: float(v) for k, v in m.covariate_refs.items()},
                           "terms": {k: float(v) for k, v in m.covariate_terms.items()}}
    if m.baseline is not None:
        b = model_to_dict(m.baseline)
        d["baseline"] = {k: b[k] for k in _MODEL_KEYS if k in b}
    for k in ("evaluation", "provenance"):
        if k in m.info:
            d[k] = {kk: vv for kk, vv in m.info[k].items() if vv is not None}
    return d


def model_from_dict(d: dict[str, Any], source: str = "model") -> AugmentedModel:
    """Build the model from the file's dict; errors name the file, the key and the valid values."""
    ver = d.get("format_version")
    if ver is None:
        raise ValueError(f"{source}: format_version is missing (a chainid model file has format_version = 1)")
    if ver != FORMAT_VERSION:
        raise ValueError(f"{source}: format_version = {ver!r} is not supported; this chainid reads version "
                         f"{FORMAT_VERSION}")
    if d.get("kind", KIND) != KIND:
        raise ValueError(f"{source}: kind = {d.get('kind')!r}; expected {KIND!r}")
    _unknown(d, _TOP, source)
    units = d.get("units", UNITS)
    if units != UNITS:
        raise ValueError(f"{source}: units = {units!r}; this format uses {UNITS}")
    return _model(d, source, with_baseline=True)


def _model(d: dict[str, Any], where: str, with_baseline: bool) -> AugmentedModel:
    if "base" not in d:
        raise ValueError(f"{where}: [base] is missing")
    effects = []
    for i, e in enumerate(d.get("effects", [])):
        _unknown(e, {"name", "params"}, f"{where}.effects[{i}]")
        effects.append((str(e.get("name")), {k: float(v) for k, v in dict(e.get("params", {})).items()}))
    base = _base_from(dict(d["base"]), f"{where}.base")
    mass = d.get("mass_kg")
    cov = dict(d.get("covariates", {}))
    _unknown(cov, {"refs", "terms"}, f"{where}.covariates")
    m = AugmentedModel(base, effects, Damping.from_dict(dict(d.get("damping", {})), f"{where}.damping"),
                       float(d.get("delay_s", 0.0)), None if mass is None else float(mass),
                       offsets=dict(d["base"]).get("offsets", "none") == "per-test",
                       covariate_terms={str(k): float(v) for k, v in dict(cov.get("terms", {})).items()},
                       covariate_refs={str(k): float(v) for k, v in dict(cov.get("refs", {})).items()})
    if with_baseline and "baseline" in d:
        b = dict(d["baseline"])
        _unknown(b, set(_MODEL_KEYS), f"{where}.baseline")
        m.baseline = _model(b, f"{where}.baseline", with_baseline=False)
    m.info = {k: dict(d[k]) for k in ("evaluation", "provenance") if k in d}
    return m


# ---------------------------------------------------------------------- TOML text
def _scalar(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_scalar(x) for x in v) + "]"
    raise ValueError(f"cannot write {type(v).__name__} {v!r} to TOML")


def _key(k: str) -> str:
    return k if k and all(c.isalnum() or c in "_-" for c in k) else json.dumps(k)


def to_toml(d: dict[str, Any], prefix: str = "") -> str:
    """TOML text of a dict of scalars, lists, tables and arrays of tables (None values omitted)."""
    lines, tables, arrays = [], [], []
    for k, v in d.items():
        if v is None:
            continue
        if isinstance(v, dict):
            tables.append((k, v))
        elif isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
            arrays.append((k, v))
        else:
            lines.append(f"{_key(k)} = {_scalar(v)}")
    out = "\n".join(lines) + ("\n" if lines else "")
    for k, v in tables:
        name = f"{prefix}{_key(k)}"
        out += f"\n[{name}]\n" + to_toml(v, name + ".")
    for k, v in arrays:
        name = f"{prefix}{_key(k)}"
        for item in v:
            out += f"\n[[{name}]]\n" + to_toml(item, name + ".")
    return out


# ---------------------------------------------------------------------- files
def save_model(model: AugmentedModel, path: str | Path, overwrite: bool = False) -> Path:
    """Write the model file atomically (TOML; JSON when the name ends in ``.json``)."""
    from chainid.infra.fileio import atomic_write_text

    p = Path(path)
    d = model_to_dict(model)
    text = json.dumps(d, indent=2) + "\n" if p.suffix.lower() == ".json" else "# chainid augmented model\n" + to_toml(d)
    atomic_write_text(p, text, force=overwrite, what="model file")
    return p


def load_model(path: str | Path) -> AugmentedModel:
    """Read a model file (TOML or JSON); clear errors for a missing file, bad syntax, version or keys."""
    p = Path(path)
    if not p.is_file():
        raise ValueError(f"model file {str(p)!r} does not exist")
    try:
        if p.suffix.lower() == ".json":
            d = json.loads(p.read_text(encoding="utf-8"))
        else:
            with p.open("rb") as fh:
                d = tomllib.load(fh)
    except (tomllib.TOMLDecodeError, json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise ValueError(f"model file {str(p)!r} is not valid {'JSON' if p.suffix == '.json' else 'TOML'}: {exc}") from None
    if not isinstance(d, dict):
        raise ValueError(f"model file {str(p)!r}: the top level must be a table")
    return model_from_dict(d, source=f"model file {str(p)!r}")
