"""The fit bounds and starts of every library effect are dimensionally consistent: a device measured in other
units, or a device of another size, gets the same search relative to its own scales.

Each fitted parameter's unit is read as powers of N, mm and s (kg = N·s²/mm up to a factor); the scales are
changed by λ (force), μ (length; the mean displacement and the velocity with it) and ν (frequency; the velocity with
it, the lag against it), and each finite, non-zero bound and start must change by λ^a·μ^b·ν^(−c).  An absolute
number in a bound (a compliance searched up to 1e-2 mm/N whatever the device) fails here: on a soft device it is
no search at all, on a stiff one a search of nothing but noise.  Units with a fitted exponent (N/mm^p) are left
out: their dimension is the fit's."""
from __future__ import annotations

import math

import pytest

from chainid.model.effects.library import SPECS, Scales

#: powers of (N, mm, s) of the units the library uses
BASE = {"N": (1, 0, 0), "mm": (0, 1, 0), "s": (0, 0, 1), "kg": (1, -1, 2), "rad": (0, 0, 0), "-": (0, 0, 0)}


def powers(unit: str) -> tuple[int, int, int]:
    """(a, b, c) of N^a·mm^b·s^c for a unit such as ``N·s²/mm`` or ``N/mm^3``."""
    u = unit.replace("²", "^2").replace("³", "^3")
    num, _, den = u.partition("/")
    out = [0, 0, 0]
    for sign, part in ((1, num), (-1, den)):
        for tok in filter(None, part.split("·")):
            name, _, p = tok.partition("^")
            for i in range(3):
                out[i] += sign * BASE[name][i] * (int(p) if p else 1)
    return out[0], out[1], out[2]


def test_unit_powers_by_hand():
    assert powers("N·s²/mm") == (1, -1, 2) and powers("N/mm^3") == (1, -3, 0) and powers("mm/N") == (-1, 1, 0)
    assert powers("kg") == (1, -1, 2) and powers("rad/s") == (0, 0, -1) and powers("-") == (0, 0, 0)


FITTED = [(spec.name, p) for spec in SPECS.values() for p in spec.params if p.fitted and "^p" not in p.unit]


@pytest.mark.parametrize("lam, mu, nu", [(3.0, 0.2, 5.0), (1e-3, 40.0, 0.5)])
@pytest.mark.parametrize("effect, param", FITTED, ids=[f"{e}.{p.name}" for e, p in FITTED])
def test_bounds_and_start_scale_with_the_parameters_unit(effect, param, lam, mu, nu):
    s0 = Scales(F=1000.0, x=0.5, omega=6.0, v=3.0, x_mid=2.0)
    s1 = Scales(F=1000.0 * lam, x=0.5 * mu, omega=6.0 * nu, v=3.0 * mu * nu, x_mid=2.0 * mu)
    a, b, c = powers(param.unit)
    ratio = lam ** a * mu ** b * nu ** (-c)
    pairs = [*zip(param.bounds(s0), param.bounds(s1)), (param.guess(s0), param.guess(s1))]
    for v0, v1 in pairs:
        if v0 == v1 and (v0 == 0.0 or math.isinf(v0)):
            continue  # 0 and ±inf are the same in every unit
        assert v1 == pytest.approx(v0 * ratio, rel=1e-9), (effect, param.name, param.unit, v0, v1)


def test_every_unit_of_the_library_is_read():
    units = {p.unit for spec in SPECS.values() for p in spec.params if "^p" not in p.unit}
    for u in units:
        powers(u)  # a unit the table does not know raises KeyError
    assert {e for e, _ in FITTED} == set(SPECS)  # every effect has parameters under the check


@pytest.mark.parametrize("scales", [Scales(F=1000.0, x=0.5, omega=6.0, v=3.0, x_mid=2.0),
                                    Scales(F=5e6, x=20.0, omega=300.0, v=6000.0, x_mid=-50.0)],
                         ids=["rig", "large-chain"])
def test_the_fit_searches_only_physically_valid_values_and_starts_inside_its_bounds(scales):
    """A fitted value can be written to a model file and read back: every fit bound lies in the parameter's valid
    range of :mod:`chainid.model.ranges` (an open end not reached), and the start lies within the fit bounds."""
    from chainid.model.ranges import EFFECT_RANGES

    for spec in SPECS.values():
        for p in spec.params:
            if not p.fitted:
                continue
            r, (lo, hi), g = EFFECT_RANGES[spec.name][p.name], p.bounds(scales), p.guess(scales)
            key = f"{spec.name}.{p.name}"
            assert r.lo <= lo and hi <= r.hi, (key, (lo, hi), (r.lo, r.hi))
            assert not (r.lo_open and lo == r.lo) and not (r.hi_open and hi == r.hi), key
            assert lo <= g <= hi, (key, g, (lo, hi))
