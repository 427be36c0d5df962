"""What reading notices in many files is one line per check (:func:`chainid.records.plausible.grouped`), as a
warning (``--bad-lines warn``) or as a note (``--bad-lines skip``), each with the command's prefix, and the note never
ends in a traceback.

Three text files, each a 2 Hz sine in s, mm, N with one line of text in the middle (line 53 of each file, counting
the header as line 1); the reference is the file layout written here.
"""
from __future__ import annotations

import math

import pytest

from chainid.cli import main


@pytest.fixture()
def folder(tmp_path):
    d = tmp_path / "in"
    d.mkdir()
    for k in range(3):
        rows = ["t,x,F"]
        for i in range(200):
            t = i * 0.01
            s = math.sin(4 * math.pi * t)
            rows.append(f"{t:.2f},{1 + 0.2 * s:.6f},{1000 + 100 * s:.4f}")
            if i == 50:
                rows.append("oops,bad,line")
        (d / f"T{k}.csv").write_text("\n".join(rows) + "\n")
    return d


@pytest.mark.parametrize("mode, kind", [("warn", "warning"), ("skip", "note")])
def test_one_bad_line_in_every_file_is_one_line(folder, tmp_path, capsys, mode, kind):
    out = tmp_path / f"out_{mode}.csv"
    assert main(["convert", str(folder), "--to", str(out), "--bad-lines", mode]) == 0
    err = capsys.readouterr().err
    lines = [ln for ln in err.splitlines() if "bad line(s) left out" in ln]
    assert len(lines) == 1, err
    first = str(folder / "T0.csv")
    assert f"file {first!r}: 1 bad line(s) left out (--bad-lines {mode}); the first: {first}, line 53:" in lines[0]
    assert lines[0].endswith(f"[the same check on 2 more file(s): {str(folder / 'T1.csv')!r}, "
                             f"{str(folder / 'T2.csv')!r}]")
    assert lines[0].startswith(f"chainid convert: {kind}: ")  # a note carries the command's prefix too
    assert "Traceback" not in err
    assert out.read_text().count("\n") == 1 + 3 * 200  # header + every good row of the three files
