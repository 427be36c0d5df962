"""``chainid convert``: the canonical file, a bad cell or suffix in one line, reading options checked, a file
system fault in one line."""
from __future__ import annotations

import numpy as np
import pytest

from chainid.cli import main


@pytest.mark.parametrize("n, ok", [(-1, False), (0, True), (1, True)])
def test_skip_rows_below_zero_is_refused(tmp_path, capsys, n, ok):
    data = tmp_path / "d.csv"
    lines = ["# a header block of one line"] if n == 1 else []
    t = np.arange(0, 20, 0.05)
    lines += ["test,t,x,F"] + [f"1,{v:.3f},{2 + 0.2 * np.sin(v):.6f},{1000 + 200 * np.sin(v):.6f}" for v in t]
    data.write_text("\n".join(lines) + "\n")
    rc = main(["identify", str(data), "--model", "linear", "--k", "1000", "--quiet", "--skip-rows", str(n)])
    err = capsys.readouterr().err
    if ok:
        assert "--skip-rows" not in err
        assert rc == 2 and "only 1 test(s) identified" in err  # read and identified; too few for a law
    else:
        assert rc == 2 and "error: --skip-rows = -1 is invalid; valid range >= 0" in err


def test_convert_writes_the_canonical_file_and_refuses_a_bad_cell_in_one_line(tmp_path, capsys):
    src = tmp_path / "rig.csv"
    src.write_text("Time;Disp;Load\n0,0;2,2;11000\n0,1;2,3;11500,5\n0,2;2,25;11250\n")
    out = tmp_path / "o.csv"
    rc = main(["convert", str(src), "--to", str(out), "--columns", "t=Time,x=Disp,F=Load", "--delimiter", ";",
               "--decimal", ","])
    cap = capsys.readouterr()
    assert rc == 0, cap.err
    assert cap.out.strip() == f"wrote {out}: 1 test(s), 3 rows (test,t,x,F in s, mm, N)"
    # the contract is the value, not its spelling (pyarrow writes 0, polars 0.0): every number reads back exactly
    lines = out.read_text().splitlines()
    assert lines[0] == "test,t,x,F"
    rows = [ln.split(",") for ln in lines[1:]]
    assert [r[0] for r in rows] == ["rig"] * 3
    assert [[float(v) for v in r[1:]] for r in rows] == [[0.0, 2.2, 11000.0], [0.1, 2.3, 11500.5], [0.2, 2.25, 11250.0]]
    src.write_text("Time;Disp;Load\n0,0;2,2;11000\n0,1;abc;11500\n")
    rc = main(["convert", str(src), "--to", str(tmp_path / "o2.csv"), "--columns", "t=Time,x=Disp,F=Load",
               "--delimiter", ";", "--decimal", ","])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and err[0].startswith("chainid convert: error: ") and "abc" in err[0], err
    assert not (tmp_path / "o2.csv").exists()


def test_convert_refuses_an_unknown_output_suffix_before_reading(tmp_path, capsys):
    """``chainid convert --to``: the suffix names the format (.csv, .parquet or .pq); another suffix, or none,
    is one line naming it and the valid ones, exit 2, before the inputs are read (a missing input is not the
    error reported) and nothing written."""
    from chainid.records.writer import OUTPUT_FORMATS

    for to, shown in (("o.txt", "'.txt'"), ("o", "'(none)'"), ("o.CSV.gz", "'.gz'")):
        assert main(["convert", str(tmp_path / "missing.csv"), "--to", str(tmp_path / to)]) == 2
        err = capsys.readouterr().err
        assert err == (f"chainid convert: error: --to {str(tmp_path / to)!r}: unknown output suffix {shown}; "
                       f"valid: {', '.join(OUTPUT_FORMATS)}\n")
        assert not (tmp_path / to).exists()
    assert sorted(OUTPUT_FORMATS) == [".csv", ".parquet", ".pq"]


def test_a_file_system_fault_is_one_line_naming_the_file(monkeypatch, capsys):
    """An OSError escaping a command (a file system fault) is one line on stderr, exit 2, no traceback: with the
    file it concerns when the error names one, else the system's message alone."""
    import chainid.cli.convert as conv

    for exc, line in ((OSError(13, "Permission denied", "/data/out.csv"),
                       "chainid convert: error: '/data/out.csv' Permission denied\n"),
                      (OSError(28, "No space left on device"), "chainid convert: error: No space left on device\n")):
        def boom(args, exc=exc):
            raise exc
        monkeypatch.setattr(conv, "cmd_convert", boom)
        assert main(["convert", "in.csv", "--to", "out.csv"]) == 2
        assert capsys.readouterr().err == line
