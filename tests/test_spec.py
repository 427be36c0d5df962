"""ChainSpec validation and TOML files."""
from __future__ import annotations

import pytest

from chainid.chain.spec import ChainSpec, default_chain, load_chain

GOOD = dict(d=14.0, pitch=50.0, width=17.0, n=16, E=210000.0, nu=0.3, mass_per_m=4.0)


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
