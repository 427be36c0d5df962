"""Checks of the chain line's diagnosed-physics fields (chainid.dynamics.effect_fields.check_effects, run by
ChainLine): non-finite values, bools and zeros refused naming the field, the value and the range; numpy scalars
inside the range accepted as ChainLine's other fields accept them.  Units mm, N, s, kg."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.dynamics import ChainLine

KW = dict(n_links=16, n_masses=2)


@pytest.mark.parametrize("kw, message", [
    (dict(hertz_scale=math.inf), "hertz_scale = inf is invalid: valid range > 0"),
    (dict(hertz_scale=-1.0), "hertz_scale = -1.0 is invalid: valid range > 0"),
    (dict(contact_ref_force=0.0), "contact_ref_force = 0.0 is invalid: valid range > 0 N (finite)"),
    (dict(ea_scale=math.nan), "ea_scale = nan is invalid: valid range 0.001 to 1000"),
    (dict(contact_exponent=True), "contact_exponent = True is invalid: valid range None (Hertz) or 0.2 to 1.5"),
    (dict(contact_exponent=math.nan), "contact_exponent = nan is invalid"),
    (dict(compliance=math.inf), "compliance = inf is invalid: valid range >= 0 mm/N (finite)"),
    (dict(compliance=True), "compliance = True is invalid: valid range >= 0 mm/N (finite)"),
    (dict(backlash_mm=math.nan), "backlash_mm = nan is invalid: valid range >= 0 mm (finite)"),
    (dict(drive_mass_kg=math.inf), "drive_mass_kg = inf is invalid: valid range >= 0 kg (finite)"),
    (dict(slack=True), "slack = True is invalid: valid range a finite number of mm"),
    (dict(slack="0.1"), "slack = '0.1' is invalid: valid range a finite number of mm"),
    (dict(stribeck_stiffness=math.inf), "stribeck_stiffness = inf is invalid: valid range > 0 N/mm (finite) or None"),
    (dict(stribeck_stiffness=-5.0), "stribeck_stiffness = -5.0 is invalid"),
    (dict(bouc_wen=5.0), "bouc_wen = 5.0 is invalid: valid range tuples (F_y > 0 N, x_y > 0 mm, n 0.1 to 20, r 0 "
                         "to 1)"),
    (dict(bouc_wen=((5.0, math.inf, 1.0, 1.0),)), "bouc_wen = (5.0, inf, 1.0, 1.0) is invalid"),
    (dict(stribeck=((10.0, 5.0, 1.0),)), "stribeck = (10.0, 5.0, 1.0) is invalid: valid range tuples (F_c >= 0 N"),
    (dict(stribeck=((10.0, 5.0, 1.0, -10.5),)), "stribeck = (10.0, 5.0, 1.0, -10.5) is invalid"),
    (dict(deadband=(1.0, 0.1, 2.0, 0.0, 5.0)), "deadband = (1.0, 0.1, 2.0, 0.0, 5.0) is invalid"),
])
def test_a_field_that_is_not_a_finite_number_in_range_is_refused_by_name(kw, message):
    """Each refusal starts with 'field = value is invalid: valid range …'.
    Bugs caught: the finiteness test of _real dropped (inf passes ``lo <= v <= hi`` with hi = inf), the bool test
    dropped, ``v > 0`` of the scales dropped (0 passes lo = 0), a tuple's width not checked, |dF| without abs."""
    with pytest.raises(ValueError) as exc:
        ChainLine(**KW, **kw)
    assert str(exc.value).startswith(message)


def test_numpy_scalars_inside_the_range_are_accepted():
    """numpy scalars (np.float32, np.int64) inside each range are valid, as they are for pretension_N: the line
    takes them at their value (ea_scale 2 halves c_lin; contact exponent 0.9 makes the spring table's β 0.9).
    Bug caught (found by this test): ``hertz_scale = np.float32(1.5) is invalid: valid range > 0`` (only Python
    int and float were numbers)."""
    plain = ChainLine(**KW).segment_coefficients()[0]
    line = ChainLine(**KW, ea_scale=np.int64(2), hertz_scale=np.float32(1.5), contact_exponent=np.float64(0.9),
                     slack=np.float32(0.25), compliance=np.float32(0.0), drive_mass_kg=np.int64(1),
                     pretension_N=np.float32(100.0))
    np.testing.assert_allclose(line.segment_coefficients()[0], plain / 2.0, rtol=1e-12)
    np.testing.assert_allclose(line.spring_table()[:, 0], 0.9, rtol=1e-12)
    np.testing.assert_allclose(line.spring_table()[:, 1], 0.25 * 8 / 16, rtol=1e-7)
    assert line.node_masses()[0] == pytest.approx(1.0 + 0.5 * 4.0 * 0.4, rel=1e-12)
    with pytest.raises(ValueError, match=r"^hertz_scale = .*0\.0\)? is invalid: valid range > 0$"):  # any numpy repr
        ChainLine(**KW, hertz_scale=np.float32(0.0))
    with pytest.raises(ValueError, match=r"^slack = (np\.)?True_? is invalid"):
        ChainLine(**KW, slack=np.bool_(True))


def test_the_range_ends_of_the_scales_and_an_empty_dead_band():
    """ea_scale just inside 0.001 … 1000 (0.001 and 1000 themselves valid, tested elsewhere) and a tiny positive
    contact reference force are valid; an empty dead band stays () and leaves the spring table's neutral p = 1.
    Bug caught: the dead band normalised to a tuple of zeros (a band of zero width engaged at once)."""
    ChainLine(**KW, ea_scale=0.0010001, contact_ref_force=1e-12)
    line = ChainLine(**KW, deadband=[])
    assert line.deadband == () and line.extended_spring() is False
    assert line.spring_table()[:, 2:].tolist() == [[0.0, 0.0, 1.0, 0.0]] * 2
