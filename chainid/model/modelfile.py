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

Loading checks every key against the typed schema (:mod:`chainid.model.schema`: types, physical ranges of
:mod:`chainid.model.ranges`, unknown keys, the version) before anything is built, and names what is wrong by
its key path; valid but implausible values are warnings (:class:`~chainid.model.schema.ModelFileWarning`).
Writing is atomic (:func:`chainid.infra.fileio.atomic_write_text`).
"""

from __future__ import annotations

import json
import math
import tomllib
import warnings
from pathlib import Path
from typing import Any

from chainid.model.augmented import AugmentedModel
from chainid.model.schema import FORMAT_VERSION, KIND, PART_KEYS, UNITS, ModelFileWarning, check_model_dict
from chainid.model.timedamping import Damping

__all__ = ["FORMAT_VERSION", "KIND", "UNITS", "model_to_dict", "model_from_dict", "to_toml", "save_model",
           "load_model"]

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
    """The base model of a checked ``base`` table (:func:`check_model_dict` ran first)."""
    from chainid.model.base import ChainModel, LinearModel
    from chainid.chain.spec import chain_from_mapping

    if d["model"] == "chain":
        mods = {k: float(d[k]) for k in _CHAIN_MODS if k in d}
        return ChainModel(chain_from_mapping(dict(d["chain"]), source=f"{where}.chain"),
                          str(d.get("variant", "paper")), **mods)
    return LinearModel(float(d["k"]), float(d.get("x_ref", 0.0)), mass=float(d.get("mass", 0.0)))


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
        d["baseline"] = {k: b[k] for k in PART_KEYS if k in b}
    for k in ("evaluation", "provenance"):
        if k in m.info:
            d[k] = {kk: vv for kk, vv in m.info[k].items() if vv is not None}
    return d


def model_from_dict(d: dict[str, Any], source: str = "model") -> AugmentedModel:
    """Build the model from the file's dict, checked first against the schema (:func:`check_model_dict`).

    Errors name the source, the key path, the value and the valid values; valid but implausible values are
    issued as :class:`ModelFileWarning` (one per key) and kept in ``model.info["warnings"]``.
    """
    try:
        found = check_model_dict(d)
        m = _model(d, "", with_baseline=True)
    except ValueError as exc:
        raise ValueError(f"{source}: {exc}") from None
    for w in found:
        warnings.warn(f"{source}: {w}", ModelFileWarning, stacklevel=2)
    if found:
        m.info["warnings"] = [f"{source}: {w}" for w in found]
    return m


def _model(d: dict[str, Any], where: str, with_baseline: bool) -> AugmentedModel:
    """The model of a checked dict (``where``: "" or "baseline", for the messages of the constructors)."""
    pre = f"{where}." if where else ""
    effects = [(str(e["name"]), {k: float(v) for k, v in dict(e.get("params", {})).items()})
               for e in d.get("effects", [])]
    base = _base_from(dict(d["base"]), f"{pre}base")
    mass = d.get("mass_kg")
    cov = dict(d.get("covariates", {}))
    try:
        m = AugmentedModel(base, effects, Damping.from_dict(dict(d.get("damping", {})), f"{pre}damping"),
                           float(d.get("delay_s", 0.0)), None if mass is None else float(mass),
                           offsets=dict(d["base"]).get("offsets", "none") == "per-test",
                           covariate_terms={str(k): float(v) for k, v in dict(cov.get("terms", {})).items()},
                           covariate_refs={str(k): float(v) for k, v in dict(cov.get("refs", {})).items()})
    except ValueError as exc:  # a combination the schema cannot see (a chain-only effect on a linear base)
        raise ValueError(f"{pre}effects: {exc}" if "effect" in str(exc) else str(exc)) from None
    if with_baseline and "baseline" in d:
        m.baseline = _model(dict(d["baseline"]), "baseline", with_baseline=False)
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
    except RecursionError:  # e.g. [[[[...]]]] thousands deep: no model file nests beyond a few levels
        raise ValueError(f"model file {str(p)!r} is nested too deeply to be a chainid model file (valid: the "
                         "tables of format_version 1, a few levels deep)") from None
    if not isinstance(d, dict):
        raise ValueError(f"model file {str(p)!r}: the top level must be a table")
    return model_from_dict(d, source=f"model file {str(p)!r}")
