"""More pins of chainid.chain to the documented contract (issue 20 §5: ChainSpec's closed ranges, derived
geometry and defaults, found by reading the module for the typical mutation survivor).  Units: mm, MPa, kg."""
from __future__ import annotations

import math

import pytest

from chainid.chain.spec import ChainSpec, steel_mass_per_m

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


def test_preset_name_recognition_and_size_text():
    """``is_preset_name``: a family (any case) before a colon is a preset, anything else a file path;
    ``format_size`` writes sizes as the names do (76, 76.5)."""
    from chainid.chain.catalogue import format_size, is_preset_name

    assert is_preset_name("din22252:14x50") and is_preset_name("StudLess:76") and is_preset_name("studlink:76:n=3")
    assert not is_preset_name("studless") and not is_preset_name("chain.toml") and not is_preset_name("din:26x92")
    assert not is_preset_name("C:/chains/studless.toml")
    assert (format_size(76.0), format_size(76.5), format_size(120)) == ("76", "76.5", "120")


def test_match_finds_a_mooring_preset_by_dimensions_only_inside_its_range():
    """``match``: a chain with a studless chain's pitch (4 d) and inner width (3.35 d − 2 d) at d = 76 mm is
    studless:76 (its n kept); the same proportions at d = 230 mm, beyond the catalogue's 220 mm, match nothing."""
    from chainid.chain import presets

    c = ChainSpec(d=76.0, pitch=4 * 76.0, width=(3.35 - 2.0) * 76.0, n=9)
    p = presets.match(c)
    assert p is not None and p.name == "studless:76" and p.chain.n == 9 and p.grade == "R3" and not p.studlink
    assert presets.match(ChainSpec(d=230.0, pitch=4 * 230.0, width=(3.35 - 2.0) * 230.0, n=9)) is None
