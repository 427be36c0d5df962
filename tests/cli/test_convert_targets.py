"""``chainid convert`` outputs: never an input (the same path, a symbolic link to it, /dev/stdout redirected onto
it), stdout with ``--to -``, a character device whatever its name (``/dev/null --force``), and the covariates side
file beside the output.  Inputs are compared byte for byte before and after."""
from __future__ import annotations

import hashlib
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from chainid.records.record import Record
from chainid.records.writer import write_canonical

CODE = "from chainid.cli import main; raise SystemExit(main())"


def _run(args, stdout=subprocess.PIPE, **kw):
    return subprocess.run([sys.executable, "-c", CODE, "convert", *args], stdout=stdout, stderr=subprocess.PIPE,
                          **kw)


def _digest(p: Path) -> str:
    return hashlib.sha256(p.read_bytes()).hexdigest()


def _records(tmp_path, suffix=".csv") -> Path:
    t = np.arange(500) * 0.01
    return write_canonical(tmp_path / f"IN{suffix}", [Record("A", t, 1 + 0.3 * np.sin(6 * t), 1e4 + 100 * t)])


def test_the_input_as_output_is_refused_also_through_a_link(tmp_path):
    src = _records(tmp_path)
    before = _digest(src)
    r = _run([str(src), "--units", "x=in", "--to", str(src), "--force"])
    assert r.returncode == 2 and b"is the input IN" in r.stderr and r.stderr.count(b"\n") == 1
    link = tmp_path / "link.csv"
    link.symlink_to(src)
    r = _run([str(src), "--units", "x=in", "--to", str(link), "--force"])
    assert r.returncode == 2 and b"refusing to overwrite an input" in r.stderr
    assert _digest(src) == before and link.is_symlink()


def test_a_parquet_input_is_never_modified_by_a_convert_to_stdout(tmp_path):
    src = _records(tmp_path, ".parquet")
    before = _digest(src)
    for to in ("-", "/dev/stdout"):
        with open(src, "ab") as out:  # stdout redirected onto the input (>> IN.parquet)
            r = _run([str(src), "--to", to, "--force"], stdout=out)
        assert r.returncode == 2 and b"input" in r.stderr, r.stderr
        assert _digest(src) == before
    r = _run([str(src), "--to", "-"])  # stdout a pipe: the CSV
    assert r.returncode == 0 and r.stdout.startswith(b"test,t,x,F\nA,0.0,1.0,10000.0\n")
    assert _digest(src) == before
    out = tmp_path / "o.csv"
    assert _run([str(src), "--to", str(out)]).returncode == 0
    assert out.read_bytes() == r.stdout  # the same text as a file


@pytest.mark.skipif(not os.path.exists("/dev/null"), reason="no /dev/null")
def test_dev_null_is_accepted_with_force(tmp_path):
    src = _records(tmp_path)
    r = _run([str(src), "--to", "/dev/null", "--force"])
    assert r.returncode == 0 and b"wrote /dev/null: 1 test(s), 500 rows" in r.stdout


def test_covariates_go_beside_the_output_and_are_checked_first(tmp_path):
    src = tmp_path / "run_7bar.tsv"
    src.write_text("".join(f"{0.01 * i}\t{1.0 + i % 7}\t{20.0 + i % 5}\n" for i in range(100)))
    args = [str(src), "--columns", "x=1,F=2", "--fs", "100", "--covariate", "p_bar=_([0-9.]+)bar$"]
    r = _run([*args, "--to", str(tmp_path / "out.csv")], text=True)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "out.covariates.csv").read_text() == "test,name,value\nrun_7bar,p_bar,7.0\n"
    assert (tmp_path / "out.csv").read_text().splitlines()[0] == "test,t,x,F"
    (tmp_path / "o2.covariates.csv").write_text("mine\n")
    r = _run([*args, "--to", str(tmp_path / "o2.csv")], text=True)
    assert r.returncode == 2 and "covariates file" in r.stderr and "already exists" in r.stderr
    assert not (tmp_path / "o2.csv").exists() and (tmp_path / "o2.covariates.csv").read_text() == "mine\n"
