"""Records as rigs write them (issue 19, issue 20 §3): every format and layout read into the same records.

Every fixture is built here from two reference tests in s, mm, N (tmp_path), written in the rig's layout and
units; the expected values are the reference arrays (unit factors are exact definitions: 1 in = 25.4 mm,
1 kip = 4448.2216152605 N, 1 ms = 1e-3 s), compared with rtol 1e-12.
"""
from __future__ import annotations

import json
import math
import os
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


# -- formats and layouts ------------------------------------------------------------------------------------

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


# -- refusals -----------------------------------------------------------------------------------------------

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


# -- plausibility -------------------------------------------------------------------------------------------

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
