"""Pins of ``chainid dynamics``' text report and JSON (chainid.cli.dynamics; issue 20 §5, own mutation seeds of
mutH): what it prints is the library's run of the same line and drive (chainid.dynamics.simulate and modes),
with the chain's size by hand.  Units: mm, N, s, Hz, N·mm."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from chainid.cli import main

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
