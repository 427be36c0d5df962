"""The CLI's range checks at their bounds ("a clear error naming the field, the value and the valid range"): each
documented bound is accepted on its valid side and refused just outside it, with one line on stderr and exit
code 2. The bounds are the ones the messages state (">= 16", "0 to --cycles/2", "> 0 N/mm", ...)."""
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
    (["--max-memory=-1"], False, "--max-memory = -1.0 is invalid: valid range > 0 GiB"),
    (["--mass", "0"], True, None),
    (["--mass", "-1"], False, "--mass = -1.0 is invalid: valid range >= 0 kg"),
    (["--model", "linear", "--k", "0"], False, "--k = 0.0 is invalid: valid range > 0 N/mm"),
    (["--model", "linear", "--k", "150", "--x-ref", "nan"], False, "--x-ref = nan is invalid: valid range finite mm"),
]


@pytest.mark.parametrize("extra, ok, words", SIMULATE)
def test_simulate_bounds(tmp_path, plan, capsys, extra, ok, words):
    out = tmp_path / "o.csv"
    pairs = [tuple(a.split("=", 1)) if "=" in a else None for a in extra]
    extra_d = dict(p for p in pairs if p) if all(pairs) else dict(zip(extra[::2], extra[1::2]))
    opts = {"--cycles": "4", "--samples-per-cycle": "32", **extra_d}  # each option once
    rc = main(["simulate", str(out), "--plan", str(plan), *(f"{k}={v}" for k, v in opts.items())])
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


class _Reached(Exception):
    """Raised by the stubbed simulation: every check before the work has passed."""


DYN = ["dynamics", "--links", "100", "--masses", "10", "--pretension", "1000", "--t-end", "0.1", "--quiet"]


@pytest.fixture
def stub_simulate(monkeypatch):
    import chainid.dynamics as dyn

    seen = {}

    def stub(line, drive, t_end, **kw):
        seen.update(line=line, drive=drive, t_end=t_end, **kw)
        raise _Reached

    monkeypatch.setattr(dyn, "simulate", stub)
    return seen


@pytest.mark.parametrize("extra, words", [
    (["--modes", "1"], None), (["--modes", "0"], "--modes = 0 is invalid: valid range an int >= 1"),
    (["--refine", "0"], None), (["--refine", "10"], None), (["--refine", "11"], "--refine = 11 is invalid: valid range 0 .. 10"),
    (["--refine=-1"], "--refine = -1 is invalid"),
    (["--max-work", "1"], None), (["--max-work", "inf"], "--max-work = inf is invalid: valid range > 0 (finite)"),
    (["--max-memory", "inf"], "--max-memory = inf is invalid"), (["--max-memory", "0.001"], None),
    (["--sweep-speed", "100,200", "--plots", "P"], "--plots = 'P' is invalid with a sweep"),
    (["--segment-model", "m.toml", "--coulomb", "5"], "--segment-model comes with its own chain and damping: --coulomb"),
])
def test_dynamics_checks_before_work(stub_simulate, capsys, monkeypatch, tmp_path, extra, words):
    monkeypatch.chdir(tmp_path)
    if words is None:
        with pytest.raises(_Reached):
            main(DYN + extra)
    else:
        assert main(DYN + extra) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and words in err[0], err


def test_dynamics_option_values_reach_the_simulation(stub_simulate):
    """``--hysteresis K:F``, ``--dahl F_H:X_H`` and ``--load NODE:F:T`` are parsed into the line; the memory limit
    in GiB becomes bytes."""
    with pytest.raises(_Reached):
        main(DYN + ["--hysteresis", "2000:150", "--dahl", "120:0.05", "--load", "5:3000:0.04", "--max-memory", "1.5",
                    "--refine", "3", "--scheme", "implicit"])
    line = stub_simulate["line"]
    assert line.hysteresis == ((2000.0, 150.0),) and line.dahl == ((120.0, 0.05),)
    (ld,) = line.loads
    assert (ld.node, ld.force_N, ld.t_on) == (5, 3000.0, 0.04)
    assert stub_simulate["max_memory"] == 1.5 * 2**30 and stub_simulate["refine"] == 3
    assert stub_simulate["scheme"] == "implicit" and stub_simulate["t_end"] == 0.1
    assert (line.n_links, line.n_masses, line.pretension_N) == (100, 10, 1000.0)


@pytest.mark.parametrize("opt, bad, words", [("--hysteresis", "2000", "expected two numbers A:B"),
                                             ("--load", "5:3000", "expected NODE:FORCE_N:T_ON_S"),
                                             ("--sweep-masses", "10,0", "whole numbers >= 1 (got 0)"),
                                             ("--sweep-speed", "1,x", "is not a comma-separated list of numbers")])
def test_dynamics_malformed_values(capsys, opt, bad, words):
    with pytest.raises(SystemExit) as e:
        main(DYN + [opt, bad])
    assert e.value.code == 2 and words in capsys.readouterr().err
