"""Input conventions: impossible chain geometry is refused, real chains pass, and the kernel API takes
numbers the way numpy does and refuses odd types the way SciPy does (issue 13, item 5)."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import chainid
from chainid import cli
from chainid.model import kernels
from chainid.model.base import ChainModel
from chainid.chain.spec import ChainSpec, load_chain, steel_mass_per_m

GOOD = dict(d=14.0, pitch=50.0, width=17.0, n=16, E=210000.0, nu=0.3, mass_per_m=4.0)


# -- ChainSpec: impossible geometry and odd types ---------------------------------------------------

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


# -- kernel API: numpy's conventions for numbers, SciPy's for errors --------------------------------

@pytest.mark.parametrize("bad,what", [
    (True, "bool"), (np.bool_(False), "bool"), (np.array([True, False]), "bool"), (None, "NoneType"),
    ("1.0", "str"), (b"1", "bytes"), (np.datetime64("2026-11-23"), "datetime64"),
    (np.timedelta64(3, "s"), "timedelta64"), (1 + 2j, "complex"), ([1.0, None], "object"), (["1", "2"], "str"),
])
@pytest.mark.parametrize("func", [chainid.force, chainid.stiffness, chainid.displacement])
def test_odd_types_raise_type_error(func, bad, what):
    with pytest.raises(TypeError, match=rf"must be a real number or an array of real numbers \[(mm|N)\], not {what}"):
        func(bad)


def test_scalars_lists_and_integer_arrays():
    ref = chainid.force(np.array([1.0, 2.0]))
    assert type(chainid.force(1)) is float and type(chainid.force(np.float32(1.0))) is float
    assert type(chainid.force(np.array(1.0))) is float  # 0-d in, float out
    assert chainid.force(np.int64(1)) == chainid.force(1.0) == ref[0]
    np.testing.assert_array_equal(chainid.force(np.array([1, 2], dtype=np.int32)), ref)
    np.testing.assert_array_equal(chainid.force(np.array([1, 2], dtype=np.uint8)), ref)
    np.testing.assert_array_equal(chainid.force([1, 2]), ref)
    assert chainid.force([[1, 2], [1, 2]]).shape == (2, 2)
    assert chainid.force(np.array([1.0, 2.0], dtype=np.float32)).dtype == np.float64


def test_infinity_and_nan():
    assert chainid.force(math.inf) == math.inf
    assert chainid.displacement(math.inf) == math.inf
    assert chainid.force(-math.inf) == 0.0 and chainid.stiffness(-math.inf) == 0.0
    # k_e -> 1/c_lin for F -> inf, and c_lin = lim x/F: from the closed form x(F) of Eq. 15 at F = 1e30 N
    # (the Hertz term adds c_hertz F^(-1/3) ~ 4e-9 relative)
    assert chainid.stiffness(math.inf) == pytest.approx(1e30 / chainid.displacement(1e30), rel=1e-8)
    assert chainid.stiffness(1e80) == chainid.stiffness(math.inf)
    out = chainid.force(np.array([1.0, np.nan, np.inf]))
    assert np.isfinite(out[0]) and np.isnan(out[1]) and out[2] == np.inf
    assert math.isnan(chainid.stiffness(math.nan)) and math.isnan(chainid.displacement(math.nan))
    with pytest.raises(ValueError, match=r"F = -1\.0 N is invalid: a chain carries no compression"):
        chainid.displacement([3.0, -1.0])


def test_masked_arrays_keep_their_mask():
    x = np.ma.array([1.0, -5.0, 2.0, np.nan], mask=[False, True, False, True])
    out = chainid.force(x)
    assert isinstance(out, np.ma.MaskedArray)
    np.testing.assert_array_equal(np.ma.getmaskarray(out), [False, True, False, True])
    assert out[0] == chainid.force(1.0) and out[2] == chainid.force(2.0)
    F = np.ma.array([100.0, -1.0], mask=[False, True])  # the masked negative force is not an error
    assert chainid.displacement(F)[0] == chainid.displacement(100.0) and chainid.displacement(F).mask[1]
    with pytest.raises(ValueError, match="no compression"):
        chainid.displacement(np.ma.array([100.0, -1.0], mask=[True, False]))
    assert chainid.stiffness(np.ma.masked) is np.ma.masked
    assert type(chainid.force(np.ma.array(2.0, mask=False))) is float


def test_chain_argument_accepts_spec_none_and_toml_path(tmp_path):
    p = tmp_path / "c26.toml"
    p.write_text("d = 26\npitch = 92\nwidth = 30\nn = 10\nmass_per_m = 13.7\n")
    spec = ChainSpec(d=26, pitch=92, width=30, n=10, mass_per_m=13.7)
    want = chainid.force(1.5, chain=spec)
    assert chainid.force(1.5, chain=str(p)) == want and chainid.force(1.5, chain=p) == want
    assert chainid.stiffness(1.5, chain=p) == chainid.stiffness(1.5, chain=spec)
    assert chainid.force(1.5, chain=None) == chainid.force(1.5)
    assert ChainModel(chain=p).chain == spec
    for bad in (3, {"d": 26}, 2.5):
        with pytest.raises(TypeError, match=rf"chain must be a ChainSpec, None or a path .* not {type(bad).__name__}"):
            chainid.force(1.5, chain=bad)
    with pytest.raises(TypeError, match="not int"):
        ChainModel(chain=3)
    with pytest.raises(ValueError, match="does not exist"):
        chainid.force(1.5, chain=tmp_path / "missing.toml")


@settings(max_examples=60, deadline=None)
@given(st.floats(-6, 300), st.floats(-6, 300))
def test_round_trip_and_monotonic_across_the_asymptote(a, b):
    x1, x2 = sorted((10.0**a, 10.0**b))  # 1e-6 to 1e300 mm, across kernels.X_LINEAR = 1e60 mm (the iteration
    # of the kernels alone gives NaN from about 1e200 mm)
    F1, F2 = chainid.force(np.array([x1, x2]))
    assert F1 <= F2
    assert chainid.displacement(F1) == pytest.approx(x1, rel=1e-12)
    k1, k2 = chainid.stiffness(np.array([x1, x2]))
    assert 0 < k1 <= k2 * (1 + 1e-12)  # a hardening spring


@settings(max_examples=40, deadline=None)
@given(st.integers(-1000, 10**6))
def test_integers_give_the_float_result(i):
    assert chainid.force(i) == chainid.force(float(i))
    assert chainid.stiffness(np.int64(i)) == chainid.stiffness(float(i))


# -- the command line: the same inputs, one line on stderr, rc 2 ------------------------------------

@pytest.mark.parametrize("toml,needle", [
    ("d = 100\npitch = 250\nwidth = 17\nn = 16\nmass_per_m = 4\n", "ChainSpec.width = 17.0"),
    ("d = 14\npitch = 50\nwidth = 17\nn = 1e20\nmass_per_m = 4\n", "ChainSpec.n = 1e+20"),
    ("d = 14\npitch = 50\nwidth = 17\nn = true\nmass_per_m = 4\n", "ChainSpec.n = True"),
    ("d = 14\npitch = 50\nwidth = 17\nn = 16\nE = 1e300\nmass_per_m = 4\n", "ChainSpec.E = 1e+300"),
])
def test_cli_stiffness_refuses_bad_chain_files(tmp_path, capsys, toml, needle):
    p = tmp_path / "c.toml"
    p.write_text(toml)
    assert cli.main(["stiffness", "--x", "1", "--chain", str(p)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("chainid stiffness: error: " + needle), err


def test_cli_stiffness_inf_and_negative_force(capsys):
    assert cli.main(["stiffness", "--F", "-1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "F = -1.0 N is invalid" in err
    assert cli.main(["stiffness", "--F", "inf"]) == 0
    row = capsys.readouterr().out.strip().splitlines()[-1].split()
    assert row[:2] == ["inf", "inf"] and float(row[2]) == pytest.approx(chainid.stiffness(math.inf), rel=1e-5)


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
