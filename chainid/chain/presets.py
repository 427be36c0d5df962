"""Standard chain sizes as presets: DIN 22252 mining chain, studless and stud-link mooring chain.

Units: mm, N, MPa, kg.  The data and the source of every value are in
``chainid/data/chains.toml``.

Preset names (the same spelling in ``--chain``, in :func:`chainid.chain.spec.load_chain`
and in :meth:`chainid.chain.spec.ChainSpec.preset`)::

    din22252:14x50            DIN 22252 size d x pitch (listed sizes only)
    studless:76               offshore studless chain of nominal diameter 76 mm
    studlink:76               offshore stud-link chain (the model has no stud; see the data file)
    din22252:14x50:n=32       any preset with options: n (links), E [MPa], nu, grade

The number of links defaults to 16 (the paper's test), overridable.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from chainid.chain.catalogue import FAMILIES, data, dimensions, format_size, is_preset_name
from chainid.chain.spec import ChainSpec

__all__ = ["FAMILIES", "Preset", "data", "is_preset_name", "resolve", "chain", "listed", "match"]


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
    e = dimensions(name, n=n, grade=grade)
    return Preset(name=e["name"], family=e["family"], chain=ChainSpec(**e["fields"]), grade=e["grade"],
                  outer_width=e["outer_width"], source=e["source"])


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
            out += [resolve(f"{fam}:{format_size(d)}") for d in db[fam]["listed"]]
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
            return resolve(f"{fam}:{format_size(d)}", n=spec.n)
    return None
