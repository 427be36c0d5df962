"""The CLI's range checks at their bounds (issue 20: "a clear error naming the field, the value and the valid
range"): each documented bound is accepted on its valid side and refused just outside it, with one line on stderr
and exit code 2. The bounds are the ones the messages state (">= 16", "0 to --cycles/2", "> 0 N/mm", ...)."""
from __future__ import annotations

import pytest

from chainid.cli import main


@pytest.fixture
def plan(tmp_path):
    p = tmp_path / "plan.csv"
    p.write_text("test,omega,x0,A\n1,2.0,2.2,0.25\n")
    return p


# (extra options, accepted?, words of the one error line)
SIMULATE = [
    (["--samples-per-cycle", "16"], True, None),
    (["--samples-per-cycle", "15"], False, "--samples-per-cycle = 15 is invalid: valid range >= 16"),
    (["--cycles", "4", "--taper-cycles", "2"], True, None),
    (["--cycles", "4", "--taper-cycles", "2.01"], False, "--taper-cycles = 2.01 is invalid: valid range 0 to --cycles/2"),
    (["--taper-cycles", "-0.1"], False, "--taper-cycles = -0.1 is invalid"),
    (["--ramp-rate", "0"], True, None),
    (["--ramp-rate", "-0.01"], False, "--ramp-rate = -0.01 is invalid: valid range >= 0 mm/s (0 = no ramp)"),
    (["--noise-x", "0", "--noise-F", "0"], True, None),
    (["--noise-x", "-0.001"], False, "--noise-x = -0.001 is invalid: valid range >= 0 mm"),
    (["--noise-F", "-1"], False, "--noise-F = -1.0 is invalid: valid range >= 0 N"),
    (["--cycles", "0"], False, "--cycles = 0.0 is invalid: valid range > 0"),
    (["--max-memory", "0"], False, "--max-memory = 0.0 is invalid: valid range > 0 GiB"),
    (["--mass", "0"], True, None),
    (["--mass", "-1"], False, "--mass = -1.0 is invalid: valid range >= 0 kg"),
    (["--model", "linear", "--k", "0"], False, "--k = 0.0 is invalid: valid range > 0 N/mm"),
    (["--model", "linear", "--k", "150", "--x-ref", "nan"], False, "--x-ref = nan is invalid: valid range finite mm"),
]


@pytest.mark.parametrize("extra, ok, words", SIMULATE)
def test_simulate_bounds(tmp_path, plan, capsys, extra, ok, words):
    out = tmp_path / "o.csv"
    opts = {"--cycles": "4", "--samples-per-cycle": "32", **dict(zip(extra[::2], extra[1::2]))}  # each once
    rc = main(["simulate", str(out), "--plan", str(plan), *(a for kv in opts.items() for a in kv)])
    err = capsys.readouterr().err.strip().splitlines()
    if ok:
        assert rc == 0 and out.is_file(), err
    else:
        assert rc == 2 and len(err) == 1 and words in err[0], err
        assert not out.exists()


@pytest.fixture(scope="module")
def records(tmp_path_factory):
    d = tmp_path_factory.mktemp("b") / "d.csv"
    assert main(["simulate", str(d), "--cycles", "5", "--samples-per-cycle", "48", "--noise-F", "5"]) == 0
    return d


@pytest.mark.parametrize("tol, ok, words", [
    ("5%", True, None), ("0.05", True, None), ("auto", True, None), ("99.9%", True, None),
    ("0", False, "--steady-tol '0': must be between 0 and 1"), ("1", False, "must be between 0 and 1 (0 and 100 %)"),
    ("100%", False, "must be between 0 and 1"), ("five", False, "--steady-tol 'five': expected a fraction such as 0.05"),
])
def test_identify_steady_tol_forms(records, capsys, tol, ok, words):
    """``--steady-tol`` is a fraction, a percentage or auto; the tolerance used is printed per test."""
    rc = main(["identify", str(records), "--steady-tol", tol, "--quiet"])
    cap = capsys.readouterr()
    err = cap.err.strip().splitlines()
    if ok:
        assert rc == 0, err
        kept = [ln for ln in cap.out.splitlines() if "cycle(s) kept" in ln]
        assert kept
        if tol == "auto":
            assert all("(adaptive)" in ln for ln in kept)
        else:
            pct = float(tol[:-1]) if tol.endswith("%") else 100 * float(tol)
            assert all(f"tolerance {pct:g} %" in ln and "(adaptive)" not in ln for ln in kept), kept
    else:
        assert rc == 2 and len(err) == 1 and words in err[0], err


@pytest.mark.parametrize("extra, ok, words", [
    (["--mass", "0"], True, None), (["--model", "linear", "--k", "0"], False, "--k = 0.0 is invalid: valid range > 0"),
    (["--model", "linear", "--k", "1e-9"], True, None),
])
def test_identify_model_numbers(records, capsys, extra, ok, words):
    rc = main(["identify", str(records), "--quiet", *extra])
    err = capsys.readouterr().err.strip().splitlines()
    if ok:
        assert rc == 0, err
    else:
        assert rc == 2 and len(err) == 1 and words in err[0], err
