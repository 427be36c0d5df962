"""The catalogue of standard chain sizes: ``chainid/data/chains.toml`` and preset names resolved to dimensions.

Units: mm, MPa, kg/m.  This is the data layer under :class:`chainid.chain.spec.ChainSpec` (which builds a chain
from a name) and :mod:`chainid.chain.presets` (the :class:`~chainid.chain.presets.Preset` objects): it returns
plain numbers, so that neither needs the other to read the catalogue.
"""
from __future__ import annotations

from functools import lru_cache
from pathlib import Path
from typing import Any

try:  # Python >= 3.11
    import tomllib as _toml
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as _toml  # type: ignore[no-redef]

__all__ = ["FAMILIES", "data", "is_preset_name", "dimensions", "format_size", "canonical_grade", "suggest_preset"]

#: Preset families: DIN 22252 mining chain and offshore mooring chain.
FAMILIES: tuple[str, ...] = ("din22252", "studless", "studlink")
_OPTIONS = {"n", "E", "nu", "grade"}
_OPTION_KEYS = {k.lower(): k for k in _OPTIONS}  # option keys are case-insensitive: N=32, e=200000, GRADE=r4


@lru_cache(maxsize=1)
def data() -> dict[str, Any]:
    """The parsed ``chainid/data/chains.toml`` (read once)."""
    path = Path(__file__).resolve().parents[1] / "data" / "chains.toml"
    with path.open("rb") as fh:
        return _toml.load(fh)


def is_preset_name(text: str) -> bool:
    """True if ``text`` looks like a preset name (``family:size...``) rather than a file path."""
    head = str(text).split(":", 1)[0].lower()
    return ":" in str(text) and head in FAMILIES


def canonical_grade(grade: str, family: str | None = None, what: str = "grade") -> str:
    """The grade's canonical (upper-case) key, checked against the family.

    Parameters
    ----------
    grade : str
        Any case: ``"r4"``, ``"R4s"``, ``"c"``.
    family : str or None
        One of :data:`FAMILIES` (DIN 22252 takes the nominal-stress grades, mooring chain the W22 grades), or
        None (any grade).
    what : str
        The field's name in the error message (``"grade"``, ``"ChainSpec.grade ="``).

    Raises
    ------
    ValueError
        Unknown grade, or a grade of the other kind of chain.
    """
    grades = data()["grades"]
    g = str(grade).strip().upper()
    if g not in grades:
        raise ValueError(f"{what} {grade!r} is invalid: valid grades are {sorted(grades)}")
    if family is not None and (family == "din22252") != (grades[g]["kind"] == "nominal_stress"):
        valid = sorted(k for k, v in grades.items() if (v["kind"] == "nominal_stress") == (family == "din22252"))
        raise ValueError(f"{what} {grade!r} does not apply to {family} chain: valid grades are {valid}")
    return g


def suggest_preset(text: str) -> str:
    """A hint for a ``--chain`` value that is neither a file nor a preset name (empty if none fits).

    ``"din:26x92"`` gives ``"preset names are spelled din22252:SIZE, studless:D, studlink:D (options
    :n=, :E=, :nu=, :grade=); did you mean 'din22252:26x92'?"``.
    """
    import difflib

    t = str(text).strip()
    spelled = ("preset names are spelled din22252:DxPITCH, studless:D, studlink:D (d in mm; options :n=, :E=, "
               ":nu=, :grade=; `chainid chains` lists them)")
    if ":" not in t:
        return spelled if not t.lower().endswith(".toml") else ""
    head, _, rest = t.partition(":")
    h = head.strip().lower()
    fams = ([f for f in FAMILIES if h and f.startswith(h)] or difflib.get_close_matches(h, FAMILIES, n=1, cutoff=0.5)
            or [f for f in FAMILIES if h.startswith(f[:3])])
    if not fams:
        return spelled
    fam = fams[0]
    size, _, opts = rest.partition(":")
    size = size.strip().lower().replace("×", "x")
    if fam == "din22252":
        sizes = [r[0] for r in data()[fam]["sizes"]]
        close = difflib.get_close_matches(size, sizes, n=1, cutoff=0.0)
        size = close[0] if close else sizes[0]
    guess = f"{fam}:{size}" + (f":{opts}" if opts else "")
    return f"{spelled}; did you mean {guess!r}?"


def format_size(v: float) -> str:
    """A size number as the preset names write it (76, 76.5) [mm]."""
    return f"{v:g}"


def _parse_options(parts: list[str], name: str) -> dict[str, Any]:
    """The ``key=value`` options of a preset name; each key at most once (a repeated key, in any case, is an
    error: ``studless:76:n=32:n=64`` would otherwise silently mean n = 64)."""
    opts: dict[str, Any] = {}
    raw: dict[str, str] = {}
    for p in parts:
        if "=" not in p:
            raise ValueError(f"preset {name!r}: option {p!r} is invalid; use key=value with keys {sorted(_OPTIONS)}")
        k, v = (s.strip() for s in p.split("=", 1))
        k = _OPTION_KEYS.get(k.lower(), k)
        if k not in _OPTIONS:
            raise ValueError(f"preset {name!r}: unknown option {k!r}; valid options are {sorted(_OPTIONS)}")
        if k in raw:
            raise ValueError(f"preset {name!r}: option {k!r} is given twice ({k}={raw[k]} and {k}={v}); "
                             "valid: each option at most once")
        raw[k] = v
        if k == "grade":
            opts[k] = v
            continue
        try:
            num = float(v)
        except ValueError:
            raise ValueError(f"preset {name!r}: option {k} = {v!r} is not a number") from None
        opts[k] = int(num) if k == "n" and num.is_integer() else num
    return opts


def dimensions(name: str, n: int | None = None, grade: str | None = None) -> dict[str, Any]:
    """A preset name resolved to its catalogue entry (see :func:`chainid.chain.presets.resolve` for the names).

    Returns
    -------
    dict
        ``name`` (canonical), ``family``, ``fields`` (the :class:`~chainid.chain.spec.ChainSpec` keywords: d,
        pitch, width mm, n, E MPa, nu, mass_per_m kg/m, family, grade), ``grade`` (canonical, upper-case), ``outer_width`` [mm], ``source``.

    Raises
    ------
    ValueError
        Unknown family or size, d outside the family's range, bad or repeated option.

    Notes
    -----
    An explicit ``n`` or ``grade`` argument beats the name's ``:n=`` / ``:grade=`` option (the caller's
    choice is the later, more specific one); ``chainid chains --grade`` says so in a note.
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
        canon = f"{family}:{format_size(d)}"
    g = grade or opts.get("grade") or fam["grade"]
    try:
        g = canonical_grade(g, family)
    except ValueError as exc:
        raise ValueError(f"preset {name!r}: {exc}") from None
    links = n if n is not None else opts.get("n", defaults["n"])
    fields = {"d": d, "pitch": pitch, "width": width, "n": links, "E": opts.get("E", defaults["E"]),
              "nu": opts.get("nu", defaults["nu"]), "mass_per_m": mass, "family": family, "grade": g}
    return {"name": canon, "family": family, "fields": fields, "grade": g, "outer_width": float(outer),
            "source": fam["source"]}
