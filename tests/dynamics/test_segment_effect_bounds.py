"""ChainLine's diagnosed-physics fields refused at their bounds, naming the field, the value and the valid range;
the bounds themselves pass.  Units mm, N, s, kg."""
import pytest

from chainid.dynamics import ChainLine

KW = dict(n_links=16, n_masses=2)


@pytest.mark.parametrize("kw, message", [
    (dict(ea_scale=0.0009), "ea_scale = 0.0009 is invalid: valid range 0.001 to 1000"),
    (dict(ea_scale=1001.0), "ea_scale = 1001.0 is invalid: valid range 0.001 to 1000"),
    (dict(hertz_scale=0.0), "hertz_scale = 0.0 is invalid: valid range > 0"),
    (dict(contact_exponent=0.19), "contact_exponent = 0.19 is invalid: valid range None (Hertz) or 0.2 to 1.5"),
    (dict(contact_exponent=1.51), "contact_exponent = 1.51 is invalid"),
    (dict(contact_ref_force=float("inf")), "contact_ref_force = inf is invalid: valid range > 0 N (finite)"),
    (dict(compliance=-1e-9), "compliance = -1e-09 is invalid: valid range >= 0 mm/N (finite)"),
    (dict(slack=float("nan")), "slack = nan is invalid: valid range a finite number of mm"),
    (dict(backlash_mm=-0.01), "backlash_mm = -0.01 is invalid: valid range >= 0 mm (finite)"),
    (dict(drive_mass_kg=-1.0), "drive_mass_kg = -1.0 is invalid: valid range >= 0 kg (finite)"),
    (dict(stribeck_stiffness=0.0), "stribeck_stiffness = 0.0 is invalid: valid range > 0 N/mm (finite) or None"),
    (dict(deadband=(1.0, 0.1, 0.9, 0.0)), "deadband = (1.0, 0.1, 0.9, 0.0) is invalid: valid range () or (k_d >= 0"),
    (dict(deadband=(1.0, -0.1, 2.0, 0.0)), "deadband = (1.0, -0.1, 2.0, 0.0) is invalid"),
    (dict(deadband=(1.0, 0.1, 2.0)), "deadband = (1.0, 0.1, 2.0) is invalid"),
    (dict(stribeck=((10.0, 5.0, 1.0, 10.5),)), "stribeck = (10.0, 5.0, 1.0, 10.5) is invalid: valid range tuples "
                                               "(F_c >= 0 N, dF_s >= 0 N, v_s > 0 mm/s, dF N with |dF| <= F_c)"),
    (dict(stribeck=((10.0, 5.0, 0.0, 0.0),)), "stribeck = (10.0, 5.0, 0.0, 0.0) is invalid"),
    (dict(stribeck=((10.0, -5.0, 1.0, 0.0),)), "stribeck = (10.0, -5.0, 1.0, 0.0) is invalid"),
    (dict(bouc_wen=((0.0, 0.1, 1.0, 1.0),)), "bouc_wen = (0.0, 0.1, 1.0, 1.0) is invalid: valid range tuples "
                                             "(F_y > 0 N, x_y > 0 mm, n 0.1 to 20, r 0 to 1)"),
    (dict(bouc_wen=((5.0, 0.1, 0.09, 1.0),)), "bouc_wen = (5.0, 0.1, 0.09, 1.0) is invalid"),
    (dict(bouc_wen=((5.0, 0.1, 2.0, 1.01),)), "bouc_wen = (5.0, 0.1, 2.0, 1.01) is invalid"),
    (dict(bouc_wen=((5.0, 0.1, 2.0),)), "bouc_wen = (5.0, 0.1, 2.0) is invalid"),
])
def test_each_field_is_refused_at_its_bound(kw, message):
    with pytest.raises(ValueError) as exc:
        ChainLine(**KW, **kw)
    assert str(exc.value).startswith(message)


def test_the_bounds_pass_and_tuples_are_normalised():
    line = ChainLine(**KW, ea_scale=0.001, hertz_scale=1e-9, contact_exponent=0.2, compliance=0.0, slack=-0.5,
                     backlash_mm=0.0, deadband=[0, 0, 1, -3], stribeck=[[10, 0, 1e-9, -10]],
                     bouc_wen=[[1e-9, 1e-9, 0.1, 0]], drive_mass_kg=0.0)
    assert line.deadband == (0.0, 0.0, 1.0, -3.0) and line.stribeck == ((10.0, 0.0, 1e-9, -10.0),)
    assert line.bouc_wen == ((1e-9, 1e-9, 0.1, 0.0),)
    ChainLine(**KW, ea_scale=1000.0, contact_exponent=1.5, deadband=(1.0, 0.0, 6.0, 0.0), bouc_wen=((1, 1, 20, 1),))


@pytest.mark.parametrize("kw, message", [
    (dict(ea_scale=True), "ea_scale = True is invalid: valid range 0.001 to 1000"),
    (dict(deadband=(-0.5, 0.1, 2.0, 0.0)), "deadband = (-0.5, 0.1, 2.0, 0.0) is invalid: valid range () or (k_d >= 0"),
    (dict(deadband=(1.0, 0.1, 6.5, 0.0)), "deadband = (1.0, 0.1, 6.5, 0.0) is invalid"),
    (dict(deadband=(1.0, 0.1, 2.0, float("inf"))), "deadband = (1.0, 0.1, 2.0, inf) is invalid"),
    (dict(deadband=("x", 0.1, 2.0, 0.0)), "deadband = ('x', 0.1, 2.0, 0.0) is invalid: valid range () or (k_d >= 0"),
    (dict(deadband=(None, 0.1, 2.0, 0.0)), "deadband = (None, 0.1, 2.0, 0.0) is invalid: valid range () or (k_d"),
    (dict(stribeck=((10.0, -0.5, 1.0, 0.0),)), "stribeck = (10.0, -0.5, 1.0, 0.0) is invalid: valid range tuples"),
    (dict(stribeck=((10.0, 5.0, float("inf"), 0.0),)), "stribeck = (10.0, 5.0, inf, 0.0) is invalid"),
    (dict(stribeck=(("a", 5.0, 1.0, 0.0),)), "stribeck = (('a', 5.0, 1.0, 0.0),) is invalid: valid range tuples"),
    (dict(stribeck=((None, 5.0, 1.0, 0.0),)), "stribeck = ((None, 5.0, 1.0, 0.0),) is invalid: valid range tuples"),
    (dict(bouc_wen=((5.0, 0.0, 1.0, 1.0),)), "bouc_wen = (5.0, 0.0, 1.0, 1.0) is invalid: valid range tuples"),
    (dict(bouc_wen=((5.0, 0.1, 20.5, 1.0),)), "bouc_wen = (5.0, 0.1, 20.5, 1.0) is invalid"),
    (dict(bouc_wen=((5.0, 0.1, 2.0, -0.5),)), "bouc_wen = (5.0, 0.1, 2.0, -0.5) is invalid"),
])
def test_values_just_past_a_bound_or_not_numbers_are_refused_as_value_errors(kw, message):
    """Past each bound by less than one unit (k_d = −0.5, dF_s = −0.5, r = −0.5 below 0; p = 6.5 above 6; n = 20.5
    above 20; x_y = 0 not > 0), a non-finite entry, a bool scale and entries that are not numbers (a string: float()
    raises ValueError; None: TypeError) are each refused with a ValueError naming the field, the value and the range.
    Bugs caught: a bound shifted by one (0 → −1, 6 → 7, 20 → 21), ``x_y > 0`` → ``>= 0``, the finiteness test
    dropped, the bool test dropped, one exception type dropped from ``except (TypeError, ValueError)``."""
    with pytest.raises(ValueError) as exc:
        ChainLine(**KW, **kw)
    assert str(exc.value).startswith(message)


def test_a_stribeck_element_without_kinetic_force_is_valid():
    """F_c = 0 N is inside F_c >= 0 (with dF = 0, |dF| <= F_c): a purely static (Stribeck) excess of 5 N is valid.
    Bug caught: ``F_c >= 0`` → ``F_c > 0``."""
    line = ChainLine(**KW, stribeck=((0.0, 5.0, 1.0, 0.0),))
    assert line.stribeck == ((0.0, 5.0, 1.0, 0.0),)
