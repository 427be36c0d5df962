"""Odd cells and options are refused with one clear line (exit 2), never taken silently, never a traceback: an
option given twice, ``identify --mass -100``, duplicate side-file rows, an empty ``--holdout``, ``diagnose`` on
F ≈ 1e154 N and on F ≡ 0, implausible records under --strict."""
from __future__ import annotations

import numpy as np
import pytest

from chainid.cli import main
from chainid.records.files import Record, read_records, write_records


@pytest.fixture(scope="module")
def data(tmp_path_factory):
    p = tmp_path_factory.mktemp("ic") / "d.csv"
    assert main(["simulate", str(p), "--cycles", "5", "--samples-per-cycle", "48"]) == 0
    return p


def _err(capsys, argv):
    capsys.readouterr()
    try:
        rc = main(argv)
    except SystemExit as exc:  # argparse's own errors
        rc = exc.code
    err = capsys.readouterr().err.strip().splitlines()
    return rc, err


@pytest.mark.parametrize("argv, opt", [
    (["identify", "{d}", "--json", "{o}/a.json", "--json", "{o}/b.json"], "--json"),
    (["identify", "{d}", "--mass", "1", "--mass", "2"], "--mass"),
    (["stiffness", "--x", "1", "--x", "2"], "--x"),
    (["stiffness", "--x", "1", "--force", "--force"], "--force"),
    (["diagnose", "--resamples", "0", "{d}", "--holdout", "3", "--holdout", "7"], "--holdout"),
    (["simulate", "{o}/s.csv", "--effect", "friction:F_c=100", "--effect", "backlash:b=0.01"], "--effect"),
])
def test_option_given_twice_is_refused(data, tmp_path, capsys, argv, opt):
    rc, err = _err(capsys, [a.format(d=data, o=tmp_path) for a in argv])
    assert rc == 2
    assert err[-1].endswith(f"error: {opt} given twice; give it once"), err
    assert not list(tmp_path.iterdir())  # nothing written


def test_repeatable_options_still_repeat(capsys):
    # --load is an append option of dynamics: two loads are two loads
    from chainid.cli.parser import build_parser

    args = build_parser().parse_args(["dynamics", "--load", "2:10:0", "--load", "3:20:0.5"])
    assert len(args.load) == 2
    args = build_parser().parse_args(["dynamics", "--hysteresis", "1000:10", "--hysteresis", "2000:20"])
    assert len(args.hysteresis) == 2


@pytest.mark.parametrize("mass", ["-100", "nan", "inf"])
def test_identify_mass_out_of_range(data, capsys, mass):
    rc, err = _err(capsys, ["identify", str(data), f"--mass={mass}"])
    assert rc == 2 and len(err) == 1
    assert "--mass" in err[0] and "valid range >= 0 kg" in err[0]


def test_side_file_duplicate_rows_refused(data, tmp_path, capsys):
    side = tmp_path / "side.csv"
    side.write_text("test,omega,x0,A\n1,0.314159,2.2,0.25\n2,1.25664,2.2,0.25\n1,0.3,2.2,0.25\n")
    rc, err = _err(capsys, ["identify", str(data), "--side", str(side)])
    assert rc == 2 and len(err) == 1
    assert "line 4: test '1' appears twice (line 2 too)" in err[0]


@pytest.mark.parametrize("holdout", ["", ",", " , "])
def test_empty_holdout_is_one_clear_line(data, capsys, holdout):
    rc, err = _err(capsys, ["diagnose", "--resamples", "0", str(data), f"--holdout={holdout}"])
    assert rc == 2 and len(err) == 1
    assert err[0] == "chainid diagnose: error: --holdout: no test held out; give test ids or --holdout-blocks K"


def _scaled(data, tmp_path, name, fn):
    recs = read_records(data, validate=False)
    return write_records(tmp_path / name, [Record(r.test, r.t, r.x, fn(r.F)) for r in recs])


def test_diagnose_huge_force_is_a_clear_error(data, tmp_path, capsys):
    p = _scaled(data, tmp_path, "big.csv", lambda F: F * 1e150)
    rc, err = _err(capsys, ["diagnose", "--resamples", "0", str(p), "--holdout", "3", "--max-combo", "1"])
    assert rc == 2 and len(err) == 1, err
    assert "|F| = " in err[0] and "e+154 N is out of range; valid range |F| <= 1e+12 N" in err[0]


def test_diagnose_zero_force_is_a_clear_error(data, tmp_path, capsys):
    p = _scaled(data, tmp_path, "zero.csv", np.zeros_like)
    rc, err = _err(capsys, ["diagnose", "--resamples", "0", str(p), "--holdout", "3", "--max-combo", "1"])
    assert rc == 2 and len(err) == 1, err
    assert "the force F is constant (0 N in all" in err[0] and "nothing to diagnose" in err[0]


@pytest.mark.parametrize("mass", [-100.0, float("nan"), True])
def test_identify_records_api_refuses_a_bad_mass(data, mass):
    from chainid.damping.identify import identify_records
    from chainid.model.base import ChainModel

    with pytest.raises(ValueError, match="mass_kg = .* is invalid: valid range >= 0 kg"):
        identify_records(read_records(data, validate=False)[:1], ChainModel(), mass_kg=mass)


def test_strict_makes_implausible_records_one_error_line(tmp_path, capsys):
    """x in µm read as mm (a 500 mm span on the 14x50 chain): a warning, and with ``--strict`` the one error
    line that lists it."""
    t = np.linspace(0, 20, 2000)
    p = tmp_path / "um.csv"
    from chainid.records.record import Record

    write_records(p, [Record("u", t, 2200 + 250 * np.sin(t), 11000 + 1000 * np.sin(t))])
    rc = main(["identify", str(p), "--quiet", "--strict"])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1, err
    assert err[0].startswith("chainid identify: error: --strict: implausible records: test 'u': x spans 500 mm")
    assert "; test 'u': " in err[0]  # the second warning, joined on the same line


def test_simulating_a_linear_spring_needs_its_stiffness(tmp_path, capsys):
    """``simulate --model linear`` without ``--k``: refused before any work, naming the missing option and its unit;
    nothing written."""
    rc, err = _err(capsys, ["simulate", str(tmp_path / "s.csv"), "--model", "linear"])
    assert rc == 2
    assert err[-1].endswith("error: --model linear needs --k [N/mm] (and --x-ref [mm]) for simulation"), err
    assert not list(tmp_path.iterdir())
