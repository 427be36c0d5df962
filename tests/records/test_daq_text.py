"""DAQ text as written: a header block with metadata, ``skip_rows`` against the file's ``Header Size``, a header
marker, ragged rows (an ``Events`` field on event rows only), the time step from ``Sampling Interval``, the
bad-lines policy, and the ``header``/``names`` keys.  References: the numbers the test wrote (daq_files) and a
hand parse of the text here (split on the delimiter)."""
from __future__ import annotations

import sys

import numpy as np
import pytest

from chainid.records.reader import ReadLog, read_any
from chainid.records.spec import ReaderSpec, load_profile, spec_from_options
from daq_files import write_daq


def _spec(**kw):
    return spec_from_options(columns="x=CHANNEL1,F=CHANNEL0", **kw)


def test_header_size_counts_the_name_line_so_skip_rows_is_one_less(tmp_path):
    p = tmp_path / "ME.txt"
    ref = write_daq(p, [200])
    for wrong in (7, 0, 5):
        with pytest.raises(ValueError, match=rf"ME\.txt, line 1: the file says 'Header Size:  7', a block of 7 lines "
                                             rf"counting the column-name line, so the names are on line 7: "
                                             rf"--skip-rows counts the lines above the names and must be 6, not "
                                             rf"{wrong}"):
            read_any(p, _spec(skip_rows=wrong))
    (rec,) = read_any(p, _spec(skip_rows=6))
    np.testing.assert_array_equal(rec.x, ref[0]["disp"])  # the first data row is not lost
    np.testing.assert_array_equal(rec.F, ref[0]["force"])


def test_header_marker_finds_the_name_line(tmp_path):
    p = tmp_path / "ME.txt"
    ref = write_daq(p, [150])
    (rec,) = read_any(p, _spec(header_marker=r"^Sample Number"))
    np.testing.assert_array_equal(rec.x, ref[0]["disp"])
    with pytest.raises(ValueError, match=r"no line among the first 157 \(after 0 skipped\) matches --header-marker "
                                         r"'\^Time'"):
        read_any(p, _spec(header_marker=r"^Time"))


def test_sampling_interval_line_gives_the_time_axis_per_segment(tmp_path):
    p = tmp_path / "ME.txt"
    write_daq(p, [120, 80], interval=0.001)
    recs = read_any(p, _spec(skip_rows=6, split_events="DAQ Pause"))
    assert [r.t.size for r in recs] == [120, 80]
    for r in recs:  # t = (sample - first of the segment) x 0.001 s
        np.testing.assert_allclose(r.t, np.arange(r.t.size) * 0.001, rtol=0, atol=1e-15)
    with pytest.raises(ValueError, match=r"both a time column"):
        read_any(p, _spec(skip_rows=6, fs=1000.0).merged(columns={"t": "Sample Number", **_spec().columns}))


def _hand_parse(path):
    """The rows after the name line, split on ',' (4 or 5 fields)."""
    lines = path.read_text().splitlines()[7:]
    rows = [[f.strip() for f in ln.split(",")] for ln in lines if ln.strip()]
    return rows


def test_ragged_rows_on_the_fast_path_equal_the_line_scan_and_a_hand_parse(tmp_path, monkeypatch):
    p = tmp_path / "ME.txt"
    write_daq(p, [300, 250, 100], force_first=False)
    rows = _hand_parse(p)
    assert {len(r) for r in rows} == {4, 5}
    cuts = [i + 1 for i, r in enumerate(rows) if len(r) == 5 and r[4] == "DAQ Pause"]
    spec = spec_from_options(skip_rows=6, columns="x=CHANNEL0,F=CHANNEL1", split_events="DAQ Pause")
    from chainid.records.plan import plan_columns
    from chainid.records.textread import _fast, text_layout

    lay = text_layout(p, spec)
    assert (lay.n_fields, lay.n_common) == (5, 4)
    cols = _fast(p, lay, plan_columns(lay.names, spec, str(p), dt_meta=lay.dt).use(), ".")
    assert cols is not None, "the ragged file must stay on pyarrow's fast path"
    assert [i for i, e in enumerate(cols["Events"]) if "Pause" in e] == [c - 1 for c in cuts]
    fast = read_any(p, spec)
    monkeypatch.setitem(sys.modules, "pyarrow", None)  # the line-by-line scan
    monkeypatch.setitem(sys.modules, "pyarrow.csv", None)
    slow = read_any(p, spec)
    starts = [0] + cuts[:-1]
    assert [r.t.size for r in fast] == [b - a for a, b in zip(starts, cuts)] == [300, 250, 100]
    for a, b, s, e in zip(fast, slow, starts, cuts):
        np.testing.assert_array_equal(a.x, [float(r[2]) for r in rows[s:e]])
        np.testing.assert_array_equal(a.F, [float(r[3]) for r in rows[s:e]])
        np.testing.assert_array_equal(a.x, b.x)
        np.testing.assert_array_equal(a.F, b.F)


def test_a_row_with_missing_trailing_fields_has_them_empty(tmp_path):
    p = tmp_path / "notes.csv"
    body = [f"{0.01 * i!r},{1.0 + 0.1 * i!r},{100.0 + i!r}" + (",calibrated" if i % 50 == 0 else "")
            for i in range(200)]
    p.write_text("t,x,F,note\n" + "\n".join(body) + "\n")
    (rec,) = read_any(p, spec_from_options(units="t=s"))
    np.testing.assert_array_equal(rec.F, [100.0 + i for i in range(200)])


def test_a_data_row_taken_as_the_names_is_refused(tmp_path):
    p = tmp_path / "log.txt"
    p.write_text("Station 1\nOperator: A\nidx, disp, load, note\n" + "".join(f"{i}, {0.1 * i:.3f}, {i * 2.5:.3f}, ok\n"
                                                                             for i in range(30)))
    with pytest.raises(ValueError, match=r"log\.txt, line 4 was taken as the column names but looks like a data row "
                                         r"\(field\(s\) \[1, 2, 3\] are numbers, as on the next line\): is --skip-rows "
                                         r"one too many \(it is 3\)"):
        read_any(p, spec_from_options(skip_rows=3, columns="x=disp,F=load", fs=10.0))
    (rec,) = read_any(p, spec_from_options(skip_rows=2, columns="x=disp,F=load", fs=10.0))
    assert rec.t.size == 30 and rec.F[0] == 0.0 and rec.F[-1] == 72.5


def test_header_as_a_list_is_refused_and_names_name_a_headerless_file(tmp_path):
    with pytest.raises(ValueError, match=r"reader header = \['t', 'x', 'F'\] is a list; header is true or false .*"
                                         r"give the names as names = \[\.\.\.\]"):
        ReaderSpec(header=["t", "x", "F"])
    p = tmp_path / "h.tsv"
    p.write_text("".join(f"{0.01 * i}\t{1.0 + i}\t{50.0 - i}\n" for i in range(40)))
    prof = tmp_path / "r.toml"
    prof.write_text('names = ["time", "disp", "load"]\n[columns]\nt = "time"\nx = "disp"\nF = "load"\n')
    (rec,) = read_any(p, load_profile(prof))
    np.testing.assert_array_equal(rec.x, [1.0 + i for i in range(40)])  # row 1 is data, not names
    np.testing.assert_array_equal(rec.F, [50.0 - i for i in range(40)])


def _bad_file(tmp_path):
    p = tmp_path / "bad.csv"
    lines = [f"{0.01 * i!r},{1.0 + i!r},{200.0 - i!r}" for i in range(12)]
    lines[4] = "0.04,5.0,196,0"      # line 5: 4 fields (a decimal comma)
    lines[8] = "0.08,9.0,abc"        # line 9: not a number
    p.write_text("\n".join(lines) + "\n")
    return p


def test_bad_lines_error_names_the_line_warn_and_skip_count_them(tmp_path):
    p = _bad_file(tmp_path)
    spec = spec_from_options(columns="t=1,x=2,F=3")
    with pytest.raises(ValueError, match=r"bad\.csv, line 5: 4 fields but the first data row has 3"):
        read_any(p, spec)
    keep = [i for i in range(12) if i not in (4, 8)]
    for policy, where in (("warn", "warnings"), ("skip", "notes")):
        log = ReadLog()
        (rec,) = read_any(p, spec.merged(bad_lines=policy), log=log)
        np.testing.assert_array_equal(rec.x, [1.0 + i for i in keep])
        msgs = getattr(log, where)
        assert len(msgs) == 1 and f"2 bad line(s) left out (--bad-lines {policy}); the first: " in msgs[0]
        assert "line 5: 4 fields" in msgs[0]
        assert getattr(log, "notes" if where == "warnings" else "warnings") == []


def test_a_time_column_at_odds_with_the_stated_interval_is_a_warning(tmp_path):
    p = tmp_path / "ME.txt"
    write_daq(p, [200], interval=0.005)
    cols = "x=CHANNEL1,F=CHANNEL0,t=Sample Number"
    log = ReadLog()
    (rec,) = read_any(p, spec_from_options(skip_rows=6, columns=cols, scale="t=0.005"), log=log)
    assert log.warnings == [] and rec.t[1] - rec.t[0] == pytest.approx(0.005, rel=1e-12)
    read_any(p, spec_from_options(skip_rows=6, columns=cols, scale="t=0.001"), log=log)
    (msg,) = log.warnings
    assert msg.startswith(f"file {str(p)!r}: the time column's median step is 0.001 s but the file states a sampling "
                          "interval of 0.005 s (0.2x)")


def test_a_files_rule_with_a_bad_key_names_its_pattern(tmp_path):
    prof = tmp_path / "r.toml"
    prof.write_text('skip_rows = 6\n[[files]]\npattern = "*.txt"\nskiprows = 3\n')
    with pytest.raises(ValueError, match=r"\[\[files\]\] pattern = '\*\.txt': unknown key\(s\) \['skiprows'\]"):
        load_profile(prof)
    prof.write_text('[[files]]\nskip_rows = 3\n')
    with pytest.raises(ValueError, match=r"\[\[files\]\] table .* has no pattern"):
        load_profile(prof)
