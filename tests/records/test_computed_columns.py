"""Computed columns (``--derive``, ``[derive]``): expressions over numbered (``c7``) and named columns, evaluated by
numexpr behind a whitelist.  The references are the same arithmetic done here in plain Python on the numbers the
test wrote into the file (the IEEE operations are the same: agreement to 1e-12 relative)."""
from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from chainid.records.reader import read_any
from chainid.records.spec import ReaderSpec, spec_from_options
from daq_files import write_seal


def test_friction_is_force_minus_pressure_times_area_by_column_number(tmp_path):
    ref = write_seal(tmp_path / "S_3bar.csv")
    spec = spec_from_options(columns="t=1,x=5", units="t=ms", derive=["F = c7 - c6*51.875"])
    (rec,) = read_any(tmp_path / "S_3bar.csv", spec)
    want_F = [f - p * 51.875 for f, p in zip(ref["F_N"], ref["p_bar"])]
    np.testing.assert_allclose(rec.F, want_F, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(rec.t, ref["t_ms"] / 1000.0, rtol=1e-15, atol=0)
    np.testing.assert_array_equal(rec.x, ref["x_mm"])


def test_named_columns_and_a_chain_of_expressions_in_any_order(tmp_path):
    p = tmp_path / "named.csv"
    rows = [(0.01 * i, 40.0 + 3 * math.sin(i / 7), 2.0 + 0.001 * i, 5.0 * math.cos(i / 9)) for i in range(300)]
    p.write_text("time,F_meas,p_bar,disp\n" + "\n".join(",".join(repr(v) for v in r) for r in rows) + "\n")
    spec = ReaderSpec(columns={"t": "time", "x": "disp"}, derive={"F": "F_meas - pA", "pA": "p_bar*49.087"})
    (rec,) = read_any(p, spec)
    np.testing.assert_allclose(rec.F, [r[1] - r[2] * 49.087 for r in rows], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(rec.x, [r[3] for r in rows], rtol=0, atol=0)


def test_unknown_symbol_is_one_error_naming_it_and_the_known_columns(tmp_path):
    write_seal(tmp_path / "S.csv")
    spec = spec_from_options(columns="t=1,x=5", units="t=ms", derive=["F = c7 - q*51.875"])
    with pytest.raises(ValueError, match=r"derive F = 'c7 - q\*51\.875': unknown symbol 'q'; known columns: c1, c2"):
        read_any(tmp_path / "S.csv", spec)


@pytest.mark.parametrize("expr, words", [
    ('__import__("os").system("true")', "'Attribute' is not allowed"),
    ('__import__("os")', "unknown function '__import__'"),
    ("c1.real", "'Attribute' is not allowed"),
    ("(lambda: 1)()", "'Lambda' is not allowed"),
    ("c1[0]", "'Subscript' is not allowed"),
    ("'a'", "the constant 'a' is not a number"),
    ("open(c1)", "unknown function 'open'"),
    ("sqrt(c1, c2)", "sqrt() takes 1 argument(s), got 2"),
    ("c1 +", "not an expression"),
])
def test_the_whitelist_refuses_code_before_anything_is_evaluated(expr, words, monkeypatch):
    import numexpr

    def never(*a, **k):  # noqa: ANN002, ANN003
        raise AssertionError("numexpr must not be called on a refused expression")

    monkeypatch.setattr(numexpr, "evaluate", never)
    with pytest.raises(ValueError) as exc:
        spec_from_options(columns="t=1,x=5", derive=[f"F = {expr}"])
    assert words in str(exc.value)


def test_a_division_by_zero_names_the_row(tmp_path):
    p = tmp_path / "z.tsv"
    p.write_text("".join(f"{i}\t{1.0 + i}\t{0.0 if i == 4 else 2.0}\n" for i in range(20)))
    spec = spec_from_options(columns="t=1,x=2", derive=["F = c2 / c3"])
    with pytest.raises(ValueError, match=r"derive F = 'c2 / c3' is inf at data row 5 \(1 non-finite value\(s\)\)"):
        read_any(p, spec)


def test_kept_channel_in_mpa_and_reduced_covariate(tmp_path):
    ref = write_seal(tmp_path / "S_5bar.csv", p_bar=5.0)
    spec = spec_from_options(columns="t=1,x=5", units="t=ms,p=bar", derive=["F = c7 - c6*51.875", "p = c6"],
                             keep="p", reduce="p_mean=mean(c6),p_first=first(c6)")
    (rec,) = read_any(tmp_path / "S_5bar.csv", spec)
    np.testing.assert_allclose(rec.channels["p"], ref["p_bar"] * 0.1, rtol=1e-15)  # 1 bar = 0.1 MPa
    assert rec.covariates["p_mean"] == pytest.approx(sum(ref["p_bar"]) / len(ref["p_bar"]), rel=1e-13)
    assert rec.covariates["p_first"] == ref["p_bar"][0]
    win = rec.window(1.0, 2.0)  # a window keeps both
    assert win.channels["p"].size == win.t.size == 100 and win.covariates == rec.covariates


def test_command_line_and_profile_give_the_same_computed_force(tmp_path):
    write_seal(tmp_path / "S_3bar.csv")
    prof = tmp_path / "seal.toml"
    prof.write_text('delimiter = "tab"\nheader = false\n[columns]\nt = 1\nx = 5\n[units]\nt = "ms"\n'
                    '[derive]\nF = "c7 - c6*51.875"\n')
    code = "from chainid.cli import main; raise SystemExit(main())"
    outs = []
    for extra, name in ((["--reader", str(prof)], "a.csv"),
                        (["--columns", "t=1,x=5", "--units", "t=ms", "--derive", "F = c7 - c6*51.875"], "b.csv")):
        r = subprocess.run([sys.executable, "-c", code, "convert", str(tmp_path / "S_3bar.csv"),
                            "--to", str(tmp_path / name), *extra], capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
        outs.append((tmp_path / name).read_bytes())
    assert outs[0] == outs[1] and outs[0].startswith(b"test,t,x,F\n")


def test_container_columns_are_named_never_numbered(tmp_path):
    import json

    t = [0.01 * i for i in range(40)]
    (tmp_path / "r.json").write_text(json.dumps({"time": t, "disp": [1 + a for a in t], "load": [5 + a for a in t],
                                                 "p": [2.0] * 40}))
    spec = spec_from_options(columns="t=time,x=disp", derive=["F = load - p*10"])
    (rec,) = read_any(tmp_path / "r.json", spec)
    np.testing.assert_allclose(rec.F, [5 + a - 20.0 for a in t], rtol=1e-15, atol=1e-15)
    with pytest.raises(ValueError, match=r"r\.json: no 'disp' and 'c3' and 'p' columns found \(top level: \['time', "):
        read_any(tmp_path / "r.json", spec_from_options(columns="t=time,x=disp", derive=["F = c3 - p*10"]))
