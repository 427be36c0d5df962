"""The grade is part of a chain's identity: spec, preset names, TOML, JSON, warnings, `chainid chains`.

Reference numbers are hand computations from the IACS W22 / DNV-OS-E302 formula F = c·d²(44 − 0.08 d) kN
(d in mm; coefficients in chainid/data/chains.toml, cited there) and the catalogue values: 76 mm R4 stud-link
proof force 4.73 MN, 120 mm R4 studless MBL 13.57 MN."""
from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from chainid.chain import presets
from chainid.chain.spec import PAPER_CHAIN, ChainSpec, load_chain
from chainid.cli import main
from chainid.model.practice import chain_practice, load_warnings, practice_section

# Hand computations (kN -> N), coefficients from the pilotfits table / IACS W22:
R4_STUDLINK_76_PROOF_N = 0.0216 * 76 ** 2 * (44 - 0.08 * 76) * 1e3      # 4 731 131 N  (issue: 4.73 MN)
R3_STUDLINK_76_PROOF_N = 0.0156 * 76 ** 2 * (44 - 0.08 * 76) * 1e3      # 3 416 928 N  (the old, wrong 3.417e6)
R4_STUDLESS_120_MBL_N = 0.0274 * 120 ** 2 * (44 - 0.08 * 120) * 1e3     # 13 572 864 N (issue: 13.57 MN)


def test_hand_numbers_are_the_issues():
    assert R4_STUDLINK_76_PROOF_N == pytest.approx(4.73e6, rel=1e-3)
    assert R4_STUDLESS_120_MBL_N == pytest.approx(13.57e6, rel=1e-3)


def test_studlink_r4_warnings_use_r4_proof_force():
    c = load_chain("studlink:76:grade=R4")
    assert (c.family, c.grade) == ("studlink", "R4")
    p = chain_practice(c)
    assert p["proof_load_N"] == pytest.approx(R4_STUDLINK_76_PROOF_N, rel=1e-12)
    w = load_warnings(4e6, c)  # above the R3 proof force (3.417 MN), below the R4 one (4.73 MN)
    assert not any("exceeds the proof force" in m for m in w)
    assert all("grade R4" in m for m in w) and w
    w5 = load_warnings(4.8e6, c)
    assert any(f"the proof force {R4_STUDLINK_76_PROOF_N:.4g} N" in m for m in w5)


def test_cli_stiffness_warns_with_the_grade_of_the_name(capsys):
    assert main(["stiffness", "--chain", "studlink:76:grade=R4", "--F", "4e6"]) == 0
    err = capsys.readouterr().err
    assert "grade R3" not in err and "grade R4" in err and "3.417e+06" not in err


def test_audit_reports_r4_mbl(tmp_path):
    out = tmp_path / "a.json"
    assert main(["audit", "--chain", "studless:120:grade=R4", "--json", str(out)]) == 0
    ch = json.loads(out.read_text())["practice"]["chain"]
    assert ch["grade"] == "R4"
    assert ch["breaking_load_N"] == pytest.approx(R4_STUDLESS_120_MBL_N, rel=1e-12)


def test_r5_uses_r5_yield_and_loads():
    p = chain_practice(ChainSpec.preset("studless:76:grade=R5"))
    assert p["grade"] == "R5" and p["yield_MPa"] == 760.0
    assert p["breaking_load_N"] == pytest.approx(0.0320 * 76 ** 2 * (44 - 6.08) * 1e3, rel=1e-12)
    assert p["proof_load_N"] == pytest.approx(0.0223 * 76 ** 2 * (44 - 6.08) * 1e3, rel=1e-12)


def test_practice_of_preset_spec_keeps_grade():
    assert chain_practice(ChainSpec.preset("studless:76:grade=R4"))["grade"] == "R4"
    assert practice_section(ChainSpec.preset("studless:76:grade=r4s"))["chain"]["grade"] == "R4S"


def test_toml_preset_with_override_stays_mooring(tmp_path):
    f = tmp_path / "c.toml"
    f.write_text('preset = "studless:76:grade=R4"\nwidth = 100\n')
    c = load_chain(f)
    assert (c.family, c.grade, c.width) == ("studless", "R4", 100.0)
    p = chain_practice(c)
    assert p["grade"] == "R4" and p["yield_MPa"] == 580.0 and p["family"] == "studless"
    assert p["breaking_load_N"] == pytest.approx(0.0274 * 76 ** 2 * (44 - 6.08) * 1e3, rel=1e-12)


def test_toml_grade_key(tmp_path):
    f = tmp_path / "c.toml"
    f.write_text("d = 76\npitch = 304\nwidth = 102.6\nn = 16\nmass_per_m = 115\nfamily = 'Studless'\ngrade = 'r4s'\n")
    c = load_chain(f)
    assert (c.family, c.grade) == ("studless", "R4S")
    assert chain_practice(c)["yield_MPa"] == 700.0
    f.write_text("d = 76\npitch = 304\nwidth = 102.6\nn = 16\nmass_per_m = 115\nfamily = 'studless'\ngrade = 'C'\n")
    with pytest.raises(ValueError, match=r"grade = 'C' does not apply to studless"):
        load_chain(f)


def test_old_toml_without_grade_still_valid(tmp_path):
    f = tmp_path / "c.toml"
    f.write_text("d = 14\npitch = 50\nwidth = 17\nn = 16\nmass_per_m = 4.0\n")
    c = load_chain(f)
    assert c.grade is None and c.family is None
    assert "grade" not in c.to_dict() and "family" not in c.to_dict()
    assert chain_practice(c)["grade"] == "C"  # by the matching DIN 22252 preset, as before


def test_grade_field_validation():
    with pytest.raises(ValueError, match=r"ChainSpec.grade = 'X'.*valid grades"):
        PAPER_CHAIN.replace(grade="X")
    with pytest.raises(ValueError, match=r"ChainSpec.family = 'din'"):
        PAPER_CHAIN.replace(family="din")
    assert PAPER_CHAIN.replace(family="STUDLESS", grade=None).grade == "R3"  # family default
    assert PAPER_CHAIN.replace(width=18).grade == "C"  # an override keeps the grade


@pytest.mark.parametrize("alias,canon", [
    ("din22252:26X92", "din22252:26x92"), ("DIN22252:26x92", "din22252:26x92"),
    ("studless:76:grade=r4", "studless:76:grade=R4"), ("Studless:76:GRADE=R4:N=4", "studless:76:grade=R4:n=4"),
])
def test_spellings_alike(alias, canon):
    assert load_chain(alias) == load_chain(canon)


def test_unknown_file_suggests_preset():
    with pytest.raises(ValueError) as e:
        load_chain("din:26x92")
    msg = str(e.value)
    assert "does not exist" in msg and "din22252:26x92" in msg and "studless:D" in msg


def test_cli_unknown_chain_exit_2(capsys):
    assert main(["stiffness", "--chain", "din:26x92", "--F", "1000"]) == 2
    err = capsys.readouterr().err
    assert "din22252:26x92" in err and "Traceback" not in err and len(err.strip().splitlines()) == 1


def test_chains_any_diameter_shows_loads(capsys):
    assert main(["chains", "studless:120", "--grade", "R4", "--json"]) == 0
    (r,) = json.loads(capsys.readouterr().out)["presets"]
    assert (r["name"], r["grade"], r["d_mm"]) == ("studless:120", "R4", 120.0)
    assert r["breaking_load_N"] == pytest.approx(R4_STUDLESS_120_MBL_N, rel=1e-12)
    assert r["proof_load_N"] == pytest.approx(0.0192 * 120 ** 2 * (44 - 9.6) * 1e3, rel=1e-12)


def test_chains_grade_lists_other_grade(capsys):
    assert main(["chains", "--grade", "r4", "--family", "studlink", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    r76 = next(r for r in doc["presets"] if r["name"] == "studlink:76")
    assert r76["grade"] == "R4" and r76["proof_load_N"] == pytest.approx(R4_STUDLINK_76_PROOF_N, rel=1e-12)
    assert main(["chains", "--grade", "R9"]) == 2


@pytest.mark.parametrize("fam", ["studless", "studlink"])
def test_diameter_bounds_inclusive(fam, capsys):
    db = presets.data()[fam]
    lo, hi = db["d_min"], db["d_max"]
    assert (lo, hi) == (16.0, 220.0)
    assert presets.resolve(f"{fam}:{lo:g}").chain.d == 16.0
    assert presets.resolve(f"{fam}:{hi:g}").chain.d == 220.0
    for bad in (15.99, 220.01):
        with pytest.raises(ValueError, match="valid range is 16 <= d <= 220 mm"):
            presets.resolve(f"{fam}:{bad}")
    assert main(["chains", f"{fam}:220"]) == 0
    assert main(["chains", f"{fam}:220.01"]) == 2


def test_labels():
    text = (Path(presets.__file__).resolve().parents[1] / "data" / "chains.toml").read_text(encoding="utf-8")
    assert "c·d²(44 − 0.08 d) kN" in text and "c·d²(44 − 0.08 d) N " not in text
    din = chain_practice(PAPER_CHAIN)
    assert "no catalogue EA exists for DIN 22252" in din["EA_catalogue_label"]
    assert "reference" in din["EA_catalogue_label"]
    moor = chain_practice(ChainSpec.preset("studless:76"))
    assert "no catalogue EA" not in moor["EA_catalogue_label"]


def test_model_file_round_trip_keeps_grade(tmp_path):
    from chainid.model.augmented import AugmentedModel, Damping
    from chainid.model.base import ChainModel
    from chainid.model.modelfile import load_model, save_model

    m = AugmentedModel(ChainModel(ChainSpec.preset("studless:76:grade=R4")), [], Damping("viscous", {"c": 1.0}),
                       0.0, 3.2)
    for name in ("m.toml", "m.json"):
        save_model(m, tmp_path / name)
        c = load_model(tmp_path / name).base.chain
        assert (c.family, c.grade) == ("studless", "R4")


@pytest.mark.parametrize("fam", ["studless", "studlink"])
@pytest.mark.parametrize("d", [16.0, 220.0])
def test_match_finds_mooring_chain_at_the_diameter_bounds(fam, d):
    """A chain given by dimensions at d_min or d_max is matched to its family (inclusive bounds, as in resolve)."""
    spec = ChainSpec.preset(f"{fam}:{d:g}").replace(family=None, grade=None)
    p = presets.match(spec)
    assert p is not None and p.family == fam and p.chain.d == d


def test_stiffness_json_carries_the_grade(capsys):
    assert main(["stiffness", "--chain", "studlink:76:grade=r4", "--F", "1000", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["chain"]["grade"] == "R4" and doc["chain"]["family"] == "studlink"


def test_bar_diameter_bounds_inclusive():
    """0.5 <= d <= 500 mm (ChainSpec docstring): both ends accepted, just outside refused with the range."""
    assert ChainSpec(d=0.5, pitch=1.5, width=0.6, n=1).d == 0.5
    assert ChainSpec(d=500.0, pitch=2000.0, width=600.0, n=1).d == 500.0
    for d in (0.4999, 500.01):
        with pytest.raises(ValueError, match=r"ChainSpec.d = .* valid range is 0.5 <= d <= 500.0 mm"):
            ChainSpec(d=d, pitch=4 * d, width=1.2 * d, n=1)


def test_stated_mooring_grade_on_din_dimensions_is_used(tmp_path):
    """Dimensions of DIN 22252 14x50 with grade = 'R4' and no family: the stated grade wins (R4 loads by the W22
    formula: MBL 0.0274·14²·(44 − 1.12) kN = 230.3 kN), not an error and not grade C."""
    f = tmp_path / "c.toml"
    f.write_text("d = 14\npitch = 50\nwidth = 17\nn = 16\nmass_per_m = 4.0\ngrade = 'R4'\n")
    p = chain_practice(load_chain(f))
    assert p["grade"] == "R4" and p["family"] is None
    assert p["breaking_load_N"] == pytest.approx(0.0274 * 14 ** 2 * (44 - 1.12) * 1e3, rel=1e-12)
