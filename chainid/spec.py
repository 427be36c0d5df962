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
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

try:  # Python >= 3.11
    import tomllib as _toml
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as _toml  # type: ignore[no-redef]

__all__ = ["ChainSpec", "default_chain", "load_chain", "PAPER_CHAIN"]


def _require(cond: bool, field: str, value: Any, valid: str) -> None:
    if not cond:
        raise ValueError(f"ChainSpec.{field} = {value!r} is invalid: valid range is {valid}")


@dataclass(frozen=True)
class ChainSpec:
    """A round link chain between two fixtures.

    Parameters
    ----------
    d : float
        Bar diameter [mm], > 0.
    pitch : float
        Inner length of a link [mm], > width.
    width : float
        Inner width of a link [mm], > 0.
    n : int
        Number of links between the fixtures, >= 1.
    E : float
        Young's modulus [MPa], > 0.  Default 210000 (steel).
    nu : float
        Poisson's ratio, in (0, 0.5).  Default 0.3.
    mass_per_m : float
        Mass per metre of chain [kg/m], >= 0.

    Raises
    ------
    ValueError
        Naming the field, its value and the valid range, for any value out of range.
    """

    d: float
    pitch: float
    width: float
    n: int
    E: float = 210000.0
    nu: float = 0.3
    mass_per_m: float = 0.0

    def __post_init__(self) -> None:
        for name in ("d", "pitch", "width", "E", "nu", "mass_per_m"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(float(v)):
                raise ValueError(f"ChainSpec.{name} = {v!r} is invalid: must be a finite number")
            object.__setattr__(self, name, float(v))
        n = self.n
        if isinstance(n, float) and n.is_integer():
            n = int(n)
        _require(isinstance(n, int) and not isinstance(n, bool), "n", self.n, "an integer >= 1")
        object.__setattr__(self, "n", n)
        _require(self.d > 0, "d", self.d, "d > 0 mm")
        _require(self.width > 0, "width", self.width, "width > 0 mm")
        _require(self.pitch > self.width, "pitch", self.pitch, f"pitch > width = {self.width} mm")
        _require(self.n >= 1, "n", self.n, "n >= 1")
        _require(self.E > 0, "E", self.E, "E > 0 MPa")
        _require(0.0 < self.nu < 0.5, "nu", self.nu, "0 < nu < 0.5")
        _require(self.mass_per_m >= 0, "mass_per_m", self.mass_per_m, "mass_per_m >= 0 kg/m")

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
        """Fields as a plain dict (TOML/JSON keys), units as in the class docstring."""
        return asdict(self)

    @classmethod
    def preset(cls, name: str, n: int | None = None) -> "ChainSpec":
        """A standard chain by name, e.g. ``"din22252:26x92"``, ``"studless:76"`` (see :mod:`chainid.presets`)."""
        from .presets import chain  # lazy: presets imports this module

        return chain(name, n=n)


PAPER_CHAIN = ChainSpec(d=14.0, pitch=50.0, width=17.0, n=16, E=210000.0, nu=0.3, mass_per_m=4.0)


def default_chain() -> ChainSpec:
    """The built-in chain: the paper's 14x50 mining chain, n = 16 (see module docstring)."""
    return PAPER_CHAIN


_KEYS = {"d", "pitch", "width", "n", "E", "nu", "mass_per_m"}
_REQUIRED = {"d", "pitch", "width", "n", "mass_per_m"}


def chain_from_mapping(data: dict[str, Any], source: str = "chain") -> ChainSpec:
    """Build a :class:`ChainSpec` from a mapping with the TOML keys.

    Keys: ``d`` mm, ``pitch`` mm, ``width`` mm, ``n``, ``E`` MPa (default 210000),
    ``nu`` (default 0.3), ``mass_per_m`` kg/m.  A ``[chain]`` table is accepted too, and
    ``preset = "din22252:14x50"`` (:mod:`chainid.presets`) with any of the keys overriding it.
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
        or a preset name such as ``"din22252:14x50"`` (:mod:`chainid.presets`).
    """
    if path is None:
        return default_chain()
    from .presets import is_preset_name  # lazy: presets imports this module

    if not Path(path).is_file() and is_preset_name(str(path)):  # e.g. "din22252:14x50"
        return ChainSpec.preset(str(path))
    p = Path(path)
    if not p.is_file():
        raise ValueError(f"chain file {str(p)!r} does not exist")
    with p.open("rb") as fh:
        try:
            data = _toml.load(fh)
        except _toml.TOMLDecodeError as exc:
            raise ValueError(f"chain file {str(p)!r} is not valid TOML: {exc}") from None
    return chain_from_mapping(data, source=f"chain file {str(p)!r}")
