"""``chainid dynamics``: checks before work, strict, JSON, warnings, the text report and the JSON of a run, the
sine drive's default ω."""
from __future__ import annotations

import json
import os

import numpy as np
import pytest

from chainid.cli import main


SMALL = ["dynamics", "--links", "100", "--masses", "10", "--pretension", "1000", "--speed", "200",
         "--t-ramp", "0.05", "--t-end", "0.1", "--quiet"]


def _fail_if_simulated(monkeypatch):
    import chainid.dynamics as dyn

    def boom(*a, **k):
        raise AssertionError("simulate() was called: the check must come first")
    monkeypatch.setattr(dyn, "simulate", boom)


@pytest.mark.parametrize("extra, needle", [
    (["--modes", "0"], "--modes = 0"),
    (["--refine", "11"], "--refine = 11"),
    (["--max-memory", "0"], "--max-memory"),
])
def test_bad_options_are_refused_before_work(monkeypatch, capsys, extra, needle):
    _fail_if_simulated(monkeypatch)
    assert main(SMALL + extra) == 2
    assert needle in capsys.readouterr().err


def test_sweep_masses_must_be_whole(capsys):
    with pytest.raises(SystemExit) as e:
        main(SMALL + ["--sweep-masses", "1.5"])
    assert e.value.code == 2
    assert "whole numbers" in capsys.readouterr().err


def test_outputs_checked_before_simulating(monkeypatch, tmp_path, capsys):
    _fail_if_simulated(monkeypatch)
    out = tmp_path / "r.json"
    out.write_text("{}")
    assert main(SMALL + ["--json", str(out)]) == 2
    assert "already exists" in capsys.readouterr().err and out.read_text() == "{}"
    f = tmp_path / "plots_is_a_file"
    f.write_text("x")
    assert main(SMALL + ["--plots", str(f)]) == 2
    assert "is a file" in capsys.readouterr().err


def test_huge_damping_is_one_line_not_a_traceback(capsys):
    assert main(SMALL + ["--damping", "1e9"]) == 2
    err = capsys.readouterr().err
    assert "max_work" in err and "Traceback" not in err


@pytest.mark.slow
def test_huge_pretension_warns(tmp_path, capsys):
    out = tmp_path / "r.json"
    assert main(SMALL[:6] + ["1e12"] + SMALL[7:] + ["--refine", "0", "--json", str(out)]) == 0
    err = capsys.readouterr().err
    assert "exceeds the minimum breaking force" in err
    assert any("breaking force" in w for w in json.loads(out.read_text())["warnings"])


def test_json_nan_is_null_and_stdout_is_pure_json(capsys):
    """No static tension (drive 'none', no pretension): dynamic_factor is NaN → null; --json - is parseable."""
    argv = ["dynamics", "--links", "20", "--masses", "2", "--pretension", "0", "--drive", "none",
            "--t-end", "0.01", "--quiet", "--json", "-"]
    assert main(argv) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["summary"]["dynamic_factor"] is None


def test_json_write_is_atomic(monkeypatch, tmp_path):
    """The JSON goes through chainid.infra.fileio: a failure at the final link/rename leaves no file, no temp."""
    import chainid.infra.fileio as fio

    def fail(*a, **k):
        raise OSError(28, "No space left on device")
    monkeypatch.setattr(fio.os, "replace", fail)
    monkeypatch.setattr(fio.os, "link", fail)
    out = tmp_path / "r.json"
    assert main(SMALL + ["--json", str(out)]) == 2
    assert os.listdir(tmp_path) == []


def test_strict_turns_the_check_into_an_exit_code(capsys):
    """A coarse implicit run of a slack polygon drive fails its energy balance: warning (0), --strict (2)."""
    argv = ["dynamics", "--links", "200", "--masses", "20", "--pretension", "500", "--drive", "polygon",
            "--teeth", "6", "--speed", "1500", "--t-ramp", "0.2", "--t-end", "1", "--scheme", "implicit",
            "--dt", "5e-3", "--refine", "0", "--quiet"]
    assert main(argv) == 0
    assert "energy balance error" in capsys.readouterr().err
    assert main(argv + ["--strict"]) == 2
    assert "strict" in capsys.readouterr().err


ARGS = ["dynamics", "--links", "40", "--masses", "4", "--pretension", "3000", "--drive", "sine", "--amplitude",
        "0.05", "--omega", "200", "--t-end", "0.05", "--modes", "3", "--refine", "0", "--quiet"]


def _library():
    from chainid.dynamics import ChainLine, Drive, simulate
    from chainid.dynamics.modes import modes

    line = ChainLine(n_links=40, n_masses=4, pretension_N=3000.0)
    return simulate(line, Drive("sine", A=0.05, omega=200.0), 0.05, refine=0), modes(line, n_modes=3)


def test_text_report_states_the_run(capsys):
    """Four lines: the chain (40 links × 50 mm = 2 m, 4 masses), scheme, step and steps; peak, static and dynamic
    factor; the first three natural frequencies; the energy balance — each number the library's for the same run."""
    assert main(ARGS) == 0
    out = capsys.readouterr().out.splitlines()
    res, md = _library()
    eb = res.energy_balance()
    assert out[0] == (f"chain 40 links (2 m) in 4 masses, explicit, dt = {res.dt:.3g} s ({res.n_steps} steps, "
                      "0 refinement(s))")
    assert out[1] == (f"peak tension {res.peak_tension:.6g} N, static 3000 N, dynamic factor "
                      f"{res.peak_tension / 3000.0:.4g}")
    assert out[2] == "natural frequencies [Hz]: " + ", ".join(f"{f:.4g}" for f in md.frequency_hz)
    assert len(md.frequency_hz) == 3 and np.all(np.diff(md.frequency_hz) > 0)
    assert out[3] == (f"energy [N·mm]: work in {eb['work_in']:.6g} = kinetic {eb['kinetic']:.6g} + stored "
                      f"{eb['elastic']:.6g} + dissipated {eb['dissipated']:.6g} (balance error "
                      f"{eb['relative_error']:.2g} at its worst, t = {eb['worst_t_s']:.4g} s)")


def test_json_has_the_final_tensions_modes_line_and_drive(tmp_path, capsys):
    """The JSON: the last output time's segment tensions, the natural frequencies, the line's fields (without the
    chain and loads, given apart), the drive law and the summary of the library's run."""
    p = tmp_path / "d.json"
    assert main(ARGS + ["--json", str(p)]) == 0
    capsys.readouterr()
    doc = json.loads(p.read_text())
    res, md = _library()
    np.testing.assert_allclose(doc["tension_final_N"], res.tension[-1], rtol=1e-12)
    assert len(doc["tension_final_N"]) == 4
    np.testing.assert_allclose(doc["modes"]["frequency_hz"], md.frequency_hz, rtol=1e-12)
    assert doc["line"]["n_links"] == 40 and doc["line"]["pretension_N"] == 3000.0
    assert "chain" not in doc["line"] and "loads" not in doc["line"] and doc["loads"] == []
    assert doc["chain"]["pitch"] == 50.0
    assert doc["drive"]["law"] == "sine" and doc["drive"]["A"] == 0.05 and doc["drive"]["omega"] == 200.0
    assert doc["summary"]["peak_tension_N"] == pytest.approx(res.peak_tension, rel=1e-12)
    assert doc["summary"]["n_steps"] == res.n_steps and doc["segment_model"] is None


class _Reached(Exception):
    """Raised by a stand-in once the command has handed over its arguments."""


def test_dynamics_sine_drive_defaults_to_the_librarys_omega(monkeypatch):
    """``dynamics --drive sine --amplitude 5`` without ``--omega`` builds the drive with ω = 1 rad/s, the
    library's default (``Drive("sine").omega``) and the option's help.  Bug caught: the option's default 1 → 2."""
    import chainid.dynamics as dyn
    from chainid.cli.parser import build_parser
    from chainid.dynamics import Drive

    seen = {}

    def stand_in(line, drive, t_end, **kw):  # noqa: ANN001
        seen["drive"] = drive
        raise _Reached

    monkeypatch.setattr(dyn, "simulate", stand_in)
    with pytest.raises(_Reached):
        main(["dynamics", "--links", "100", "--masses", "10", "--pretension", "1000", "--t-end", "0.1", "--quiet",
              "--drive", "sine", "--amplitude", "5"])
    assert seen["drive"].omega == Drive("sine").omega == 1.0
    sub = next(a for a in build_parser()._subparsers._group_actions[0].choices.items() if a[0] == "dynamics")[1]
    assert "(default 1)" in next(a.help for a in sub._actions if "--omega" in a.option_strings)
