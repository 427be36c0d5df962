"""``--tests IDS|GLOB`` (ids or fnmatch globs, file order kept, an item matching nothing is an error listing the
valid ids) and the duplicate-id error's advice, which fits where the ids came from: ``--id-pattern`` only for ids
taken from file names, ``--tests`` or unique ids for a test column, ``--segment-id`` for split files."""
from __future__ import annotations

import numpy as np
import pytest

from chainid.records.reader import read_any
from chainid.records.record import Record
from chainid.records.select import parse_tests, select_ids
from chainid.records.spec import spec_from_options
from chainid.records.writer import write_canonical
from daq_files import write_daq


def _rec(test: str, k: float = 1.0) -> Record:
    t = np.arange(64) * 0.01
    return Record(test, t, 1.0 + 0.1 * np.sin(t * k), 100.0 + t)


def test_ids_and_globs_keep_the_file_order_and_unmatched_items_are_named():
    ids = ["ME2mm5Hz_i0", "ME2mm5Hz_i1", "ME10mm2Hz_i0", "T1"]
    assert select_ids(ids, parse_tests(" T1, ME2mm*_i1 ,")) == ["ME2mm5Hz_i1", "T1"]
    assert select_ids(ids, ["*_i0"]) == ["ME2mm5Hz_i0", "ME10mm2Hz_i0"]
    with pytest.raises(ValueError, match=r"^--tests: 'T9', 'X\*' match\(es\) no test; valid ids: ME2mm5Hz_i0, "
                                         r"ME2mm5Hz_i1, ME10mm2Hz_i0, T1$"):
        select_ids(ids, ["T9", "T1", "X*"])
    with pytest.raises(ValueError, match=r"--tests ',': give test ids or globs"):
        parse_tests(",")


def test_reading_keeps_only_the_selected_tests(tmp_path):
    p = write_canonical(tmp_path / "r.csv", [_rec("A"), _rec("B"), _rec("C")])
    assert [r.test for r in read_any(p, None, tests=["C", "A"])] == ["A", "C"]
    assert [r.test for r in read_any(p, spec_from_options(units="x=mm"), tests=["[BC]"])] == ["B", "C"]
    with pytest.raises(ValueError, match=r"valid ids: A, B, C"):
        read_any(p, None, tests=["D"])


def test_duplicate_ids_from_file_names_suggest_id_pattern(tmp_path):
    for d in ("a", "b"):
        (tmp_path / d).mkdir()
        write_canonical(tmp_path / d / "run.csv", [_rec("x")])
    spec = spec_from_options(columns="x=x,F=F,t=t")  # no test column mapped: ids from the file names
    with pytest.raises(ValueError, match=r"test id 'x' appears in .* and .*; the files' test columns repeat"):
        read_any([tmp_path / "a" / "run.csv", tmp_path / "b" / "run.csv"], spec)  # the files have test columns
    for d in ("a", "b"):
        (tmp_path / d / "run.csv").write_text("t,x,F\n" + "".join(f"{0.01 * i},{1 + i},{2 + i}\n" for i in range(9)))
    with pytest.raises(ValueError, match=r"test id 'run' appears in .*; give --id-pattern to take distinct ids from "
                                         r"the file names$"):
        read_any([tmp_path / "a" / "run.csv", tmp_path / "b" / "run.csv"], spec)


def test_duplicate_ids_from_a_test_column_suggest_tests_not_id_pattern(tmp_path):
    a = write_canonical(tmp_path / "a.csv", [_rec("A"), _rec("B")])
    b = write_canonical(tmp_path / "b.csv", [_rec("A", 2.0), _rec("C")])
    spec = spec_from_options(units="t=s")
    with pytest.raises(ValueError) as exc:
        read_any([a, b], spec)
    msg = str(exc.value)
    assert "test id 'A' appears in" in msg and "--tests IDS" in msg and "make the ids unique" in msg
    assert "--id-pattern" not in msg
    assert [r.test for r in read_any([a, b], spec, tests=["B", "C"])] == ["B", "C"]  # the advice works


def test_duplicate_segment_ids_suggest_a_template_with_the_stem(tmp_path):
    d1, d2 = tmp_path / "d1", tmp_path / "d2"
    d1.mkdir()
    d2.mkdir()
    write_daq(d1 / "ME.txt", [50, 50])
    write_daq(d2 / "ME.txt", [50, 50])
    spec = spec_from_options(skip_rows=6, columns="x=CHANNEL1,F=CHANNEL0", split_events="DAQ Pause",
                             segment_ids="lo,hi", segment_id="I{label}")
    with pytest.raises(ValueError, match=r"test id 'Ilo' appears in .*; give --segment-id with \{stem\}"):
        read_any([d1 / "ME.txt", d2 / "ME.txt"], spec)
