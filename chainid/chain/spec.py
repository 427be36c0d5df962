"""Chain geometry and material: :class:`ChainSpec`, the built-in chain, TOML files.

Units throughout chainid: mm, N, s, MPa (= N/mm²), kg.

Geometry of one round link (paper Fig. 3)::

    d      bar (wire) diameter                                   mm
    pitch  inner length of the link                              mm
    width  inner width of the link                               mm
    R      bend radius of the centre line   = (width + d) / 2    mm
    L      half the straight length          = (pitch - width) / 2 mm

The built-in default is the paper's 14x50 mining chain.  The paper's Fig. 7
(dimensions of the link) is an image that is not in the text; d = 14 mm and
pitch = 50 mm come from the designation "14x50", n = 16 links, E = 210 GPa,
4.0 kg/m and the 800 mm fixture length come from the text, ν = 0.3 is the
usual value for steel, and the inner width 17 mm is the DIN 22252 nominal
inner width of a 14x50 round steel link chain.
"""
from __future__ import annotations

import math
import numbers
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from chainid.chain.catalogue import FAMILIES, canonical_grade, data, dimensions, is_preset_name, suggest_preset

try:  # Python >= 3.11
    import tomllib as _toml
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as _toml  # type: ignore[no-redef]

__all__ = ["ChainSpec", "default_chain", "load_chain", "PAPER_CHAIN", "steel_mass_per_m"]


def _require(cond: bool, field: str, value: Any, valid: str) -> None:
    if not cond:
        raise ValueError(f"ChainSpec.{field} = {value!r} is invalid: valid range is {valid}")


# Physical limits of a round steel link chain (see ChainSpec's docstring for the reasons).
D_MIN, D_MAX = 0.5, 500.0  # bar diameter [mm]
WIDTH_MAX_D = 10.0  # inner width <= 10 d
PITCH_MAX_D = 20.0  # inner length <= 20 d
N_MAX = 1_000_000  # links between the fixtures
E_MIN, E_MAX = 40_000.0, 450_000.0  # Young's modulus [MPa]: magnesium alloys (45 GPa) to tungsten (411 GPa)
STEEL_DENSITY = 7.85e-6  # kg/mm^3
MASS_MAX_FACTOR = 10.0  # mass_per_m <= 10 x the bare steel links' mass per metre


def _real(name: str, v: Any) -> float:
    """A finite real number (Python or numpy int/float, not bool) as float, else ValueError."""
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, numbers.Real):
        raise ValueError(f"ChainSpec.{name} = {v!r} is invalid: must be a finite real number, "
                         f"not {type(v).__name__}")
    f = float(v)
    if not math.isfinite(f):
        raise ValueError(f"ChainSpec.{name} = {v!r} is invalid: must be a finite real number")
    return f


def _count(v: Any) -> int:
    """The link count as int (an int, numpy integer or integral float), else ValueError."""
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, numbers.Real):
        raise ValueError(f"ChainSpec.n = {v!r} is invalid: must be a positive integer, not {type(v).__name__}")
    if isinstance(v, numbers.Integral):
        return int(v)
    f = float(v)
    if not (math.isfinite(f) and f.is_integer()):
        raise ValueError(f"ChainSpec.n = {v!r} is invalid: must be a positive integer (1 <= n <= {N_MAX})")
    return int(f)


def _check_family_grade(spec: "ChainSpec") -> None:
    """Canonicalise and validate ``family`` and ``grade`` (case-insensitive; the grade must apply to the family)."""
    fam, g = spec.family, spec.grade
    if fam is not None:
        if not isinstance(fam, str) or fam.strip().lower() not in FAMILIES:
            raise ValueError(f"ChainSpec.family = {fam!r} is invalid: valid values are {list(FAMILIES)} or None")
        fam = fam.strip().lower()
        object.__setattr__(spec, "family", fam)
    if g is not None:
        if not isinstance(g, str):
            raise ValueError(f"ChainSpec.grade = {g!r} is invalid: must be a grade name such as 'C' or 'R4', "
                             f"not {type(g).__name__}")
        g = canonical_grade(g, fam, what="ChainSpec.grade =")
    elif fam is not None:
        g = data()[fam]["grade"]
    object.__setattr__(spec, "grade", g)


def steel_mass_per_m(d: float, pitch: float, width: float) -> float:
    """Mass per metre [kg/m] of bare round steel links: ρ·(π d²/4)·(2(pitch − width) + π(width + d)) / pitch.

    The bar's centre line is two straights of length pitch − width and two half
    circles of radius (width + d)/2; ρ = 7850 kg/m³.  (14x50, width 17: 3.95 kg/m;
    the paper gives 4.0 kg/m.)
    """
    centre_line = 2.0 * (pitch - width) + math.pi * (width + d)
    return STEEL_DENSITY * math.pi * d * d / 4.0 * centre_line / pitch * 1e3


@dataclass(frozen=True)
class ChainSpec:
    """A round link chain between two fixtures.

    Parameters
    ----------
    d : float
        Bar diameter [mm], 0.5 <= d <= 500.
    pitch : float
        Inner length of a link [mm]: pitch > width and 2 d <= pitch <= 20 d.
    width : float
        Inner width of a link [mm]: d < width <= 10 d.
    n : int
        Number of links between the fixtures, 1 <= n <= 1 000 000.
    E : float
        Young's modulus [MPa], 40 000 <= E <= 450 000.  Default 210000 (steel).
    nu : float
        Poisson's ratio, in (0, 0.5).  Default 0.3.
    mass_per_m : float
        Mass per metre of chain [kg/m], 0 <= mass_per_m <= 10 x that of the bare
        links in steel (:func:`steel_mass_per_m`).
    family : str or None
        ``"din22252"`` (mining chain), ``"studless"`` or ``"studlink"`` (mooring chain), or None (not
        stated: the family is then taken from the preset with the same dimensions, else DIN 22252).
        Case-insensitive.
    grade : str or None
        The steel grade (``[grades]`` of ``chainid/data/chains.toml``): DIN 22252 ``C``; mooring ``R3``,
        ``R3S``, ``R4``, ``R4S``, ``R5``.  Case-insensitive, stored upper-case.  None: the family's default
        (DIN 22252: C, mooring: R3); with no family either, the grade of the preset with the same
        dimensions, else C.  The grade sets the proof and breaking loads and the yield stress used in every
        load warning.

    Notes
    -----
    Numbers may be Python or numpy ints and floats (``np.int64(16)``,
    ``np.float32(14)``); bool, str and None are refused; ``n`` may be an
    integral float (``16.0``, as TOML writes it).

    The limits are physical, so that a unit slip or a typo is refused rather
    than computed:

    - the inner width must let the bar of the next link pass: width > d;
    - the inner length holds the bars of both neighbours and the two bends:
      pitch >= 2 d and pitch > width (the straight part L = (pitch - width)/2 > 0);
    - d from 0.5 mm (finer wire is jewellery, not a load chain) to 500 mm (more
      than twice the largest offshore mooring chain, about 220 mm); width <= 10 d
      and pitch <= 20 d: beyond that the "link" is a wire loop or a rod, outside
      the curved-beam model of the paper (real links: width 1.1 to 1.6 d, pitch
      2.8 to 5 d);
    - E within the engineering metals, magnesium alloys (45 GPa) to tungsten
      (411 GPa); E in GPa (210) or Pa (2.1e11) is refused;
    - n <= 1 000 000 links: 50 km of the 14x50 chain, far beyond any installed
      chain (conveyor and mooring chains have about 10^4 links);
    - mass_per_m at most 10 x the steel links' own mass per metre, which leaves
      room for attachments (flights, sensors) and refuses g/m entered as kg/m.

    All DIN 22252 mining chains (14x50 width 17 ... 42x146 width 46) and studless
    (pitch 4 d, width 1.35 d) and stud-link (4 d, 1.6 d) mooring chains pass.

    Raises
    ------
    ValueError
        Naming the field, its value and the valid range, for any value out of range
        or of a type other than a real number.
    """

    d: float
    pitch: float
    width: float
    n: int
    E: float = 210000.0
    nu: float = 0.3
    mass_per_m: float = 0.0
    family: str | None = None
    grade: str | None = None

    def __post_init__(self) -> None:
        _check_family_grade(self)
        for name in ("d", "pitch", "width", "E", "nu", "mass_per_m"):
            object.__setattr__(self, name, _real(name, getattr(self, name)))
        n_raw = self.n
        object.__setattr__(self, "n", _count(n_raw))
        d, w, p = self.d, self.width, self.pitch
        _require(D_MIN <= d <= D_MAX, "d", d, f"{D_MIN} <= d <= {D_MAX} mm")
        _require(d < w <= WIDTH_MAX_D * d, "width", w,
                 f"d = {d} < width <= {WIDTH_MAX_D:g} d = {WIDTH_MAX_D * d:g} mm "
                 "(the inner width must let the next link's bar pass)")
        lo = max(2.0 * d, w)
        _require(p > w and p >= 2.0 * d and p <= PITCH_MAX_D * d, "pitch", p,
                 f"max(2 d, width) = {lo:g} {'<' if lo == w else '<='} pitch <= {PITCH_MAX_D:g} d = "
                 f"{PITCH_MAX_D * d:g} mm (the inner length holds two bars and the bends)")
        _require(1 <= self.n <= N_MAX, "n", n_raw, f"an integer 1 <= n <= {N_MAX}")
        _require(E_MIN <= self.E <= E_MAX, "E", self.E,
                 f"{E_MIN:.0f} <= E <= {E_MAX:.0f} MPa (engineering metals; E is in MPa, steel 210000)")
        _require(0.0 < self.nu < 0.5, "nu", self.nu, "0 < nu < 0.5")
        m_max = MASS_MAX_FACTOR * steel_mass_per_m(d, p, w)
        _require(0.0 <= self.mass_per_m <= m_max, "mass_per_m", self.mass_per_m,
                 f"0 <= mass_per_m <= {m_max:.4g} kg/m (10 x the bare steel links' mass per metre)")

    # Derived geometry -------------------------------------------------------
    @property
    def R(self) -> float:
        """Bend radius of the link centre line, (width + d)/2 [mm]."""
        return 0.5 * (self.width + self.d)

    @property
    def L(self) -> float:
        """Half the straight length of a link side, (pitch - width)/2 [mm]."""
        return 0.5 * (self.pitch - self.width)

    @property
    def length_mm(self) -> float:
        """Length of the chain between the fixtures, n * pitch [mm] (paper: 16 x 50 = 800 mm)."""
        return self.n * self.pitch

    @property
    def mass_kg(self) -> float:
        """Total mass m of the n links [kg] = mass_per_m * n * pitch / 1000 (paper: 3.2 kg)."""
        return self.mass_per_m * self.length_mm * 1e-3

    def replace(self, **changes: Any) -> "ChainSpec":
        """Return a copy with some fields changed (validated again)."""
        data = asdict(self)
        data.update(changes)
        return ChainSpec(**data)

    def to_dict(self) -> dict[str, Any]:
        """Fields as a plain dict (TOML/JSON keys), units as in the class docstring.

        ``family`` and ``grade`` are left out when None (not stated), so that a chain without them writes
        the same keys as before they existed.
        """
        d = asdict(self)
        return {k: v for k, v in d.items() if not (k in ("family", "grade") and v is None)}

    @classmethod
    def preset(cls, name: str, n: int | None = None) -> "ChainSpec":
        """A standard chain by name, e.g. ``"din22252:26x92"``, ``"studless:76"`` (see :mod:`chainid.chain.presets`)."""
        return cls(**dimensions(name, n=n)["fields"])


PAPER_CHAIN = ChainSpec(d=14.0, pitch=50.0, width=17.0, n=16, E=210000.0, nu=0.3, mass_per_m=4.0,
                        family="din22252", grade="C")


def default_chain() -> ChainSpec:
    """The built-in chain: the paper's 14x50 mining chain, n = 16 (see module docstring)."""
    return PAPER_CHAIN


_KEYS = {"d", "pitch", "width", "n", "E", "nu", "mass_per_m", "family", "grade"}
_REQUIRED = {"d", "pitch", "width", "n", "mass_per_m"}


def chain_from_mapping(data: dict[str, Any], source: str = "chain") -> ChainSpec:
    """Build a :class:`ChainSpec` from a mapping with the TOML keys.

    Keys: ``d`` mm, ``pitch`` mm, ``width`` mm, ``n``, ``E`` MPa (default 210000),
    ``nu`` (default 0.3), ``mass_per_m`` kg/m, optional ``family`` and ``grade`` (see :class:`ChainSpec`).
    A ``[chain]`` table is accepted too, and ``preset = "din22252:14x50"`` (:mod:`chainid.chain.presets`) with
    any of the keys overriding it: the preset's family and grade are kept (``preset = "studless:76:grade=R4"``
    with ``width = 100`` stays a studless R4 chain), unless ``grade`` / ``family`` are given too.
    """
    if "chain" in data and isinstance(data["chain"], dict):
        data = data["chain"]
    if "preset" in data:  # preset = "din22252:14x50"; other keys override the preset's fields
        data = {**ChainSpec.preset(str(data["preset"])).to_dict(), **{k: v for k, v in data.items() if k != "preset"}}
    unknown = set(data) - _KEYS
    if unknown:
        raise ValueError(f"{source}: unknown key(s) {sorted(unknown)}; valid keys are {sorted(_KEYS)}")
    missing = _REQUIRED - set(data)
    if missing:
        raise ValueError(f"{source}: missing key(s) {sorted(missing)}; required keys are {sorted(_REQUIRED)}")
    return ChainSpec(**{k: data[k] for k in data})


def load_chain(path: str | Path | None) -> ChainSpec:
    """Read a chain TOML file (``None`` gives the built-in chain).

    Parameters
    ----------
    path : str or Path or None
        TOML file with keys d, pitch, width, n, E, nu, mass_per_m (units mm, MPa, kg/m),
        or a preset name such as ``"din22252:14x50"`` (:mod:`chainid.chain.presets`).
    """
    if path is None:
        return default_chain()
    if not Path(path).is_file() and is_preset_name(str(path)):  # e.g. "din22252:14x50"
        return ChainSpec.preset(str(path))
    p = Path(path)
    if not p.is_file():
        hint = suggest_preset(str(path))
        raise ValueError(f"chain file {str(p)!r} does not exist" + (f"; {hint}" if hint else ""))
    with p.open("rb") as fh:
        try:
            data = _toml.load(fh)
        except _toml.TOMLDecodeError as exc:
            raise ValueError(f"chain file {str(p)!r} is not valid TOML: {exc}") from None
    return chain_from_mapping(data, source=f"chain file {str(p)!r}")
