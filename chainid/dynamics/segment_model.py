"""A diagnosed model file (issue 17) as the segments of a chain line: ``chainid dynamics --segment-model M.toml``.

The model file describes one *specimen* (the tested piece of chain of n_ref = ``base.chain.n`` links):
its chain kernel (``base``), memory effects and a time-domain damping.  Every segment of the chain line
carries the same physics, scaled in series (springs and dampers in series: a segment of n_s links carries
the specimen's force at n_s/n_ref times its elongation, so every compliance scales by n_s/n_ref and every
force is unchanged; see :class:`chainid.dynamics.model.ChainLine`):

==================================  ==================================================================
model file                          segment (specimen values; scaled by ChainLine)
==================================  ==================================================================
``base.model = "chain"``            chain spec and kernel variant of the line; n_ref = base.chain.n
``damping.form = "viscous"`` c      viscous c [N·s/mm] (``damping``)
``damping.form = "hysteretic"``     Iwan elements of :func:`chainid.model.operators.iwan_for_loss`
  eta_k, x_max, n                   (F_c,i, x_s,i) → Jenkins (k = F_c/x_s, f = F_c) (``hysteresis``)
``damping.form = "coulomb"``        Coulomb with stick: f = F_c, stick stiffness F_c/x_s (x_s = 0: rigid
  F_c, x_s                          stick, regularised by the specimen's link stiffness 1/c_lin)
``effects`` ``friction``            the same Jenkins element (mu = 0 only: a load-dependent friction
  F_c, x_s, mu                      force is not a segment element)
==================================  ==================================================================

Refused with a message naming the key: a linear base, kernel modifiers and stiffness-side effects (the
segments carry the generated chain kernel), Dahl hysteresis (no segment form; use ``hysteretic``), an
identified ``law`` (c_e(ω, A) has no meaning in a transient: convert it to a time-domain form first), the
mass and the delay are not used (segment masses come from the chain, a sensor lag is not dynamics).
"""
from __future__ import annotations

import json
import math
import tomllib
from pathlib import Path
from typing import Any

from chainid.chain.spec import chain_from_mapping
from chainid.model.operators import iwan_for_loss

__all__ = ["segment_kwargs", "read_model_file"]

_STIFFNESS_SIDE = ("slack", "compliance", "hertz_scale", "contact_exponent", "contact_ref_force", "ea_scale")


def read_model_file(path: str | Path) -> dict[str, Any]:
    """The model file's dict (TOML, or JSON by the ``.json`` suffix), checked for format_version 1."""
    p = Path(path)
    if not p.is_file():
        raise ValueError(f"--segment-model {str(p)!r}: not an existing file")
    try:
        d = json.loads(p.read_text(encoding="utf-8")) if p.suffix.lower() == ".json" else \
            tomllib.loads(p.read_text(encoding="utf-8"))
    except (ValueError, UnicodeDecodeError) as exc:
        raise ValueError(f"--segment-model {str(p)!r}: not a readable model file ({exc})") from None
    if d.get("format_version") != 1:
        raise ValueError(f"{p}: format_version = {d.get('format_version')!r} is not supported; valid: 1")
    units = d.get("units", {"length": "mm", "force": "N", "time": "s", "mass": "kg"})
    if units.get("length", "mm") != "mm" or units.get("force", "N") != "N":
        raise ValueError(f"{p}: units = {units!r}; valid: length mm, force N")
    return d


def _num(d: dict[str, Any], key: str, where: str, default: float | None = None) -> float:
    v = d.get(key, default)
    if v is None or isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v < 0:
        raise ValueError(f"{where}.{key} = {v!r} is invalid: valid range a finite number >= 0")
    return float(v)


def segment_kwargs(path: str | Path) -> dict[str, Any]:
    """Keyword arguments of :class:`~chainid.dynamics.model.ChainLine` from a model file (see the module docstring).

    Returns
    -------
    dict
        ``chain``, ``variant``, ``damping_ref_links`` (n_ref), ``damping`` [N·s/mm], ``hysteresis``
        ((k [N/mm], f [N]), ...), ``coulomb_N`` [N], ``coulomb_stiffness`` [N/mm] or None.
    """
    d = read_model_file(path)
    src = str(path)
    base = d.get("base", {})
    if base.get("model") != "chain":
        raise ValueError(f"{src}: base.model = {base.get('model')!r}; dynamics segments need a chain base "
                         "(the generated kernel of a chain spec)")
    mods = [k for k in _STIFFNESS_SIDE if base.get(k) is not None]
    if mods:
        raise ValueError(f"{src}: base kernel modifiers {mods} are not supported by dynamics segments "
                         "(they carry the unmodified chain kernel)")
    chain = chain_from_mapping(dict(base.get("chain", {})), source=f"{src}: base.chain")
    out: dict[str, Any] = {"chain": chain, "variant": str(base.get("variant", "paper")),
                           "damping_ref_links": int(chain.n), "damping": 0.0, "hysteresis": (),
                           "coulomb_N": 0.0, "coulomb_stiffness": None}
    els: list[tuple[float, float]] = []
    for i, eff in enumerate(d.get("effects", [])):
        name, p = eff.get("name"), eff.get("params", {})
        where = f"{src}: effects[{i}] ({name})"
        if name != "friction":
            raise ValueError(f"{where}: effect {name!r} is not supported by dynamics segments; valid: friction "
                             "(with mu = 0)")
        if _num(p, "mu", where, 0.0) != 0.0:
            raise ValueError(f"{where}: mu = {p['mu']!r}; a load-dependent friction is not a segment element "
                             "(valid: mu = 0)")
        F_c, x_s = _num(p, "F_c", where), _num(p, "x_s", where, 0.0)
        if F_c > 0:
            _add(out, els, F_c, x_s)
    dmp = d.get("damping", {"form": "none"})
    form, p = dmp.get("form", "none"), dmp.get("params", {})
    where = f"{src}: damping ({form})"
    if form == "viscous":
        out["damping"] = _num(p, "c", where)
    elif form == "hysteretic":
        n = int(p.get("n", 32))
        F_c, x_s = iwan_for_loss(_num(p, "eta_k", where), _num(p, "x_max", where), n)
        els += [(float(f) / float(x), float(f)) for f, x in zip(F_c, x_s) if f > 0]
    elif form == "coulomb":
        _add(out, els, _num(p, "F_c", where), _num(p, "x_s", where, 0.0))
    elif form != "none":
        raise ValueError(f"{where}: damping form {form!r} is not supported by dynamics segments; valid: none, "
                         "viscous, hysteretic, coulomb (convert a law or a Dahl model to one of them)")
    out["hysteresis"] = tuple(els)
    return out


def _add(out: dict[str, Any], els: list[tuple[float, float]], F_c: float, x_s: float) -> None:
    """A Jenkins element (x_s > 0) or, for a rigid stick (x_s = 0), the line's Coulomb element."""
    if x_s > 0:
        els.append((F_c / x_s, F_c))
    elif out["coulomb_N"] > 0:
        raise ValueError("two Coulomb elements with rigid stick (x_s = 0) in one model; valid: one")
    else:
        out["coulomb_N"] = F_c
