"""Standard chain sizes as presets: DIN 22252 mining chain, studless and stud-link mooring chain.

Units: mm, N, MPa, kg.  The data and the source of every value are in
``chainid/data/chains.toml``.

Preset names (the same spelling in ``--chain``, in :func:`chainid.spec.load_chain`
and in :meth:`chainid.spec.ChainSpec.preset`)::

    din22252:14x50            DIN 22252 size d x pitch (listed sizes only)
    studless:76               offshore studless chain of nominal diameter 76 mm
    studlink:76               offshore stud-link chain (the model has no stud; see the data file)
    din22252:14x50:n=32       any preset with options: n (links), E [MPa], nu, grade

The number of links defaults to 16 (the paper's test), overridable.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any

try:  # Python >= 3.11
    import tomllib as _toml
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as _toml  # type: ignore[no-redef]

from .spec import ChainSpec

__all__ = ["FAMILIES", "Preset", "data", "is_preset_name", "resolve", "chain", "listed", "match"]

#: Preset families: DIN 22252 mining chain and offshore mooring chain.
FAMILIES: tuple[str, ...] = ("din22252", "studless", "studlink")
_OPTIONS = {"n", "E", "nu", "grade"}


@dataclass(frozen=True)
class Preset:
    """A resolved preset: the chain, its family, size label, grade and source text.

    Attributes
    ----------
    name : str
        Canonical name, e.g. ``"din22252:14x50"`` or ``"studless:76"`` (options not included).
    family : str
        One of :data:`FAMILIES`.
    chain : ChainSpec
        Geometry [mm], E [MPa], ν, n, mass per metre [kg/m].
    grade : str
        Grade key of ``[grades]`` in the data file (e.g. ``"C"``, ``"R3"``).
    outer_width : float
        Outer width of a link [mm] (DIN 22252: maximum b2; mooring: 3.35 d / 3.6 d).
    source : str
        Where the dimensions come from (keys explained in the data file's header).
    """

    name: str
    family: str
    chain: ChainSpec
    grade: str
    outer_width: float
    source: str

    @property
    def studlink(self) -> bool:
        """True for stud-link chain (which the paper's model, having no stud, does not describe)."""
        return self.family == "studlink"


@lru_cache(maxsize=1)
def data() -> dict[str, Any]:
    """The parsed ``chainid/data/chains.toml`` (read once)."""
    path = Path(__file__).resolve().parent / "data" / "chains.toml"
    with path.open("rb") as fh:
        return _toml.load(fh)


def is_preset_name(text: str) -> bool:
    """True if ``text`` looks like a preset name (``family:size...``) rather than a file path."""
    head = str(text).split(":", 1)[0].lower()
    return ":" in str(text) and head in FAMILIES


def _fmt(v: float) -> str:
    return f"{v:g}"


def _parse_options(parts: list[str], name: str) -> dict[str, Any]:
    opts: dict[str, Any] = {}
    for p in parts:
        if "=" not in p:
            raise ValueError(f"preset {name!r}: option {p!r} is invalid; use key=value with keys {sorted(_OPTIONS)}")
        k, v = (s.strip() for s in p.split("=", 1))
        if k not in _OPTIONS:
            raise ValueError(f"preset {name!r}: unknown option {k!r}; valid options are {sorted(_OPTIONS)}")
        if k == "grade":
            opts[k] = v
            continue
        try:
            num = float(v)
        except ValueError:
            raise ValueError(f"preset {name!r}: option {k} = {v!r} is not a number") from None
        opts[k] = int(num) if k == "n" and num.is_integer() else num
    return opts


def resolve(name: str, n: int | None = None, grade: str | None = None) -> Preset:
    """Resolve a preset name to a :class:`Preset`.

    Parameters
    ----------
    name : str
        ``din22252:<d>x<pitch>``, ``studless:<d>`` or ``studlink:<d>`` (d in mm), optionally followed by
        ``:n=<links>``, ``:E=<MPa>``, ``:nu=<ν>``, ``:grade=<grade>``.
    n : int, optional
        Number of links between the fixtures; overrides the name's option and the default (16).
    grade : str, optional
        Grade key (``C`` for DIN 22252; ``R3``, ``R3S``, ``R4``, ``R4S``, ``R5`` for mooring chain).

    Raises
    ------
    ValueError
        Unknown family or size, d outside the family's range, bad option.
    """
    text = str(name).strip()
    parts = text.split(":")
    family = parts[0].lower()
    if family not in FAMILIES or len(parts) < 2 or not parts[1]:
        raise ValueError(f"preset name {name!r} is invalid: use one of {[f + ':SIZE' for f in FAMILIES]} "
                         f"(`chainid chains` lists them)")
    opts = _parse_options(parts[2:], text)
    db = data()
    defaults = db["defaults"]
    fam = db[family]
    size = parts[1].lower().replace("×", "x")
    if family == "din22252":
        rows = {r[0]: r for r in fam["sizes"]}
        if size not in rows:
            raise ValueError(f"preset {name!r}: DIN 22252 size {size!r} is not listed; valid sizes are {list(rows)}")
        _, d, pitch, width, outer, mass = rows[size]
        canon = f"din22252:{size}"
    else:
        try:
            d = float(size)
        except ValueError:
            raise ValueError(f"preset {name!r}: nominal diameter {size!r} is not a number (mm)") from None
        if not (fam["d_min"] <= d <= fam["d_max"]):
            raise ValueError(f"preset {name!r}: nominal diameter d = {d:g} mm is invalid: valid range is "
                             f"{fam['d_min']:g} <= d <= {fam['d_max']:g} mm")
        pitch = round(fam["pitch_over_d"] * d, 9)
        outer = round(fam["outer_width_over_d"] * d, 9)
        width = round(outer - 2.0 * d, 9)
        mass = round(fam["mass_coeff"] * d * d, 9)
        canon = f"{family}:{_fmt(d)}"
    g = grade or opts.get("grade") or fam["grade"]
    if g not in db["grades"]:
        raise ValueError(f"preset {name!r}: grade {g!r} is unknown; valid grades are {sorted(db['grades'])}")
    if (family == "din22252") != (db["grades"][g]["kind"] == "nominal_stress"):
        raise ValueError(f"preset {name!r}: grade {g!r} does not apply to {family} chain")
    links = n if n is not None else opts.get("n", defaults["n"])
    spec = ChainSpec(d=d, pitch=pitch, width=width, n=links, E=opts.get("E", defaults["E"]),
                     nu=opts.get("nu", defaults["nu"]), mass_per_m=mass)
    return Preset(name=canon, family=family, chain=spec, grade=g, outer_width=float(outer), source=fam["source"])


def chain(name: str, n: int | None = None) -> ChainSpec:
    """The :class:`ChainSpec` of a preset name (see :func:`resolve`)."""
    return resolve(name, n=n).chain


def listed(families: tuple[str, ...] = FAMILIES) -> list[Preset]:
    """Every preset that ``chainid chains`` lists (DIN 22252 sizes, the listed mooring diameters)."""
    db = data()
    out: list[Preset] = []
    for fam in families:
        if fam == "din22252":
            out += [resolve(f"din22252:{r[0]}") for r in db[fam]["sizes"]]
        else:
            out += [resolve(f"{fam}:{_fmt(d)}") for d in db[fam]["listed"]]
    return out


def match(spec: ChainSpec) -> Preset | None:
    """The listed or parametric preset with the same d, pitch and width as ``spec`` (n, E, ν may differ), or None.

    Used to find a chain's grade (proof and breaking loads) when it was given by dimensions.
    """
    for p in listed(("din22252",)):
        c = p.chain
        if math.isclose(c.d, spec.d) and math.isclose(c.pitch, spec.pitch) and math.isclose(c.width, spec.width):
            return resolve(p.name, n=spec.n)
    db = data()
    for fam in ("studless", "studlink"):
        f = db[fam]
        d = spec.d
        if (f["d_min"] <= d <= f["d_max"] and math.isclose(spec.pitch, f["pitch_over_d"] * d)
                and math.isclose(spec.width, (f["outer_width_over_d"] - 2.0) * d)):
            return resolve(f"{fam}:{_fmt(d)}", n=spec.n)
    return None
