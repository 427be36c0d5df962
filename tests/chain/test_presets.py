"""Presets of standard chains against their cited sources (chainid/data/chains.toml).

The expected values are typed here from the sources (not read from the data file):
DIN 22252 sizes as makers reproduce the standard's table (nominal inner width b1, max. outer width b2,
mass per metre); mooring chain from the OrcaFlex line-type wizard (outer width 3.35 d studless,
3.6 d stud link; mass 19.9 d² / 21.9 d² te/m with d in m) and the 4 d inner length (zzjms.net)."""
from __future__ import annotations

import math

import pytest

from chainid.chain import presets
from chainid.chain.spec import PAPER_CHAIN, ChainSpec, load_chain


# size: (d, pitch, inner width, max outer width, kg/m)
DIN22252 = {
    "14x50": (14, 50, 17, 48, 4.0),
    "18x64": (18, 64, 21, 60, 6.6),
    "22x86": (22, 86, 26, 73, 9.5),
    "26x92": (26, 92, 30, 86, 13.7),
    "30x108": (30, 108, 34, 97, 18.0),
    "34x126": (34, 126, 38, 109, 23.0),  # jingyuan: outer width 109 mm, 22.7 kg/m
    "38x137": (38, 137, 42, 123, 29.0),
    "42x146": (42, 146, 46, 134, 35.6),
}


@pytest.mark.parametrize("size", sorted(DIN22252))
def test_din22252_dimensions_against_source(size):
    d, pitch, width, outer, mass = DIN22252[size]
    p = presets.resolve(f"din22252:{size}")
    assert (p.chain.d, p.chain.pitch, p.chain.width, p.outer_width, p.chain.mass_per_m) == (d, pitch, width, outer, mass)
    assert p.chain.n == 16 and p.grade == "C"
    # outer width = inner width + 2 d up to the tolerance of b2 max over b1 min (a few mm)
    assert 0 <= outer - (width + 2 * d) <= 6


@pytest.mark.parametrize("size", sorted(DIN22252))
def test_din22252_mass_matches_link_geometry(size):
    """Mass of a steel link (7850 kg/m³) with centre line 2(pitch - width) + π(width + d): within 3 % of the table."""
    d, pitch, width, _, mass = DIN22252[size]
    centre_line = 2 * (pitch - width) + math.pi * (width + d)  # mm
    kg_per_link = 7850e-9 * math.pi * d * d / 4 * centre_line
    assert kg_per_link * 1000 / pitch == pytest.approx(mass, rel=0.03)


def test_mooring_proportions_at_two_diameters():
    # studless 76 mm: pitch 4 d = 304, outer 3.35 d = 254.6, inner width 254.6 - 152 = 102.6, 19.9 d² te/m = 114.9424 kg/m
    p = presets.resolve("studless:76")
    assert (p.chain.pitch, p.outer_width, p.chain.width) == pytest.approx((304.0, 254.6, 102.6))
    assert p.chain.mass_per_m == pytest.approx(114.9424)
    assert p.grade == "R3" and not p.studlink
    # stud link 120 mm: pitch 480, outer 3.6 d = 432, inner width 192, 21.9 d² te/m = 315.36 kg/m
    q = presets.resolve("studlink:120")
    assert (q.chain.pitch, q.outer_width, q.chain.width) == pytest.approx((480.0, 432.0, 192.0))
    assert q.chain.mass_per_m == pytest.approx(315.36)
    assert q.studlink


def test_studless_mass_formula_close_to_geometry():
    """0.0199 d² kg/m against a 4 d x 1.35 d link of steel: within 3 % (the catalogue link is fuller)."""
    d = 100.0
    centre_line = 2 * (4 * d - 1.35 * d) + math.pi * (1.35 * d + d)
    geo = 7850e-9 * math.pi * d * d / 4 * centre_line * 1000 / (4 * d)
    assert presets.chain("studless:100").mass_per_m == pytest.approx(geo, rel=0.03)


def test_paper_chain_is_the_din_14x50_preset_and_default_unchanged():
    assert load_chain("din22252:14x50") == PAPER_CHAIN
    assert ChainSpec.preset("din22252:14x50") == PAPER_CHAIN
    assert load_chain(None) == PAPER_CHAIN


def test_n_and_options_override():
    assert ChainSpec.preset("din22252:26x92", n=8).n == 8
    c = load_chain("studless:76:n=4:E=200000:grade=R4")
    assert (c.n, c.E) == (4, 200000.0)
    assert presets.resolve("studless:76:grade=R4").grade == "R4"


@pytest.mark.parametrize("name, words", [
    ("din22252:25x92", ["25x92", "14x50"]),
    ("studless:10", ["d = 10 mm", "16 <= d <= 220"]),
    ("studless:abc", ["abc"]),
    ("din22252:14x50:m=3", ["unknown option 'm'"]),
    ("din22252:14x50:grade=R4", ["does not apply"]),
    ("studlink:76:grade=X", ["grade 'X'"]),
    ("din22252:14x50:n=0", ["n"]),
])
def test_bad_names_are_value_errors(name, words):
    with pytest.raises(ValueError) as ei:
        load_chain(name)
    for w in words:
        assert w in str(ei.value)


def test_missing_file_is_still_a_file_error():
    with pytest.raises(ValueError, match="does not exist"):
        load_chain("no/such/file.toml")


def test_match_finds_preset_by_dimensions():
    assert presets.match(PAPER_CHAIN.replace(n=40)).name == "din22252:14x50"
    assert presets.match(presets.chain("studlink:84")).family == "studlink"
    assert presets.match(PAPER_CHAIN.replace(width=18)) is None


def test_listed_covers_families():
    names = [p.name for p in presets.listed()]
    assert names[:8] == [f"din22252:{s}" for s in DIN22252]
    assert "studless:76" in names and "studlink:76" in names


def test_cli_chains_json(capsys):
    import json

    from chainid.cli import main

    assert main(["chains", "--family", "din22252", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert [p["name"] for p in doc["presets"]] == [f"din22252:{s}" for s in DIN22252]
    assert doc["presets"][0]["width_mm"] == 17.0


def test_preset_in_a_chain_toml(tmp_path):
    f = tmp_path / "c.toml"
    f.write_text('[chain]\npreset = "din22252:26x92"\nn = 8\n', encoding="utf-8")
    c = load_chain(f)
    assert (c.d, c.pitch, c.width, c.n, c.mass_per_m) == (26.0, 92.0, 30.0, 8, 13.7)
    f.write_text('preset = "din22252:99x1"\n', encoding="utf-8")
    with pytest.raises(ValueError, match="99x1"):
        load_chain(f)


def test_match_finds_a_mooring_preset_by_dimensions_only_inside_its_range():
    """``match``: a chain with a studless chain's pitch (4 d) and inner width (3.35 d − 2 d) at d = 76 mm is
    studless:76 (its n kept); the same proportions at d = 230 mm, beyond the catalogue's 220 mm, match nothing."""
    from chainid.chain import presets

    c = ChainSpec(d=76.0, pitch=4 * 76.0, width=(3.35 - 2.0) * 76.0, n=9)
    p = presets.match(c)
    assert p is not None and p.name == "studless:76" and p.chain.n == 9 and p.grade == "R3" and not p.studlink
    assert presets.match(ChainSpec(d=230.0, pitch=4 * 230.0, width=(3.35 - 2.0) * 230.0, n=9)) is None
