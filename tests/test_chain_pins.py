"""Pins of chainid.chain (issue 20 §5, mutation triage): the documented contracts of the catalogue and the presets
that no other test states by number.  Each test names the single-point bug it catches."""
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
