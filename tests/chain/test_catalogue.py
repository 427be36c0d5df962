"""The chain catalogue (chainid.chain.catalogue): grades per family, preset names and their options, the hint for a
--chain value that is neither a file nor a preset."""
from __future__ import annotations

import re

import pytest

from chainid.chain import catalogue


#: DNV-OS-E302 / IACS W22 offshore grades and the one DIN 22252 mining grade (the catalogue's [grades] tables)
W22_GRADES = ["R3", "R3S", "R4", "R4S", "R5"]


DIN_GRADES = ["C"]


def _listed(msg: str) -> list[str]:
    return eval(re.search(r"valid grades are (\[.*\])", msg).group(1))  # noqa: S307 - our own message


@pytest.mark.parametrize("grade,family,valid", [
    ("R4", "din22252", DIN_GRADES), ("r3s", "din22252", DIN_GRADES),
    ("C", "studless", W22_GRADES), ("c", "studlink", W22_GRADES),
])
def test_a_grade_of_the_other_kind_of_chain_lists_the_family_grades(grade, family, valid):
    """A mooring grade on DIN chain (or grade C on mooring chain) is refused, and the message lists exactly the
    grades of that family (DIN 22252: C; W22: R3, R3S, R4, R4S, R5).  Bug caught: the family filter of the list
    (``==`` → ``>``: an empty list for DIN, the DIN grade for mooring chain)."""
    with pytest.raises(ValueError, match=rf"{grade!r} does not apply to {family} chain") as e:
        catalogue.canonical_grade(grade, family)
    assert _listed(str(e.value)) == valid


def test_canonical_grade_any_case_and_family_none():
    """Any case gives the upper-case key; family None accepts both kinds; an unknown grade lists all six."""
    assert catalogue.canonical_grade(" r4s ", "studlink") == "R4S"
    assert catalogue.canonical_grade("c", None) == "C" and catalogue.canonical_grade("r5") == "R5"
    with pytest.raises(ValueError, match="grade 'R6' is invalid") as e:
        catalogue.canonical_grade("R6", "studless")
    assert _listed(str(e.value)) == sorted(DIN_GRADES + W22_GRADES)


# --- own-seed (702) mutation survivors -------------------------------------------------------------------------
SPELLED = ("preset names are spelled din22252:DxPITCH, studless:D, studlink:D (d in mm; options :n=, :E=, :nu=, "
           ":grade=; `chainid chains` lists them)")


@pytest.mark.parametrize("text,guess", [
    ("studles:76", "studless:76"),  # a prefix of a family: the size is kept as given (no DIN size list)
    ("STUDLINK:120:grade=r4", "studlink:120:grade=r4"),
    ("studlees:76", "studless:76"),  # a typo: the closest family name (difflib, ratio >= 0.5)
    ("stuzzzzzzzzzzzz:76", "studless:76"),  # neither: the first family with the same three first letters
    ("din:26X92", "din22252:26x92"),  # DIN: the closest listed size
])
def test_suggest_preset_guesses_the_family_and_the_size(text, guess):
    """The hint for a --chain value that is neither a file nor a preset: the spelling rule, then 'did you mean'
    with the family found by prefix, else by closeness, else by its first three letters.  Bugs caught: the
    closeness rule asked for 0 matches (a ValueError), the three-letter rule joined by ``and``, a mooring
    family sent into the DIN size list (``fam == 'din22252'`` → ``>=``)."""
    assert catalogue.suggest_preset(text) == f"{SPELLED}; did you mean {guess!r}?"


@pytest.mark.parametrize("text,hint", [("xyz:1", SPELLED), ("mychain", SPELLED), ("chain.toml", "")])
def test_suggest_preset_without_a_guess(text, hint):
    """No family fits: only the spelling rule; a name ending in .toml is a missing file: no hint at all."""
    assert catalogue.suggest_preset(text) == hint


@pytest.mark.parametrize("name,message", [
    ("studless:76:n", r"^preset 'studless:76:n': option 'n' is invalid; use key=value with keys "
                      r"\['E', 'grade', 'n', 'nu'\]$"),
    ("studless:76:E=abc", r"^preset 'studless:76:E=abc': option E = 'abc' is not a number$"),
    ("studless:76:m=3", r"^preset 'studless:76:m=3': unknown option 'm'; valid options are \['E', 'grade', 'n', 'nu'\]$"),
    ("chain:76", r"^preset name 'chain:76' is invalid: use one of \['din22252:SIZE', 'studless:SIZE', "
                 r"'studlink:SIZE'\]"),
    ("studless:", r"^preset name 'studless:' is invalid"),
    ("studless:15.9", r"^preset 'studless:15.9': nominal diameter d = 15.9 mm is invalid: valid range is "
                      r"16 <= d <= 220 mm$"),
])
def test_preset_option_errors_name_the_option_and_the_valid_keys(name, message):
    """Each malformed preset name is one ValueError naming the name, the option or size and what is valid (the
    catalogue's keys n, E, nu, grade; studless d from 16 to 220 mm)."""
    with pytest.raises(ValueError, match=message):
        catalogue.dimensions(name)


def test_preset_options_any_case_integral_n_and_inclusive_diameters():
    """Option keys are case-insensitive (N=32, e=, NU=, Grade=); n = 32.0 is the integer 32 (E stays a float);
    the diameter bounds 16 and 220 mm are inclusive; the canonical name drops the options and writes 76.0 as 76."""
    e = catalogue.dimensions("StudLess:76.0:N=32.0:e=200000:NU=0.29:Grade=r4s")
    f = e["fields"]
    assert e["name"] == "studless:76" and e["grade"] == "R4S" and f["grade"] == "R4S"
    assert f["n"] == 32 and type(f["n"]) is int and f["E"] == 200000.0 and f["nu"] == 0.29
    assert catalogue.dimensions("studless:16")["fields"]["d"] == 16.0
    assert catalogue.dimensions("studless:220")["fields"]["d"] == 220.0
    assert catalogue.dimensions("studless:76", n=5)["fields"]["n"] == 5  # the argument wins over the default 16
    assert catalogue.dimensions("studless:76")["fields"]["n"] == 16


def test_preset_name_recognition_and_size_text():
    """``is_preset_name``: a family (any case) before a colon is a preset, anything else a file path;
    ``format_size`` writes sizes as the names do (76, 76.5)."""
    from chainid.chain.catalogue import format_size, is_preset_name

    assert is_preset_name("din22252:14x50") and is_preset_name("StudLess:76") and is_preset_name("studlink:76:n=3")
    assert not is_preset_name("studless") and not is_preset_name("chain.toml") and not is_preset_name("din:26x92")
    assert not is_preset_name("C:/chains/studless.toml")
    assert (format_size(76.0), format_size(76.5), format_size(120)) == ("76", "76.5", "120")
