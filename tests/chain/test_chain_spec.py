"""ChainSpec (chainid.chain.spec): field ranges, closed bounds and their messages, derived geometry, steel mass,
TOML files.  Units mm, MPa, kg/m."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.chain.spec import ChainSpec, default_chain, load_chain, steel_mass_per_m
from chainid.model import kernels


GOOD = dict(d=14.0, pitch=50.0, width=17.0, n=16, E=210000.0, nu=0.3, mass_per_m=4.0)


#: the bare 14x50 links (width 17) by hand: 7.85e-6 kg/mm³ · π·14²/4 mm² · (2·33 + π·31) mm / 50 mm · 1000 mm/m
STEEL_14x50 = 7.85e-6 * math.pi * 14.0**2 / 4.0 * (2 * 33.0 + math.pi * 31.0) / 50.0 * 1e3


@pytest.mark.parametrize("changes", [
    dict(d=0.5, width=0.6, pitch=1.0, mass_per_m=0.0), dict(d=500.0, width=600.0, pitch=2000.0, mass_per_m=0.0),
    dict(width=140.0, pitch=200.0),  # width = 10 d
    dict(n=1), dict(n=1_000_000), dict(E=40_000.0), dict(E=450_000.0), dict(mass_per_m=0.0),
    dict(mass_per_m=10.0 * STEEL_14x50 * (1 - 1e-12)),
])
def test_the_documented_closed_bounds_are_accepted(changes):
    """ChainSpec's docstring gives closed ranges: 0.5 <= d <= 500 mm, width <= 10 d, 1 <= n <= 1 000 000,
    40 000 <= E <= 450 000 MPa, 0 <= mass_per_m <= 10 × the bare steel links' mass.  Each bound itself is a
    valid chain.  Bugs caught: any of these ``<=`` made strict."""
    c = ChainSpec(**(GOOD | changes))
    for k, v in changes.items():
        assert getattr(c, k) == v


@pytest.mark.parametrize("changes,message", [
    (dict(d=0.49, width=0.6, pitch=1.0), "ChainSpec.d = 0.49 is invalid: valid range is 0.5 <= d <= 500.0 mm"),
    (dict(width=140.1, pitch=200.0), "ChainSpec.width = 140.1 is invalid: valid range is d = 14.0 < width <= 10 d "
                                     "= 140 mm (the inner width must let the next link's bar pass)"),
    (dict(E=39_999.0), "ChainSpec.E = 39999.0 is invalid: valid range is 40000 <= E <= 450000 MPa"),
    (dict(E=450_001.0), "ChainSpec.E = 450001.0 is invalid: valid range is 40000 <= E <= 450000 MPa"),
    (dict(mass_per_m=-1e-9), "ChainSpec.mass_per_m = -1e-09 is invalid: valid range is 0 <= mass_per_m <= 39.49 "
                             "kg/m (10 x the bare steel links' mass per metre)"),
    (dict(mass_per_m=39.5), "valid range is 0 <= mass_per_m <= 39.49 kg/m"),
    (dict(nu=0.0), "ChainSpec.nu = 0.0 is invalid: valid range is 0 < nu < 0.5"),
    (dict(n=-1), "ChainSpec.n = -1 is invalid: valid range is an integer 1 <= n <= 1000000"),
])
def test_just_outside_a_bound_the_message_states_the_range_by_hand(changes, message):
    """Just outside each bound: the message names the field, the value and the range (the 14x50 chain's mass
    bound 10 × 3.949 = 39.49 kg/m by hand)."""
    with pytest.raises(ValueError) as info:
        ChainSpec(**(GOOD | changes))
    assert message in str(info.value)


def test_steel_mass_and_derived_geometry_of_the_paper_chain_by_hand():
    """14x50, width 17: bare links 3.949 kg/m (the docstring's 3.95); R = (17 + 14)/2 = 15.5 mm, L = (50 − 17)/2 =
    16.5 mm, 16 links = 800 mm and 4.0 kg/m × 0.8 m = 3.2 kg (the paper's numbers)."""
    assert steel_mass_per_m(14.0, 50.0, 17.0) == pytest.approx(STEEL_14x50, rel=1e-12)
    assert round(STEEL_14x50, 2) == 3.95
    c = ChainSpec(**GOOD)
    assert (c.R, c.L, c.length_mm) == (15.5, 16.5, 800.0)
    assert c.mass_kg == pytest.approx(3.2, rel=1e-12)


def test_family_and_grade_defaults_and_the_dict_keys():
    """A family without a grade takes the family's default grade (DIN 22252: C, mooring: R3, the catalogue);
    the family is case-insensitive; a grade alone is canonicalised; with neither, both stay None and ``to_dict``
    leaves them out (the keys a chain file had before they existed).  A non-string grade is refused naming
    its type."""
    assert ChainSpec(**GOOD, family="Studless").to_dict()["grade"] == "R3"
    assert ChainSpec(**GOOD, family="DIN22252").grade == "C"
    c = ChainSpec(**GOOD, grade="c")
    assert (c.family, c.grade) == (None, "C") and c.to_dict()["grade"] == "C" and "family" not in c.to_dict()
    assert ChainSpec(**GOOD).to_dict() == GOOD
    with pytest.raises(ValueError, match=r"ChainSpec.family = 'x' is invalid: valid values are \['din22252', "
                                         r"'studless', 'studlink'\] or None"):
        ChainSpec(**GOOD, family="x")
    with pytest.raises(ValueError, match=r"ChainSpec.grade = 4 is invalid: must be a grade name such as 'C' or "
                                         r"'R4', not int"):
        ChainSpec(**GOOD, grade=4)
    r = ChainSpec(**GOOD).replace(n=40)
    assert r.n == 40 and r.length_mm == 2000.0
    with pytest.raises(ValueError, match="ChainSpec.n = 0"):
        ChainSpec(**GOOD).replace(n=0)


@pytest.mark.parametrize("width,pitch", [(40.0, 35.0), (30.0, float("30"))])
def test_pitch_must_exceed_a_width_above_two_d(width, pitch):
    """d = 14 mm with an inner width above 2 d = 28 mm: the pitch must exceed the width (the straight part
    L = (pitch − width)/2 > 0), even when it is above 2 d: width 40, pitch 35 and width 30, pitch 30 (a separate
    float object) are refused with "max(2 d, width) = W < pitch".  Bug caught: ``p > w`` → ``p is not w``."""
    with pytest.raises(ValueError) as info:
        ChainSpec(**(GOOD | dict(width=width, pitch=pitch)))
    assert f"ChainSpec.pitch = {pitch!r} is invalid: valid range is max(2 d, width) = {width:g} < pitch" \
        in str(info.value)


def test_pitch_message_is_strict_when_the_width_sets_the_lower_bound():
    """d = 14: with width 28 = 2 d the lower bound is the width, and pitch > width is strict, so the message
    says '28 < pitch'; with width 20 the bound is 2 d = 28 and inclusive ('28 <= pitch').  Bug caught: the
    choice ``lo == w`` → ``lo is w`` (max(2 d, w) returns 2 d's object on a tie)."""
    from chainid.chain.spec import ChainSpec

    with pytest.raises(ValueError, match=r"ChainSpec.pitch = 28.0 is invalid: valid range is max\(2 d, width\) = "
                                         r"28 < pitch <= 20 d = 280 mm"):
        ChainSpec(d=14.0, pitch=28.0, width=28.0, n=16)
    with pytest.raises(ValueError, match=r"ChainSpec.pitch = 27.0 is invalid: valid range is max\(2 d, width\) = "
                                         r"28 <= pitch <= 20 d = 280 mm"):
        ChainSpec(d=14.0, pitch=27.0, width=20.0, n=16)


@pytest.mark.parametrize(
    "field,value",
    [("d", 0.0), ("d", -1.0), ("width", 0.0), ("width", -3.0), ("pitch", 17.0), ("pitch", 10.0), ("n", 0),
     ("n", 2.5), ("nu", 0.0), ("nu", 0.5), ("nu", -0.1), ("E", 0.0), ("mass_per_m", -1.0), ("d", float("nan"))],
)
def test_bad_values_name_the_field(field, value):
    with pytest.raises(ValueError, match=rf"ChainSpec\.{field} = "):
        ChainSpec(**(GOOD | {field: value}))


def test_builtin_chain_geometry():
    c = default_chain()
    assert (c.R, c.L, c.length_mm, c.mass_kg) == (15.5, 16.5, 800.0, pytest.approx(3.2))


def test_toml_round_trip(tmp_path):
    p = tmp_path / "c.toml"
    p.write_text("d = 26\npitch = 92\nwidth = 30\nn = 10\nE = 200000\nnu = 0.29\nmass_per_m = 13.7\n")
    c = load_chain(p)
    assert c == ChainSpec(d=26, pitch=92, width=30, n=10, E=200000, nu=0.29, mass_per_m=13.7)
    assert load_chain(None) == default_chain()


def test_toml_errors(tmp_path):
    p = tmp_path / "c.toml"
    p.write_text("d = 26\npitch = 92\nwidth = 30\nn = 10\nmass_per_m = 1\ncolour = 'red'\n")
    with pytest.raises(ValueError, match="unknown key"):
        load_chain(p)
    p.write_text("d = 26\npitch = 92\n")
    with pytest.raises(ValueError, match="missing key"):
        load_chain(p)
    with pytest.raises(ValueError, match="does not exist"):
        load_chain(tmp_path / "nope.toml")


@pytest.mark.parametrize("changes,field,shown", [
    (dict(d=100.0), "width", "17.0"),            # d > width: the next link's bar cannot pass
    (dict(width=14.0), "width", "14.0"),         # width = d: no clearance either
    (dict(width=1e-9), "width", "1e-09"),        # width -> 0
    (dict(pitch=25.0, width=17.0), "pitch", "25.0"),  # pitch > width but < 2 d = 28: two bars do not fit
    (dict(pitch=17.0), "pitch", "17.0"),         # pitch = width: no straight part
    (dict(pitch=281.0), "pitch", "281.0"),       # > 20 d: a rod, not a link
    (dict(width=141.0, pitch=200.0), "width", "141.0"),  # > 10 d
    (dict(d=0.4, width=0.5, pitch=1.0), "d", "0.4"),
    (dict(d=501.0, width=600.0, pitch=2100.0), "d", "501.0"),
    (dict(E=1e300), "E", "1e+300"),
    (dict(E=210.0), "E", "210.0"),               # GPa entered as MPa
    (dict(E=2.1e11), "E", "210000000000.0"),     # Pa entered as MPa
    (dict(n=1e20), "n", "1e+20"),
    (dict(n=1_000_001), "n", "1000001"),
    (dict(n=0), "n", "0"),
    (dict(mass_per_m=4000.0), "mass_per_m", "4000.0"),  # g/m entered as kg/m
    (dict(nu=0.5), "nu", "0.5"),
])
def test_impossible_geometry_is_refused_naming_field_value_and_range(changes, field, shown):
    with pytest.raises(ValueError) as info:
        ChainSpec(**(GOOD | changes))
    msg = str(info.value)
    assert msg.startswith(f"ChainSpec.{field} = {shown} is invalid: valid range is "), msg


@pytest.mark.parametrize("field,value", [
    ("d", True), ("n", True), ("n", np.bool_(True)), ("E", False), ("d", "14"), ("n", "16"), ("width", None),
    ("nu", 0.3 + 0j), ("n", 16.5), ("n", float("inf")), ("d", float("nan")),
])
def test_odd_types_are_refused(field, value):
    with pytest.raises(ValueError, match=rf"^ChainSpec\.{field} = .* is invalid: must be"):
        ChainSpec(**(GOOD | {field: value}))


def test_numpy_scalars_are_accepted_as_plain_numbers():
    c = ChainSpec(**(GOOD | dict(n=np.int64(16), d=np.float32(14), width=np.int32(17), E=np.float64(2.1e5))))
    assert c == ChainSpec(**GOOD)
    assert type(c.n) is int and type(c.d) is float and type(c.width) is float
    assert ChainSpec(**(GOOD | dict(n=16.0))).n == 16  # TOML writes "n = 16.0" sometimes


# DIN 22252 round steel link chains for mining (d x pitch, inner width; mass approximate, kg/m)
DIN_22252 = [(14, 50, 17, 4.0), (18, 64, 21, 6.6), (22, 86, 26, 9.7), (26, 92, 30, 13.7), (30, 108, 34, 18.0),
             (34, 126, 38, 23.0), (38, 137, 42, 29.0), (42, 146, 46, 35.8)]


@pytest.mark.parametrize("d,pitch,width,mass", DIN_22252)
def test_din_22252_chains_pass(d, pitch, width, mass):
    c = ChainSpec(d=d, pitch=pitch, width=width, n=100, mass_per_m=mass)
    assert 0 < kernels.coefficients(c)[0]


@pytest.mark.parametrize("d", [20.0, 76.0, 120.0, 220.0])
def test_mooring_chains_pass(d):
    # studless: outer 6 d x 3.35 d -> inner length 4 d, inner width 1.35 d, about 0.0199 d² kg/m;
    # stud link: outer 6 d x 3.6 d -> inner 4 d x 1.6 d, about 0.0219 d² kg/m
    ChainSpec(d=d, pitch=4 * d, width=1.35 * d, n=1000, E=207000.0, mass_per_m=0.0199 * d * d)
    ChainSpec(d=d, pitch=4 * d, width=1.6 * d, n=1000, E=207000.0, mass_per_m=0.0219 * d * d)


def test_steel_mass_per_metre_by_hand():
    # 14x50, width 17: centre line 2*33 + pi*31 = 163.389 mm; bar area pi*49 = 153.938 mm²;
    # 25 152 mm³ * 7.85e-6 kg/mm³ = 0.19744 kg per link, 20 links per metre
    assert steel_mass_per_m(14, 50, 17) == pytest.approx(3.9488, rel=1e-4)
    assert steel_mass_per_m(14, 50, 17) == pytest.approx(4.0, rel=0.02)  # the paper's 4.0 kg/m


def test_toml_refuses_impossible_geometry_and_accepts_float_n(tmp_path):
    p = tmp_path / "c.toml"
    p.write_text("d = 100\npitch = 250\nwidth = 17\nn = 16\nmass_per_m = 4\n")
    with pytest.raises(ValueError, match=r"ChainSpec\.width = 17\.0 is invalid: valid range is d = 100\.0 < width"):
        load_chain(p)
    p.write_text('d = "14"\npitch = 50\nwidth = 17\nn = 16\nmass_per_m = 4\n')
    with pytest.raises(ValueError, match=r"ChainSpec\.d = '14' is invalid: must be a finite real number, not str"):
        load_chain(p)
    p.write_text("d = 14\npitch = 50\nwidth = 17\nn = 16.0\nmass_per_m = 4\n")
    assert load_chain(p) == ChainSpec(**GOOD)


def test_pitch_bounds_are_inclusive_and_stated_in_mm():
    """d = 14 mm, width 17 mm: pitch = 2 d = 28 mm (two bars exactly) and 20 d = 280 mm are valid (the documented
    range max(2 d, width) <= pitch <= 20 d is closed); the refusal states both bounds in mm, computed by hand
    (28 <= pitch <= 20 d = 280 mm).  Bugs caught: `p >= 2 d` made strict, the upper bound 20·d garbled (20 + d)."""
    assert ChainSpec(**(GOOD | dict(pitch=28.0))).pitch == 28.0
    assert ChainSpec(**(GOOD | dict(pitch=280.0))).pitch == 280.0
    for bad in (27.999, 280.001):
        with pytest.raises(ValueError) as info:
            ChainSpec(**(GOOD | dict(pitch=bad)))
        assert "max(2 d, width) = 28 <= pitch <= 20 d = 280 mm" in str(info.value)
    with pytest.raises(ValueError) as info:  # a width above 2 d is the lower bound, strictly (pitch = width)
        ChainSpec(**(GOOD | dict(width=30.0, pitch=30.0)))
    assert "max(2 d, width) = 30 < pitch <= 20 d = 280 mm" in str(info.value)
