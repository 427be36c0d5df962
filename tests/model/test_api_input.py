"""The public kernel API (chainid.force, displacement, stiffness) takes numbers the way numpy does and refuses odd
types the way SciPy does: scalars, lists, integer and masked arrays, inf and NaN, a chain given as a spec, None
or a TOML path.  Units mm, N."""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import chainid
from chainid.chain.spec import ChainSpec
from chainid.model.base import ChainModel


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
