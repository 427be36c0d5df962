"""The typed schema of the augmented model file, checked on every load (``predict``, ``simulate --model``,
``dynamics --segment-model``: all read it through :func:`chainid.model.modelfile.load_model`).

A model file is edited by hand (a parameter tuned, a run repeated), so every key is checked before anything is
built from it: its type (a number is never a string, a list or true/false; a table is never a number), and its
physical range from :mod:`chainid.model.ranges` (one table of the effect parameters; the kernel modifiers take the
ranges of their effects).  An error names the key by its full path (``effects[1].params.F_c``), the value and
the valid range; a value that is valid but implausible (a friction force of 50 MN) is a warning with the same
path.  Every key is checked whether or not the run uses it (a NaN in an unused field is an error too).

Keys and types (``format_version = 1``; units mm, N, s, kg):

==============================  =============================================================================
key                             type
==============================  =============================================================================
``format_version``              integer, required; 1 (a newer version is refused: upgrade chainid)
``kind``                        string ``"chainid-augmented-model"``
``units``                       table, exactly length mm, force N, time s, mass kg
``base``                        table, required: ``model`` = ``"chain"`` (``variant`` string, ``chain`` table of
                                the chain keys, kernel modifiers ``slack`` ``compliance`` ``hertz_scale``
                                ``contact_exponent`` ``ea_scale`` ``contact_ref_force`` numbers) or ``"linear"``
                                (``k`` N/mm required, ``x_ref`` mm, ``mass`` kg, ``offsets`` = ``"none"`` or
                                ``"per-test"``: one force offset per test, a nuisance parameter)
``mass_kg``, ``delay_s``        numbers
``effects``                     array of tables ``{name = string, params = table of numbers}``
``damping``                     table: ``form`` string, ``params`` table of numbers, ``law`` string,
                                ``coefficients`` array of numbers, ``k_e`` number, ``rule`` string,
                                ``per_test`` table of numbers
``covariates``                  table: ``refs`` (table: operating condition → reference value) and ``terms``
                                (table: ``"effect.param@condition"``, or ``damping.c@…``, ``spring.k@…`` → slope per unit of the condition; the
                                parameter is p0 + slope·(condition − ref), each condition with a ref)
``baseline``                    table: ``base``, ``mass_kg``, ``delay_s``, ``effects``, ``damping``,
                                ``covariates`` as above
``evaluation``                  table: ``n_bins`` integer, ``steady_tol`` number, ``allow_compression`` true/false,
                                ``route`` = ``"harmonic"`` or ``"time"`` (how the diagnosis compared the records)
``provenance``                  table of strings: ``data_sha256`` (64 hex digits), ``data_file``, ``command``,
                                ``chainid_version``, ``date``
==============================  =============================================================================

**Unknown keys are errors** (naming the key, its path and the valid keys): a misspelt key (``F_C``,
``mass``) would otherwise be dropped without a word and the run would use the default.  Forward compatibility
goes through ``format_version``: a file with new keys carries a new version, which this chainid refuses by name
(rather than running a model whose new parts it would ignore).
"""
from __future__ import annotations

import re
from typing import Any

from chainid.model.ranges import DAMPING_RANGES, EFFECT_RANGES, MODEL_RANGES, MODIFIER_OF, Range, check_number

__all__ = ["FORMAT_VERSION", "KIND", "UNITS", "ModelFileWarning", "check_model_dict"]

FORMAT_VERSION = 1
KIND = "chainid-augmented-model"
UNITS = {"length": "mm", "force": "N", "time": "s", "mass": "kg"}
TOP_KEYS = ("format_version", "kind", "units", "base", "mass_kg", "effects", "damping", "delay_s", "baseline",
            "evaluation", "provenance", "covariates")
PART_KEYS = ("base", "mass_kg", "delay_s", "effects", "damping", "covariates")
CHAIN_MODS = ("slack", "compliance", "hertz_scale", "contact_exponent", "ea_scale", "contact_ref_force")
DAMPING_KEYS = ("form", "params", "law", "coefficients", "k_e", "rule", "per_test")
EVALUATION_KEYS = ("n_bins", "steady_tol", "allow_compression", "route")
PROVENANCE_KEYS = ("data_sha256", "data_file", "command", "chainid_version", "date")


class ModelFileWarning(UserWarning):
    """A model-file value that is valid but implausible (it is used as given)."""


def _join(path: str, key: str) -> str:
    return f"{path}.{key}" if path else key


def _kind(v: Any) -> str:
    if isinstance(v, bool):
        return "true/false"
    return {dict: "a table", list: "an array", str: "a string", int: "a number", float: "a number"}.get(
        type(v), type(v).__name__)


def _table(v: Any, path: str) -> dict[str, Any]:
    if not isinstance(v, dict):
        raise ValueError(f"{path} = {v!r} is invalid ({_kind(v)}): valid values are a table of keys")
    return v


def _known(d: dict[str, Any], known: tuple[str, ...], path: str) -> None:
    bad = [k for k in d if k not in known]
    if bad:
        where = ", ".join(_join(path, str(k)) for k in bad)
        raise ValueError(f"unknown key{'s' if len(bad) > 1 else ''} {where} (format_version {FORMAT_VERSION}); valid "
                         f"keys{' of ' + path if path else ''}: {', '.join(known)}")


def _string(v: Any, path: str, choices: tuple[str, ...] | None = None) -> str:
    if not isinstance(v, str):
        valid = f"one of {', '.join(choices)}" if choices else "a string"
        raise ValueError(f"{path} = {v!r} is invalid ({_kind(v)}): valid values are {valid}")
    if choices is not None and v not in choices:
        raise ValueError(f"{path} = {v!r} is invalid: valid values are {', '.join(choices)}")
    return v


class _Check:
    """One pass over a file's dict: raises on the first error, collects the warnings."""

    def __init__(self) -> None:
        self.warnings: list[str] = []

    def num(self, v: Any, rng: Range, path: str) -> float:
        x, w = check_number(v, rng, path)
        if w:
            self.warnings.append(w)
        return x

    def nums(self, d: dict[str, Any], ranges: dict[str, Range], path: str) -> None:
        for k, v in d.items():
            self.num(v, ranges[k], _join(path, k))

    # ------------------------------------------------------------------ parts
    def base(self, b: Any, path: str) -> None:
        from chainid.model.kernels import VARIANTS

        b = _table(b, path)
        model = _string(b.get("model"), _join(path, "model"), ("chain", "linear"))
        if model == "linear":
            _known(b, ("model", "k", "x_ref", "mass", "offsets"), path)
            if "offsets" in b:
                _string(b["offsets"], _join(path, "offsets"), ("none", "per-test"))
            if "k" not in b:
                raise ValueError(f"{_join(path, 'k')} is missing: a linear base needs k [N/mm] "
                                 f"({MODEL_RANGES['k'].valid_text()})")
            self.num(b["k"], MODEL_RANGES["k"], _join(path, "k"))
            if "x_ref" in b:
                self.num(b["x_ref"], MODEL_RANGES["x_ref"], _join(path, "x_ref"))
            if "mass" in b:
                self.num(b["mass"], MODEL_RANGES["mass_kg"], _join(path, "mass"))
            return
        _known(b, ("model", "variant", "chain", *CHAIN_MODS), path)
        if "variant" in b:
            _string(b["variant"], _join(path, "variant"), tuple(VARIANTS))
        for k in CHAIN_MODS:
            if k in b:
                rng = MODEL_RANGES[k] if k not in MODIFIER_OF else EFFECT_RANGES[MODIFIER_OF[k][0]][MODIFIER_OF[k][1]]
                self.num(b[k], rng, _join(path, k))
        where = _join(path, "chain")
        if "chain" not in b:
            raise ValueError(f"{where} is missing: a chain base needs its chain (d, pitch, width, n, mass_per_m ...)")
        from chainid.chain.spec import chain_from_mapping

        try:
            chain_from_mapping(dict(_table(b["chain"], where)), source=where)
        except ValueError as exc:
            msg = str(exc)
            raise ValueError(msg if msg.startswith(where) else f"{where}: {msg}") from None

    def effects(self, e: Any, path: str) -> None:
        from chainid.model.augmented import NOT_FORCE
        from chainid.model.effects import EFFECT_NAMES

        if not isinstance(e, list):
            raise ValueError(f"{path} = {e!r} is invalid ({_kind(e)}): valid values are an array of tables "
                             "[[effects]] with name and params")
        names = tuple(n for n in EFFECT_NAMES if n not in NOT_FORCE)
        for i, item in enumerate(e):
            where = f"{path}[{i}]"
            item = _table(item, where)
            _known(item, ("name", "params"), where)
            try:
                name = _string(item.get("name"), f"{where}.name", names)
            except ValueError as exc:
                raise ValueError(f"{exc} (the delay is delay_s, the damping law is [damping])") from None
            params = _table(item.get("params", {}), f"{where}.params")
            ranges = EFFECT_RANGES[name]
            bad = [k for k in params if k not in ranges]
            if bad:
                raise ValueError(f"unknown parameter {where}.params.{bad[0]} of effect {name!r}; valid parameters: "
                                 f"{', '.join(ranges)}")
            self.nums(params, ranges, f"{where}.params")

    def damping(self, d: Any, path: str) -> None:
        from chainid.model.timedamping import FORMS, LAWS, RULES

        d = _table(d, path)
        _known(d, DAMPING_KEYS, path)
        form = _string(d.get("form", "none"), _join(path, "form"), tuple(FORMS))
        params = _table(d.get("params", {}), _join(path, "params"))
        ranges = DAMPING_RANGES.get(form, {})
        _known(params, tuple(FORMS[form]), _join(path, "params"))
        self.nums(params, ranges, _join(path, "params"))
        law = None
        if "law" in d or form == "law":
            law = _string(d.get("law"), _join(path, "law"), tuple(LAWS))
        if "coefficients" in d or form == "law":
            co = d.get("coefficients")
            where = _join(path, "coefficients")
            if not isinstance(co, list):
                raise ValueError(f"{where} = {co!r} is invalid ({_kind(co)}): valid values are an array of numbers")
            if law is not None and len(co) != LAWS[law]:
                raise ValueError(f"{where} has {len(co)} number(s): valid: {LAWS[law]} for law {law!r}")
            for i, v in enumerate(co):
                self.num(v, DAMPING_RANGES["law"]["coefficient"], f"{where}[{i}]")
        if "k_e" in d:
            self.num(d["k_e"], DAMPING_RANGES["law"]["k_e"], _join(path, "k_e"))
        if "rule" in d:
            _string(d["rule"], _join(path, "rule"), tuple(RULES))
        per = _table(d.get("per_test", {}), _join(path, "per_test"))
        for k, v in per.items():
            self.num(v, DAMPING_RANGES["law"]["per_test"], f"{_join(path, 'per_test')}.{k}")

    def covariates(self, c: Any, effects: Any, path: str) -> None:
        """``refs`` numbers; ``terms`` keyed ``effect.param@condition`` of a listed effect, a condition with a ref."""
        c = _table(c, path)
        _known(c, ("refs", "terms"), path)
        refs = _table(c.get("refs", {}), _join(path, "refs"))
        for k, v in refs.items():
            self.num(v, MODEL_RANGES["covariate"], f"{_join(path, 'refs')}.{k}")
        names = {e.get("name") for e in effects if isinstance(e, dict)} if isinstance(effects, list) else set()
        terms = _table(c.get("terms", {}), _join(path, "terms"))
        for k, v in terms.items():
            where = f"{_join(path, 'terms')}.{k}"
            m = re.fullmatch(r"([a-z_]+)\.([A-Za-z_0-9]+)@(.+)", str(k))
            if m is None:
                raise ValueError(f"{where}: the key {k!r} is invalid: valid keys are \"effect.param@condition\"")
            eff, par, cov = m.groups()
            if (eff, par) in (("damping", "c"), ("spring", "k")):  # the base's viscous c, a linear base's k
                pass
            elif eff not in names:
                raise ValueError(f"{where}: effect {eff!r} is not in the model's effects (valid: damping.c, "
                                 f"spring.k, {', '.join(sorted(str(n) for n in names)) or 'no effect'})")
            elif par not in EFFECT_RANGES.get(eff, {}):
                raise ValueError(f"{where}: {par!r} is not a parameter of effect {eff!r} (valid: "
                                 f"{', '.join(EFFECT_RANGES.get(eff, {}))})")
            if cov not in refs:
                raise ValueError(f"{where}: condition {cov!r} has no reference value in {_join(path, 'refs')}")
            self.num(v, MODEL_RANGES["covariate"], where)

    def part(self, d: dict[str, Any], path: str) -> None:
        """base, mass_kg, delay_s, effects, damping of the model (path "") or of its baseline."""
        if "base" not in d:
            raise ValueError(f"{_join(path, 'base')} is missing: a model needs its base (model = \"chain\" or "
                             "\"linear\")")
        self.base(d["base"], _join(path, "base"))
        for k in ("mass_kg", "delay_s"):
            if k in d:
                self.num(d[k], MODEL_RANGES[k], _join(path, k))
        if "effects" in d:
            self.effects(d["effects"], _join(path, "effects"))
        if "damping" in d:
            self.damping(d["damping"], _join(path, "damping"))
        if "covariates" in d:
            self.covariates(d["covariates"], d.get("effects", []), _join(path, "covariates"))

    def evaluation(self, e: Any) -> None:
        e = _table(e, "evaluation")
        _known(e, EVALUATION_KEYS, "evaluation")
        if "n_bins" in e:
            self.num(e["n_bins"], MODEL_RANGES["n_bins"], "evaluation.n_bins")
        if e.get("steady_tol") is not None:
            self.num(e["steady_tol"], MODEL_RANGES["steady_tol"], "evaluation.steady_tol")
        if "route" in e:
            _string(e["route"], "evaluation.route", ("harmonic", "time"))
        if "allow_compression" in e and not isinstance(e["allow_compression"], bool):
            v = e["allow_compression"]
            raise ValueError(f"evaluation.allow_compression = {v!r} is invalid ({_kind(v)}): valid values are "
                             "true or false")

    def provenance(self, p: Any) -> None:
        p = _table(p, "provenance")
        _known(p, PROVENANCE_KEYS, "provenance")
        for k, v in p.items():
            if v is not None:
                _string(v, f"provenance.{k}")
        sha = p.get("data_sha256")
        if sha is not None and not re.fullmatch(r"[0-9a-fA-F]{64}", sha):
            raise ValueError(f"provenance.data_sha256 = {sha!r} is invalid: valid values are 64 hexadecimal digits")


def check_model_dict(d: Any) -> list[str]:
    """Check a model file's dict against the schema (see the module docstring).

    Returns
    -------
    list of str
        Warnings: valid but implausible values, each naming its key path.

    Raises
    ------
    ValueError
        The first error: a missing or wrong ``format_version``, an unknown key, a wrong type or a value
        outside its valid range, naming the key path, the value and what is valid.
    """
    if not isinstance(d, dict):
        raise ValueError(f"the top level is {_kind(d)}: valid: a table of keys (format_version, base, ...)")
    ver = d.get("format_version")
    if ver is None:
        raise ValueError(f"format_version is missing (a chainid model file has format_version = {FORMAT_VERSION})")
    if isinstance(ver, bool) or not isinstance(ver, int):
        raise ValueError(f"format_version = {ver!r} is invalid ({_kind(ver)}): valid values are the integer "
                         f"{FORMAT_VERSION}")
    if ver != FORMAT_VERSION:
        newer = " (written by a newer chainid: upgrade chainid to read it)" if ver > FORMAT_VERSION else ""
        raise ValueError(f"format_version = {ver!r} is not supported{newer}; this chainid reads version "
                         f"{FORMAT_VERSION}")
    if "kind" in d:
        _string(d["kind"], "kind", (KIND,))
    _known(d, TOP_KEYS, "")
    if "units" in d:
        units = _table(d["units"], "units")
        _known(units, tuple(UNITS), "units")
        for k, v in units.items():
            _string(v, f"units.{k}", (UNITS[k],))
    c = _Check()
    c.part(d, "")
    if "baseline" in d:
        b = _table(d["baseline"], "baseline")
        _known(b, PART_KEYS, "baseline")
        c.part(b, "baseline")
    if "evaluation" in d:
        c.evaluation(d["evaluation"])
    if "provenance" in d:
        c.provenance(d["provenance"])
    return c.warnings
