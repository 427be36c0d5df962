"""``chainid chains``: --compare labels, grades of another family named."""
from __future__ import annotations

from chainid.cli import main


def test_cli_chains_compare_labels_only_din_rows(capsys):
    """--compare: the DIN 22252 rows say their catalogue EA is the studless formula used as a reference; the
    mooring rows do not.  Bug caught: the label on the wrong rows."""
    assert main(["chains", "--compare"]) == 0
    out = capsys.readouterr().out
    comp = out[out.index("EA model N"):]
    din = [ln for ln in comp.splitlines() if ln.startswith("din22252:")]
    moor = [ln for ln in comp.splitlines() if ln.startswith(("studless:", "studlink:"))]
    assert din and moor
    assert all("(EA cat.: studless formula as reference)" in ln for ln in din)
    assert not any("studless formula as reference" in ln for ln in moor)


def test_chains_grade_of_another_kind_names_the_first_family_given(capsys):
    """``chains --grade C --family studless studlink``: C (a DIN 22252 grade) fits neither; the error names the
    first family given and its grades (R3 … R5), in one line.  Bug caught: the last family named instead."""
    assert main(["chains", "--grade", "C", "--family", "studless", "studlink"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["chainid chains: error: --grade 'C' does not apply to studless chain: valid grades are "
                   "['R3', 'R3S', 'R4', 'R4S', 'R5']"]
