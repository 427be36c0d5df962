"""Covariates of a test from the contract's sources: a pattern on the test id (group ``value`` or 1), a side file
``test,name,value``, a column reduced per test; conflicts between sources and ids the side file has but the data
do not.  References: the numbers written into the file names and side files here."""
from __future__ import annotations

import pytest

from chainid.records.covariates import apply_covariates, covariates_path, read_covariates, write_covariates
from chainid.records.reader import read_any
from chainid.records.record import Record
from chainid.records.spec import spec_from_options
from daq_files import write_seal


def _seals(tmp_path):
    for p in (1, 3, 5.5):
        write_seal(tmp_path / f"NAP310_{p}bar.csv", p_bar=float(p), n=120)
    return spec_from_options(columns="t=1,x=5,F=7", units="t=ms")


def test_covariate_from_the_test_id_group_one_or_value(tmp_path):
    spec = _seals(tmp_path)
    recs = read_any(str(tmp_path / "*.csv"), spec.merged(covariates={"p_bar": r"_([0-9.]+)bar$"}))
    assert {r.test: r.covariates for r in recs} == {"NAP310_1bar": {"p_bar": 1.0}, "NAP310_3bar": {"p_bar": 3.0},
                                                   "NAP310_5.5bar": {"p_bar": 5.5}}
    named = read_any(str(tmp_path / "*.csv"), spec.merged(covariates={"p": r"NAP(?P<seal>\d+)_(?P<value>[\d.]+)"}))
    assert [r.covariates["p"] for r in named] == [1.0, 3.0, 5.5]
    with pytest.raises(ValueError, match=r"--covariate q='_x\(\\d\+\)' does not match the test id 'NAP310_1bar'"):
        read_any(str(tmp_path / "*.csv"), spec.merged(covariates={"q": r"_x(\d+)"}))
    with pytest.raises(ValueError, match=r"--covariate s='\(NAP\)': test 'NAP310_1bar': 'NAP' is not a number"):
        read_any(str(tmp_path / "*.csv"), spec.merged(covariates={"s": r"(NAP)"}))


def test_side_file_values_conflicts_and_unknown_ids(tmp_path):
    spec = _seals(tmp_path)
    side = tmp_path / "cov.txt"
    side.write_text("test,name,value\nNAP310_1bar,T_C,21.5\nNAP310_3bar,T_C,22\nother,T_C,1\n")
    recs = read_any(str(tmp_path / "*.csv"), spec)
    warns = apply_covariates(recs, read_covariates(side), str(side))
    assert [r.covariates for r in recs] == [{"T_C": 21.5}, {"T_C": 22.0}, {}]
    assert warns == [f"file {str(side)!r}: covariates of 1 test id(s) that were not read: 'other'"]
    side.write_text("test,name,value\nA,T_C,1\nB,T_C,2\nA,T_C,3\n")
    with pytest.raises(ValueError, match=r"cov\.txt, line 4: test 'A', covariate 'T_C' appears twice \(line 2 too\)"):
        read_covariates(side)
    side.write_text("test,name,value\nA,T_C,1_0\n")
    with pytest.raises(ValueError, match=r"cov\.txt, line 2: test 'A': covariate 'T_C' value '1_0' is not a finite"):
        read_covariates(side)
    recs = read_any(str(tmp_path / "*.csv"), spec.merged(covariates={"p_bar": r"_([0-9.]+)bar$"}))
    with pytest.raises(ValueError, match=r"test 'NAP310_3bar': covariate 'p_bar' is 3 from the data and 4 in"):
        apply_covariates(recs, {"NAP310_3bar": {"p_bar": 4.0}}, "c.csv")


def test_covariates_side_file_round_trip_beside_the_records(tmp_path):
    recs = [Record("A", [0, 1, 2], [0, 1, 0], [1, 2, 1], covariates={"I_A": 0.25, "p": 1 / 3}),
            Record("B", [0, 1, 2], [0, 1, 0], [1, 2, 1], covariates={"I_A": 1.0})]
    out = covariates_path(tmp_path / "mr.csv")
    assert out.name == "mr.covariates.csv" and covariates_path("run.parquet").name == "run.covariates.csv"
    write_covariates(out, recs)
    assert out.read_text() == "test,name,value\nA,I_A,0.25\nA,p,0.3333333333333333\nB,I_A,1.0\n"
    assert read_covariates(out) == {"A": {"I_A": 0.25, "p": 1 / 3}, "B": {"I_A": 1.0}}  # exact floats


def test_a_reduced_column_and_an_id_pattern_for_one_name_is_refused():
    with pytest.raises(ValueError, match=r"reader covariates: 'p' is also a reduce covariate; give one source"):
        spec_from_options(reduce="p=mean(c6)", covariates=["p=_([0-9]+)bar"])
    with pytest.raises(ValueError, match=r"reader covariates p = 'bar' has no group"):
        spec_from_options(covariates=["p=bar"])
