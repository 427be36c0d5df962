"""Records as rigs write them (chainid.records: readers, reader profiles, text and container tables): every format
and layout read into the same records, and every malformed file refused in one line.

Every fixture is built here from two reference tests in s, mm, N (tmp_path), written in the rig's layout and
units; the expected values are the reference arrays (unit factors are exact definitions: 1 in = 25.4 mm,
1 kip = 4448.2216152605 N, 1 ms = 1e-3 s), compared with rtol 1e-12."""
from __future__ import annotations

import json
import math
import os
import re
import sys

import numpy as np
import pytest

from chainid.records import ReaderSpec, read_any, read_records, write_records
from chainid.records.record import Record
from chainid.records.spec import spec_from_options


FS = 10240.0


KIP_N = 4448.2216152605  # 1 kip = 1000 lbf = 1000 x 0.45359237 kg x 9.80665 m/s^2


IN_MM = 25.4


def _ref(test: str, f: float, A: float, n: int = 4096) -> Record:
    t = np.arange(n) / FS
    x = 2.0 + A * np.sin(2 * math.pi * f * t)
    F = 11000.0 + 7000.0 * (x - 2.0) + 50.0 * np.cos(2 * math.pi * f * t)
    return Record(test, t, x, F)


REF = [_ref("A", 5.0, 0.3), _ref("B", 7.5, 0.2)]


def _same(recs: list[Record], ref: list[Record] = REF, t_exact: bool = False) -> None:
    assert [r.test for r in recs] == [r.test for r in ref]
    for r, e in zip(recs, ref):
        np.testing.assert_allclose(r.t, e.t, rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(r.x, e.x, rtol=1e-12)
        np.testing.assert_allclose(r.F, e.F, rtol=1e-12)


def _cli(argv: list[str], capsys) -> tuple[int, str, str]:
    from chainid.cli import main

    rc = main(argv)
    out, err = capsys.readouterr()
    return rc, out, err


def test_canonical_csv_fast_and_strict_paths_agree(tmp_path, monkeypatch):
    p = write_records(tmp_path / "r.csv", REF)
    fast = read_records(p, validate=False)
    _same(fast)
    monkeypatch.setitem(sys.modules, "pyarrow", None)  # no pyarrow: the row-by-row reader
    monkeypatch.setitem(sys.modules, "pyarrow.csv", None)
    _same(read_records(p, validate=False))
    q = write_records(tmp_path / "kernel.csv", REF)  # the numba kernel's text, read by the row-by-row reader
    _same(read_records(q, validate=False))
    import chainid.infra.floattext as floattext

    monkeypatch.setattr(floattext, "jit_enabled", lambda: False)  # no kernel, no pyarrow: the %.17g writer
    q = write_records(tmp_path / "plain.csv", REF)
    _same(read_records(q, validate=False))


def test_json_inches_kips_one_file_per_test(tmp_path, capsys):
    d = tmp_path / "brfd"
    d.mkdir()
    for r in REF:
        (d / f"{r.test}.json").write_text(json.dumps(
            {"time": r.t.tolist(), "disp": (r.x / IN_MM).tolist(), "force": (r.F / KIP_N).tolist()}))
    spec = spec_from_options(columns="t=time,x=disp,F=force", units="x=in,F=kip")
    _same(read_any(d, spec))
    # a list of tests in one file, ids inside
    (tmp_path / "all.json").write_text(json.dumps(
        [{"id": r.test, "time": r.t.tolist(), "disp": (r.x / IN_MM).tolist(), "force": (r.F / KIP_N).tolist()}
         for r in REF]))
    _same(read_any(tmp_path / "all.json", spec_from_options(columns="test=id,t=time,x=disp,F=force",
                                                            units="x=in,F=kip")))


def test_headerless_tsv_with_fs(tmp_path, capsys):
    for r in REF:
        np.savetxt(tmp_path / f"iso_{r.test}.txt", np.column_stack([r.F, r.x]), delimiter="\t", fmt="%.17g")
    spec = spec_from_options(columns="F=1,x=2", fs=FS)
    _same(read_any(str(tmp_path / "iso_*.txt"), spec.merged(id_pattern=r"iso_(\w+)\.txt")))
    # whitespace-separated (runs of spaces): numpy's fast path
    for r in REF:
        np.savetxt(tmp_path / f"ws_{r.test}.dat", np.column_stack([r.F, r.x]), delimiter="   ", fmt="%.17g")
    _same(read_any(str(tmp_path / "ws_*.dat"), spec.merged(id_pattern=r"ws_(?P<id>\w+)")))


def _mts(path, r: Record, sep: str = ";") -> None:
    """An MTS-style export: a header block, own column names, time in ms, decimal comma, compression positive."""
    lines = ["MTS TestSuite export", "Station: Frame 1", f"Specimen: {r.test}", "Rate: 10240 Hz", "",
             sep.join(["Time (ms)", "Axial Displacement", "Axial Force", "Count"])]
    for ti, xi, Fi in zip(r.t * 1000.0, -r.x, r.F):
        lines.append(sep.join([repr(float(ti)).replace(".", ","), repr(float(xi)).replace(".", ","),
                               repr(float(Fi)).replace(".", ","), "1"]))
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def test_mts_header_block_decimal_comma_sign(tmp_path, monkeypatch):
    for r in REF:
        _mts(tmp_path / f"{r.test}.csv", r)
    spec = spec_from_options(columns="t=Time (ms),x=Axial Displacement,F=Axial Force", units="t=ms",
                             scale="x=-1", delimiter=";", decimal=",", skip_rows=5)
    _same(read_any(tmp_path, spec))
    monkeypatch.setitem(sys.modules, "pyarrow", None)  # the line-by-line scan gives the same
    monkeypatch.setitem(sys.modules, "pyarrow.csv", None)
    _same(read_any(tmp_path, spec))


def test_whitespace_ms_nonuniform(tmp_path):
    rng = np.random.default_rng(1)
    t = np.cumsum(rng.uniform(0.5, 1.5, 3000)) / 2000.0
    ref = [Record("seal", t, 1.0 + 0.1 * np.sin(2 * math.pi * 3 * t), 500.0 + 40 * np.sin(2 * math.pi * 3 * t))]
    rows = [f"  {a * 1000:.17g}    {b:.17g}  {c:.17g}" for a, b, c in zip(ref[0].t, ref[0].x, ref[0].F)]
    (tmp_path / "seal.txt").write_text("# pneumatic seal rig\ntime_ms disp_mm force_N\n" + "\n".join(rows) + "\n")
    spec = spec_from_options(columns="t=time_ms,x=disp_mm,F=force_N", units="t=ms", skip_rows=1,
                             delimiter="whitespace")
    _same(read_any(tmp_path / "seal.txt", spec), ref)


def test_parquet_hdf5_mat_tdms(tmp_path):
    import h5py
    import scipy.io
    from nptdms import ChannelObject, GroupObject, TdmsWriter

    write_records(tmp_path / "long.parquet", REF)
    _same(read_any(tmp_path / "long.parquet", ReaderSpec()))
    with h5py.File(tmp_path / "rig.h5", "w") as f:
        for r in REF:
            g = f.create_group(r.test)
            g["time"], g["disp_m"], g["load_kN"] = r.t, r.x / 1000.0, r.F / 1000.0
    spec = spec_from_options(columns="t=time,x=disp_m,F=load_kN", units="x=m,F=kN")
    _same(read_any(tmp_path / "rig.h5", spec))
    for r in REF:
        scipy.io.savemat(tmp_path / f"{r.test}.mat", {"time": r.t, "disp": r.x, "force": r.F})
    _same(read_any(str(tmp_path / "*.mat"), spec_from_options(columns="t=time,x=disp,F=force")))
    with TdmsWriter(tmp_path / "daq.tdms") as w:
        for r in REF:
            w.write_segment([GroupObject(r.test), ChannelObject(r.test, "Time", r.t),
                             ChannelObject(r.test, "Disp", r.x * 1000.0), ChannelObject(r.test, "Load", r.F)])
    _same(read_any(tmp_path / "daq.tdms", spec_from_options(columns="t=Time,x=Disp,F=Load", units="x=um")))


def test_reader_profile_and_override(tmp_path):
    for r in REF:
        _mts(tmp_path / f"run_{r.test}.csv", r)
    prof = tmp_path / "mts.toml"
    prof.write_text('skip_rows = 5\ndelimiter = ";"\ndecimal = ","\nid_pattern = "run_(\\\\w+)"\n'
                    '[columns]\nt = "Time (ms)"\nx = "Axial Displacement"\nF = "Axial Force"\n'
                    '[units]\nt = "ms"\n[scale]\nx = -1\n')
    _same(read_any(str(tmp_path / "run_*.csv"), spec_from_options(prof)))
    flipped = read_any(str(tmp_path / "run_*.csv"), spec_from_options(prof, scale="x=1"))
    np.testing.assert_allclose(flipped[0].x, -REF[0].x, rtol=1e-12)


def test_convert_cli_glob_id_pattern(tmp_path, capsys):
    for r in REF:
        np.savetxt(tmp_path / f"spec{r.test}_run.tsv", np.column_stack([r.F, r.x]), delimiter="\t", fmt="%.17g")
    out = tmp_path / "out.csv"
    rc, o, e = _cli(["convert", str(tmp_path / "spec*_run.tsv"), "--to", str(out), "--columns", "F=1,x=2",
                     "--fs", str(FS), "--id-pattern", r"spec(\w)_"], capsys)
    assert rc == 0, e
    _same(read_records(out, validate=False))
    rc, o, e = _cli(["convert", str(tmp_path / "spec*_run.tsv"), "--to", str(out), "--columns", "F=1,x=2",
                     "--fs", str(FS)], capsys)
    assert rc == 2 and "exists" in e and e.count("\n") == 1


def test_wrong_dimension_unit_refused(tmp_path, capsys):
    p = write_records(tmp_path / "r.csv", REF)
    with pytest.raises(ValueError, match=r"--units x=kN: 'kN' is a unit of .*mass.*column x needs a length unit"):
        read_any(p, spec_from_options(units="x=kN"))
    rc, o, e = _cli(["convert", str(p), "--to", str(tmp_path / "o.csv"), "--units", "F=mm"], capsys)
    assert rc == 2 and "column F needs a force unit" in e and e.count("\n") == 1
    with pytest.raises(ValueError, match="unknown unit"):
        read_any(p, spec_from_options(units="t=fortnights_x"))


def test_missing_optional_reader_names_the_extra(tmp_path, monkeypatch, capsys):
    import h5py

    with h5py.File(tmp_path / "a.h5", "w") as f:
        f["x"], f["F"], f["t"] = REF[0].x, REF[0].F, REF[0].t
    monkeypatch.setitem(sys.modules, "h5py", None)
    with pytest.raises(ValueError, match=r'needs the Python package .h5py.*pip install "chainid\[formats\]"'):
        read_any(tmp_path / "a.h5", ReaderSpec())
    rc, o, e = _cli(["convert", str(tmp_path / "a.h5"), "--to", str(tmp_path / "o.csv")], capsys)
    assert rc == 2 and 'pip install "chainid[formats]"' in e and e.count("\n") == 1


def test_underscore_number_is_an_error(tmp_path):
    """issue 20 §3: Python's float() reads '1_3000' as 13000; a records cell must not."""
    p = tmp_path / "u.csv"
    p.write_text("test,t,x,F\nA,0,1.0,12000\nA,0.001,1.1,1_3000\n")
    with pytest.raises(ValueError, match=r"u\.csv, line 3: test 'A': column 'F' value '1_3000' is not a number"):
        read_records(p, validate=False)
    q = tmp_path / "u.tsv"
    q.write_text("1.0\t12000\n1.1\t1_3000\n")
    with pytest.raises(ValueError, match=r"u\.tsv, line 2: column '2' value '1_3000' is not a number"):
        read_any(q, spec_from_options(columns="x=1,F=2", fs=100.0))


def test_duplicate_column_is_an_error(tmp_path):
    """issue 20 §3: a second 'x' column was used silently."""
    p = tmp_path / "d.csv"
    p.write_text("test,t,x,F,x\nA,0,1.0,12000,9.0\nA,0.001,1.1,13000,9.1\n")
    with pytest.raises(ValueError, match=r"d\.csv: column\(s\) \['x'\] appear more than once"):
        read_records(p, validate=False)
    with pytest.raises(ValueError, match=r"appear more than once in the header"):
        read_any(p, spec_from_options(units="x=mm", delimiter=","))


def test_directory_and_fifo_say_what_they_are(tmp_path):
    """issue 20 §3: a directory or FIFO was reported as 'does not exist'."""
    empty = tmp_path / "empty"
    empty.mkdir()
    with pytest.raises(ValueError, match="is a directory with no record file"):
        read_records(empty, validate=False)
    d = tmp_path / "tests"
    d.mkdir()
    for r in REF:
        write_records(d / f"{r.test}.csv", [r])
    _same(read_records(d, validate=False))  # a directory of one file per test is input now
    if hasattr(os, "mkfifo"):
        fifo = tmp_path / "pipe.csv"
        os.mkfifo(fifo)
        with pytest.raises(ValueError, match=r"is a FIFO \(named pipe\), not a file"):
            read_records(fifo, validate=False)
    with pytest.raises(ValueError, match="does not exist"):
        read_records(tmp_path / "nope.csv", validate=False)


def _chain_record(scale_x: float = 1.0) -> Record:
    """A plausible test on the built-in 14x50 chain: F0 = 11117 N, A = 0.3 mm at 2 Hz, F = F_k(x)."""
    from chainid.model import kernels

    t = np.arange(20480) / FS
    x = 1.906 + 0.3 * np.sin(2 * math.pi * 2.0 * t)
    return Record("T1", t, x * scale_x, np.asarray(kernels.force(x, None, "paper"), dtype=float))


def test_plausible_chain_record_gives_no_warning():
    from chainid.chain.spec import default_chain
    from chainid.records.plausible import plausibility_warnings

    assert plausibility_warnings([_chain_record()], default_chain()) == []


def test_metres_file_warned_never_rescaled(tmp_path, capsys):
    from chainid.chain.spec import default_chain
    from chainid.records.plausible import plausibility_warnings

    rec = _chain_record(1e-3)  # x written in metres, read as mm
    msgs = plausibility_warnings([rec], default_chain())
    assert any("x in m read as mm (--units x=m)" in m for m in msgs), msgs
    p = write_records(tmp_path / "m.csv", [rec])
    out = tmp_path / "o.csv"
    rc, o, e = _cli(["convert", str(p), "--to", str(out), "--chain", "din22252:14x50"], capsys)
    assert rc == 0 and "warning:" in e and "--units x=m" in e
    np.testing.assert_array_equal(read_records(out, validate=False)[0].x, rec.x)  # never rescaled
    rc, o, e = _cli(["convert", str(p), "--to", str(tmp_path / "o2.csv"), "--chain", "din22252:14x50",
                     "--strict"], capsys)
    assert rc == 2 and "--strict" in e and not (tmp_path / "o2.csv").exists()
    rc, o, e = _cli(["convert", str(p), "--to", str(tmp_path / "o3.csv"), "--chain", "din22252:14x50",
                     "--units", "x=m"], capsys)
    assert rc == 0 and "warning" not in e


def test_time_unit_slips_warned():
    from chainid.records.plausible import sampling_warnings

    r = _chain_record()
    assert sampling_warnings([r]) == []
    assert any("--units t=ms" in m for m in sampling_warnings([Record("ms", r.t * 1000, r.x, r.F)]))
    assert any("above 1e+06 Hz" in m for m in sampling_warnings([Record("us", r.t * 1e-3, r.x, r.F)]))


def test_progress_only_on_a_terminal(monkeypatch, capsys):
    from chainid.infra.progress import progress_enabled, progress_iter

    assert list(progress_iter(range(3), "reading")) == [0, 1, 2]
    assert capsys.readouterr().err == ""  # captured stderr is not a TTY: quiet
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True, raising=False)
    assert progress_enabled() and not progress_enabled(quiet=True)
    assert list(progress_iter(range(3), "reading", total=3)) == [0, 1, 2]
    assert "reading" in capsys.readouterr().err


def test_mapping_errors_name_the_column(tmp_path):
    p = tmp_path / "h.tsv"
    p.write_text("1.0\t2.0\n1.1\t2.1\n")
    with pytest.raises(ValueError, match=r"no header: give positions, e.g. --columns F=1,x=2"):
        read_any(p, spec_from_options(fs=100.0))
    with pytest.raises(ValueError, match=r"no time column 't'.*--fs HZ"):
        read_any(p, spec_from_options(columns="x=1,F=2"))
    with pytest.raises(ValueError, match=r"--columns F=3: the file has 2 column\(s\)"):
        read_any(p, spec_from_options(columns="x=1,F=3", fs=100.0))
    q = write_records(tmp_path / "r.csv", REF)
    with pytest.raises(ValueError, match=r"--columns x=Disp: no displacement column named 'Disp'.*\['test', 't', 'x', 'F'\]"):
        read_any(q, spec_from_options(columns="x=Disp"))
    with pytest.raises(ValueError, match=r"both a time column .* and --fs"):
        read_any(q, spec_from_options(fs=100.0))
    with pytest.raises(ValueError, match=r"appears in"):
        read_any([q, tmp_path / "r.csv"], spec_from_options(units="t=s"))
    with pytest.raises(ValueError, match=r"--scale 'x=minus': x = 'minus' is not a number"):
        spec_from_options(scale="x=minus")
    with pytest.raises(ValueError, match=r"reader decimal = ',' needs another delimiter"):
        spec_from_options(decimal=",", delimiter=",")


def test_mat_v73_through_h5py(tmp_path):
    """A MATLAB v7.3 file is HDF5 with (1, N) vectors; scipy refuses it, h5py reads it."""
    import h5py

    p = tmp_path / "A.mat"
    with h5py.File(p, "w", userblock_size=512) as f:
        f["time"], f["disp"], f["force"] = REF[0].t[None, :], REF[0].x[None, :], REF[0].F[None, :]
    with open(p, "r+b") as fh:  # the MATLAB 7.3 header in the user block
        fh.write(b"MATLAB 7.3 MAT-file, Platform: GLNXA64, Created on: Mon Jan  1 00:00:00 2024 HDF5 schema 1.00 .")
        fh.seek(124)
        fh.write(b"\x00\x02IM")
    _same(read_any(p, spec_from_options(columns="t=time,x=disp,F=force")), REF[:1])


def test_ragged_whitespace_row_is_an_error(tmp_path):
    p = tmp_path / "w.dat"
    p.write_text("1.0  2.0  3.0\n1.1  2.1  3.1  9.9\n1.2  2.2  3.2\n")
    with pytest.raises(ValueError, match=r"w\.dat, line 2: 4 fields but the first data row has 3"):
        read_any(p, spec_from_options(columns="x=1,F=2", fs=100.0))


def test_records_are_writable_arrays(tmp_path):
    p = write_records(tmp_path / "r.csv", REF)
    q = write_records(tmp_path / "r.parquet", REF)
    for recs in (read_records(p, validate=False), read_any(q, ReaderSpec())):
        for r in recs:
            assert r.t.flags.writeable and r.x.flags.writeable and r.F.flags.writeable


def test_duplicate_column_is_named_with_its_positions(tmp_path):
    p = tmp_path / "d.csv"
    p.write_text("test,t,x,F,x\n1,0,1,2,3\n1,0.1,1,2,3\n")
    with pytest.raises(ValueError, match=r"column\(s\) \['x'\] appear more than once .*at positions \[3, 5\]"):
        read_records(p)


@pytest.mark.parametrize("kw, words", [
    (dict(fs=0.0), "reader fs = 0.0 Hz is invalid; valid range fs > 0 Hz"),
    (dict(fs=float("inf")), "reader fs = inf Hz is invalid"),
    (dict(skip_rows=-1), "reader skip_rows = -1 is invalid; valid: an integer >= 0"),
    (dict(skip_rows=True), "reader skip_rows = True is invalid"),
    (dict(decimal=",", delimiter=","), "reader decimal = ',' needs another delimiter than ','"),
    (dict(decimal=":", delimiter=";"), "reader decimal = ':' is invalid; valid: '.' or ','"),
    (dict(delimiter=":"), "reader delimiter = ':' is invalid"),
    (dict(scale={"x": 0.0}), "reader scale: x = 0.0 is invalid; valid: a finite non-zero factor"),
    (dict(scale={"test": -1.0}), "reader scale: unknown role(s) ['test']"),
    (dict(columns={"x": 0}), "reader columns: x = 0 is invalid; give a column name or a 1-based position >= 1"),
    (dict(columns={"x": True}), "reader columns: x = True is invalid"),
    (dict(columns={"y": "Y"}), "reader columns: unknown role(s) ['y']"),
    (dict(units={"x": " "}), "reader units: x = ' ' is invalid"),
    (dict(id_pattern="("), "reader id_pattern = '(' is not a regular expression"),
    (dict(format="xls"), "reader format = 'xls' is invalid"),
])
def test_reader_spec_refuses_with_the_field_and_the_valid_range(kw, words):
    from chainid.records.spec import ReaderSpec

    with pytest.raises(ValueError, match=re.escape(words)):
        ReaderSpec(**kw)


def test_reader_spec_accepts_its_bounds_and_normalises():
    from chainid.records.spec import ReaderSpec, parse_assignments

    s = ReaderSpec(fs=1e-9, skip_rows=0, decimal=",", delimiter=";", scale={"x": "-1"}, columns={"F": 1, "x": "D"})
    assert s.fs == 1e-9 and s.scale == {"x": -1.0} and s.columns == {"F": 1, "x": "D"}
    assert ReaderSpec(delimiter="tab").delimiter == "\t" and ReaderSpec().is_default
    assert not s.is_default and s.merged(fs=None, skip_rows=3).skip_rows == 3 and s.merged(fs=None).fs == 1e-9
    assert parse_assignments("t=Time, x = 2 ,F=Load", "--columns") == {"t": "Time", "x": 2, "F": "Load"}
    assert parse_assignments("x=-1,F=1e3", "--scale", numeric=True) == {"x": -1.0, "F": 1000.0}
    assert parse_assignments(None, "--units") == {}
    for text, words in (("t", "item 't' is not ROLE=VALUE"), ("t=a,t=b", "role 't' is given twice"),
                        ("x=", "item 'x=' is not ROLE=VALUE")):
        with pytest.raises(ValueError, match=re.escape(f"--columns {text!r}: {words}")):
            parse_assignments(text, "--columns")
    with pytest.raises(ValueError, match=re.escape("--scale 'x=a': x = 'a' is not a number")):
        parse_assignments("x=a", "--scale", numeric=True)


def test_a_file_that_is_not_utf8_text_is_one_error(tmp_path):
    p = tmp_path / "latin.csv"
    p.write_bytes(b"test,t,x,F\n1,0,1,2\n\xff\xfe,1,1,1\n")
    with pytest.raises(ValueError, match=r"latin.csv.*not a UTF-8 text"):
        read_records(p)
    q = tmp_path / "latin.txt"
    q.write_bytes(b"\xe9t\xe9;x;F\n0;1;2\n")
    from chainid.records.spec import ReaderSpec

    with pytest.raises(ValueError, match=r"latin.txt: not a UTF-8 text file \(undecodable byte at file offset 0 near "
                                         r"line 1\)"):
        read_records(q, spec=ReaderSpec(columns={"t": 1, "x": 2, "F": 3}, delimiter=";"))


@pytest.mark.parametrize("delim", [" ", ",", ";"])
def test_a_regular_text_file_is_read_by_the_fast_path_as_by_the_scan(tmp_path, delim):
    """A regular delimited file (whitespace: numpy's loadtxt; else pyarrow) is read by the fast path, which
    gives the same numbers as the line-by-line scan (the other method; both correctly rounded).  Bug caught:
    the fast path made to fail on every file (``loadtxt(..., ndmin=3)`` raises; the scan hid it)."""
    from reader_paths import fast_and_scan

    from chainid.records.spec import ReaderSpec

    p = tmp_path / "r.txt"
    rows = [(0.01 * i, 1.0 + 0.1 * i, -3.5e2 + i / 3) for i in range(50)]
    sep = "  " if delim == " " else delim
    p.write_text(sep.join(["t", "x", "F"]) + "\n" + "".join(sep.join(repr(v) for v in r) + "\n" for r in rows))
    _, fast, slow = fast_and_scan(p, ReaderSpec())
    assert fast is not None
    for k, j in (("t", 0), ("x", 1), ("F", 2)):
        assert fast[k].tolist() == slow[k].tolist() == [r[j] for r in rows]


def test_ragged_row_message_shows_one_field_more_than_the_header(tmp_path):
    """A row with more fields than the header: the message shows the row's first nf + 1 fields (enough to see
    the extra one): a header of 4 fields and a row of 7 (decimal commas) show 'a,0.1,2,5,0'.  Bug caught: ``row[:nf + 1]`` → ``row[:nf // 1]``."""
    from chainid.records.textcanon import read_csv_strict

    p = tmp_path / "r.csv"
    p.write_text("test,t,x,F\na,0,1,2\na,0.1,2,5,0,7,8\n")
    with pytest.raises(ValueError, match=r"line 3: 7 fields but the header has 4 \(test,t,x,F\); .* "
                                         r"\(row starts 'a,0.1,2,5,0'\)"):
        read_csv_strict(p)


def _table(**cols):
    from chainid.records.table import RawTable

    return RawTable("src.csv", {k: np.asarray(v) for k, v in cols.items()}, None, False, None)


def test_table_rows_of_a_test_must_be_contiguous_and_named():
    """Rows 1–2 of test a, 3 of b, 4 of a again: 'row 4: test 'a': rows are not contiguous'; a blank id on row 3:
    'row 3: empty test id' (rows 1-based); contiguous ids give one record per test in file order."""
    from chainid.records.spec import ReaderSpec
    from chainid.records.table import records_from_table

    num = dict(t=[0.0, 0.1, 0.0, 0.2], x=[1.0, 2.0, 3.0, 4.0], F=[5.0, 6.0, 7.0, 8.0])
    with pytest.raises(ValueError, match=r"^src.csv: row 4: test 'a': rows are not contiguous"):
        records_from_table(_table(test=["a", "a", "b", "a"], **num), ReaderSpec(), "f")
    with pytest.raises(ValueError, match=r"^src.csv: row 3: empty test id$"):
        records_from_table(_table(test=["a", "a", " ", "c"], **num), ReaderSpec(), "f")
    recs = records_from_table(_table(test=["b", "b", " a", "a "], **num), ReaderSpec(), "f")
    assert [r.test for r in recs] == ["b", "a"] and recs[1].x.tolist() == [3.0, 4.0]


def test_table_names_the_first_non_finite_value_its_row_and_the_count():
    """x = [1, nan, 2, inf]: 'column 'x' (x) value nan at row 2 (of 4) is not finite (2 such value(s))'."""
    from chainid.records.spec import ReaderSpec
    from chainid.records.table import records_from_table

    tab = _table(t=[0.0, 0.1, 0.2, 0.3], x=[1.0, np.nan, 2.0, np.inf], F=[1.0, 2.0, 3.0, 4.0])
    with pytest.raises(ValueError, match=r"^src.csv: column 'x' \(x\) value nan at row 2 \(of 4\) is not finite "
                                         r"\(2 such value\(s\)\)$"):
        records_from_table(tab, ReaderSpec(), "f")


# --- weak spots of spec.py: profiles and overrides ---------------------------------------------------------------
def test_reader_profile_errors_and_role_by_role_overrides(tmp_path):
    """A ``--reader`` profile: a missing file, a file that is not TOML, an unknown key and a bad value are each one
    error naming the option and the file; command-line options replace the profile's roles one by one
    (``--units x=m`` keeps its t and F units), None keeps the profile's value, and ``parse_assignments`` reads
    ``--columns`` digits as 1-based positions and ``--scale`` values as numbers."""
    from chainid.records.spec import ReaderSpec, load_profile, parse_assignments, spec_from_options

    missing = tmp_path / "none.toml"
    with pytest.raises(ValueError, match=rf"^--reader '{missing}': no such profile file$"):
        load_profile(missing)
    bad = tmp_path / "bad.toml"
    bad.write_text("fs = = 3\n", encoding="utf-8")
    with pytest.raises(ValueError, match=rf"^--reader '{bad}': not a TOML file \("):
        load_profile(bad)
    bad.write_text("fs = 100\nrate = 3\n", encoding="utf-8")
    with pytest.raises(ValueError, match=rf"^--reader '{bad}': unknown key\(s\) \['rate'\]; valid keys are "):
        load_profile(bad)
    bad.write_text("fs = -1\n", encoding="utf-8")
    with pytest.raises(ValueError, match=rf"^--reader '{bad}': reader fs = -1 Hz is invalid; valid range fs > 0 Hz$"):
        load_profile(bad)
    prof = tmp_path / "rig.toml"
    prof.write_text('fs = 100\nskip_rows = 2\n[units]\nt = "ms"\nx = "in"\nF = "kN"\n[columns]\nx = "Disp"\n',
                    encoding="utf-8")
    s = spec_from_options(prof, units="x=m", columns="F=3", skip_rows=None)
    assert s.units == {"t": "ms", "x": "m", "F": "kN"} and s.columns == {"x": "Disp", "F": 3}
    assert s.fs == 100.0 and s.skip_rows == 2
    assert parse_assignments("x=2, F=Load", "--columns") == {"x": 2, "F": "Load"}
    assert parse_assignments("x=-1", "--scale", numeric=True) == {"x": -1.0}
    assert parse_assignments(None, "--units") == {}
    assert ReaderSpec().is_default and not ReaderSpec(fs=10.0).is_default
    assert ReaderSpec(fs=10.0).merged(fs=None, units={}).fs == 10.0


# --- weak spots of formats.py: where the tables of a container are and what they are called -------------------
def test_container_tables_their_places_and_test_ids():
    """A nested container (JSON-like dicts and lists) holds one table wherever an x and an F column sit side by
    side: a list of tables gets ids ``<file id>_1, _2``; a dict of tables (keyed) its keys; a single table no id (the
    file's); a scalar ``test`` beside the arrays names it; nested names ``group/name`` reach into groups.
    Positions are refused, and a container without the columns names its top-level keys.  MATLAB's (1, N) and
    (N, 1) vectors become (N,)."""
    from chainid.records.formats import _squeeze, _tables
    from chainid.records.spec import ReaderSpec

    S = ReaderSpec()
    a = {"t": [0, 1], "x": [1, 2], "F": [3, 4]}

    def ids(obj, keyed=False, spec=S):
        return [(tb.source, tb.test, list(tb.columns)) for tb in _tables(obj, "f.json", spec, "stem", keyed)]

    assert ids([a, a]) == [("f.json[0]", "stem_1", ["t", "x", "F"]), ("f.json[1]", "stem_2", ["t", "x", "F"])]
    assert ids({"A": a, "B": a}, keyed=True) == [("f.json/A", "A", ["t", "x", "F"]), ("f.json/B", "B", ["t", "x", "F"])]
    assert ids(a) == [("f.json", None, ["t", "x", "F"])]
    assert ids({"test": "T9", **a}) == [("f.json", "T9", ["t", "x", "F"])]
    assert ids({"run": {"data": a}}) == [("f.json/run/data", None, ["t", "x", "F"])]
    nested = ReaderSpec(columns={"x": "g/disp", "F": "g/load"})
    assert _tables({"g": {"disp": [1, 2], "load": [3, 4]}}, "f.json", nested, "s", False)[0].columns == \
        {"g/disp": [1, 2], "g/load": [3, 4]}
    with pytest.raises(ValueError, match=r"^f\.json: no 'x' and 'F' columns found \(top level: \['q'\]\); name them "
                                         r"with --columns x=NAME,F=NAME$"):
        _tables({"q": 1}, "f.json", S, "stem", False)
    with pytest.raises(ValueError, match=r"^f\.json: --columns x=2: positions are for headerless text files"):
        _tables(a, "f.json", ReaderSpec(columns={"x": 2}), "stem", False)
    assert [_squeeze(np.zeros(s)).shape for s in ((1, 3), (3, 1), (2, 3))] == [(3,), (3,), (2, 3)]


def test_canonical_csv_fast_path_returns_views_of_one_array(tmp_path):
    """``read_canonical_csv``'s docstring: with the header on line 1, the arrays of all tests are views into three
    arrays of the whole file (the pyarrow path; the strict reader makes one array per test).  Two tests of
    3 rows: both t arrays share one base, and the numbers are the file's.  Bug caught: the line-1 header test
    inverted (``not line.strip()`` → ``line.strip()``: every file went to the strict reader)."""
    pytest.importorskip("pyarrow")
    from chainid.records.textcanon import read_canonical_csv

    p = tmp_path / "r.csv"
    rows = [("a", 0.0, 1.0, 10.0), ("a", 0.1, 1.5, 12.0), ("a", 0.2, 2.0, 14.0),
            ("b", 0.0, 3.0, 30.0), ("b", 0.1, 3.5, 32.0), ("b", 0.2, 4.0, 34.0)]
    p.write_text("test,t,x,F\n" + "".join(f"{a},{b!r},{c!r},{d!r}\n" for a, b, c, d in rows))
    recs = read_canonical_csv(p)
    assert [r.test for r in recs] == ["a", "b"]
    assert recs[1].x.tolist() == [3.0, 3.5, 4.0] and recs[0].F.tolist() == [10.0, 12.0, 14.0]
    assert recs[0].t.base is not None and recs[0].t.base is recs[1].t.base


def test_whitespace_fast_path_skips_a_preamble_to_the_data_line(tmp_path):
    """A whitespace logger file with two preamble lines (``skip_rows = 2``) and a header (data from line 4) is read
    by the fast path (numpy's loadtxt skipping data_line − 1 = 3 lines), with the same numbers as the
    line-by-line scan.  Bug caught: ``skiprows = data_line − 1`` → ``data_line >> 1`` (1 line skipped: the header is read as data and
    the file left to the scan)."""
    from reader_paths import fast_and_scan

    from chainid.records.spec import ReaderSpec

    p = tmp_path / "log.txt"
    rows = [(0.01 * i, 1.0 + 0.1 * i, -3.5e2 + i / 3) for i in range(40)]
    p.write_text("logger TX-9 serial 4411\nrate 100 Hz\nt  x  F\n" + "".join("  ".join(repr(v) for v in r) + "\n"
                                                                             for r in rows))
    lay, fast, slow = fast_and_scan(p, ReaderSpec(skip_rows=2))
    assert lay.data_line == 4 and lay.names == ["t", "x", "F"]
    assert fast is not None
    for k, j in (("t", 0), ("x", 1), ("F", 2)):
        assert fast[k].tolist() == slow[k].tolist() == [r[j] for r in rows]
    assert math.isclose(fast["F"][-1], -3.5e2 + 39 / 3)
