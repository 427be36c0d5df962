"""Checks of a :class:`~chainid.dynamics.model.ChainLine`'s diagnosed-physics fields (kernel modifiers, play, dead
band, Stribeck and Bouc–Wen elements, fixture mass): each bad value is refused naming the field, the value and
its valid range.  Units: mm, N, s, kg (see the ChainLine docstring for each field)."""
from __future__ import annotations

import math
import numbers
from typing import Any

__all__ = ["check_effects", "finite_real"]


def _bad(field_name: str, value: object, valid: str) -> ValueError:
    return ValueError(f"{field_name} = {value!r} is invalid: valid range {valid}")


def finite_real(v: Any) -> bool:
    """A finite real number, Python's or numpy's (integer or float), never a bool (numpy's bool is no Real)."""
    return isinstance(v, numbers.Real) and not isinstance(v, bool) and math.isfinite(float(v))


def _tuples(line: Any, name: str, width: int, ok: Any, valid: str) -> None:
    """Normalise ``line.<name>`` to a tuple of float tuples of ``width``, each passing ``ok``."""
    try:
        vals = tuple(tuple(float(x) for x in el) for el in getattr(line, name))
    except (TypeError, ValueError):
        raise _bad(name, getattr(line, name), valid) from None
    for el in vals:
        if len(el) != width or not all(math.isfinite(x) for x in el) or not ok(*el):
            raise _bad(name, el, valid)
    object.__setattr__(line, name, vals)


def check_effects(line: Any) -> None:
    """Check and normalise the diagnosed-physics fields of ``line`` (ValueError naming the field)."""
    for name, lo, hi, valid in (("ea_scale", 1e-3, 1e3, "0.001 to 1000"), ("hertz_scale", 0.0, math.inf, "> 0"),
                                ("contact_ref_force", 0.0, math.inf, "> 0 N (finite)")):
        v = getattr(line, name)
        if not (finite_real(v) and lo <= v <= hi and v > 0):
            raise _bad(name, v, valid)
    beta = line.contact_exponent
    if beta is not None and not (finite_real(beta) and 0.2 <= beta <= 1.5):
        raise _bad("contact_exponent", beta, "None (Hertz) or 0.2 to 1.5")
    for name, valid in (("compliance", ">= 0 mm/N (finite)"), ("backlash_mm", ">= 0 mm (finite)"),
                        ("drive_mass_kg", ">= 0 kg (finite)")):
        v = getattr(line, name)
        if not (finite_real(v) and v >= 0):
            raise _bad(name, v, valid)
    if not finite_real(line.slack):
        raise _bad("slack", line.slack, "a finite number of mm")
    if line.stribeck_stiffness is not None and not (finite_real(line.stribeck_stiffness) and line.stribeck_stiffness > 0):
        raise _bad("stribeck_stiffness", line.stribeck_stiffness, "> 0 N/mm (finite) or None")
    db = tuple(line.deadband)
    if db:
        try:
            db = tuple(float(x) for x in db)
        except (TypeError, ValueError):
            raise _bad("deadband", line.deadband, "() or (k_d >= 0, g >= 0, p 1 to 6, x_c), finite") from None
        if len(db) != 4 or not all(math.isfinite(x) for x in db) or not (db[0] >= 0 and db[1] >= 0
                                                                          and 1.0 <= db[2] <= 6.0):
            raise _bad("deadband", line.deadband, "() or (k_d >= 0 N/mm^p, g >= 0 mm, p 1 to 6, x_c mm), finite")
    object.__setattr__(line, "deadband", db)
    _tuples(line, "stribeck", 4, lambda F_c, dF_s, v_s, dF: F_c >= 0 and dF_s >= 0 and v_s > 0 and abs(dF) <= F_c,
            "tuples (F_c >= 0 N, dF_s >= 0 N, v_s > 0 mm/s, dF N with |dF| <= F_c), finite")
    _tuples(line, "bouc_wen", 4, lambda F_y, x_y, n, r: F_y > 0 and x_y > 0 and 0.1 <= n <= 20 and 0 <= r <= 1,
            "tuples (F_y > 0 N, x_y > 0 mm, n 0.1 to 20, r 0 to 1), finite")
