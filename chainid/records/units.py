"""Units at the boundary: a rig's column unit -> chainid's (t s, x mm, F N), with dimension checks by pint.

The default units (s, mm, N) need no conversion and do not import pint.
"""
from __future__ import annotations

from functools import lru_cache

__all__ = ["INTERNAL_UNITS", "HOUSE_UNITS", "factor", "channel_factor"]

#: chainid's internal unit of each role.
INTERNAL_UNITS = {"t": "s", "x": "mm", "F": "N"}
_DIMENSION = {"t": "time", "x": "length", "F": "force"}
_EXAMPLES = {"t": "s, ms, us", "x": "mm, m, um, in", "F": "N, kN, lbf, kip"}


@lru_cache(maxsize=None)
def _registry():  # one pint registry per process (building it takes ~0.2 s)
    import pint

    return pint.UnitRegistry()


@lru_cache(maxsize=64)
def factor(role: str, unit: str | None) -> float:
    """Multiplier from ``unit`` to chainid's unit of ``role`` (``t`` -> s, ``x`` -> mm, ``F`` -> N).

    Parameters
    ----------
    role : {"t", "x", "F"}
        The column's role.
    unit : str or None
        Any unit pint knows (``ms``, ``us``, ``m``, ``um``, ``in``, ``kN``, ``lbf``, ``kip``...); None = the
        internal unit.

    Returns
    -------
    float
        e.g. ``factor("x", "in") == 25.4``.

    Raises
    ------
    ValueError
        An unknown unit, or a unit of the wrong dimension (a force unit for x), naming the role, the unit and
        the expected dimension.
    """
    if role not in INTERNAL_UNITS:
        raise ValueError(f"--units: role {role!r} has no unit; valid roles are {list(INTERNAL_UNITS)}")
    want = INTERNAL_UNITS[role]
    if unit is None or unit.strip() == want:
        return 1.0
    import pint

    ureg = _registry()
    try:
        q = ureg.Quantity(1.0, unit.strip())
        return float(q.to(want).magnitude)
    except pint.errors.DimensionalityError:
        raise ValueError(
            f"--units {role}={unit}: {unit!r} is a unit of {q.dimensionality}, but column {role} needs a "
            f"{_DIMENSION[role]} unit (e.g. {_EXAMPLES[role]})") from None
    except (pint.errors.UndefinedUnitError, pint.errors.DefinitionSyntaxError, AttributeError, TypeError,
            ValueError, AssertionError) as exc:
        raise ValueError(f"--units {role}={unit}: unknown unit ({exc}); column {role} needs a "
                         f"{_DIMENSION[role]} unit (e.g. {_EXAMPLES[role]})") from None


#: chainid's unit of each dimension a kept channel or a reduced covariate may have.
HOUSE_UNITS = ("mm", "N", "s", "MPa", "kg", "A", "mm/s", "Hz")


@lru_cache(maxsize=64)
def channel_factor(name: str, unit: str) -> tuple[float, str]:
    """Multiplier from ``unit`` to chainid's unit of its dimension (:data:`HOUSE_UNITS`) and that unit, for a kept
    channel or a reduced column ``name`` (``bar`` -> (0.1, ``MPa``), ``kN`` -> (1000, ``N``)).

    Raises
    ------
    ValueError
        An unknown unit, or a dimension without a chainid unit (temperature: keep such a channel without a unit).
    """
    import pint

    ureg = _registry()
    try:
        q = ureg.Quantity(1.0, unit.strip())
    except (pint.errors.UndefinedUnitError, pint.errors.DefinitionSyntaxError, AttributeError, TypeError,
            ValueError, AssertionError) as exc:
        raise ValueError(f"--units {name}={unit}: unknown unit ({exc})") from None
    for house in HOUSE_UNITS:
        h = ureg.Quantity(1.0, house)
        if q.dimensionality == h.dimensionality:
            try:
                return float(q.to(house).magnitude), house
            except pint.errors.PintError as exc:  # offset units and the like
                raise ValueError(f"--units {name}={unit}: cannot be converted to {house} ({exc})") from None
    raise ValueError(f"--units {name}={unit}: chainid has no unit for {q.dimensionality} (valid: a unit of "
                     f"{', '.join(HOUSE_UNITS)}); keep the channel as written, without --units")
