"""Pins of ``chainid identify``'s text report (chainid.cli.identify; issue 20 §5, own mutation seeds of mutH):
records simulated with a known viscous law on a linear spring, so every number printed is known by hand.
Units: mm, N, s, kg; c_e N·s/mm."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.cli import main

C = 300.0  # the simulated viscous damping [N·s/mm]


@pytest.fixture(scope="module")
def data(tmp_path_factory):
    from chainid.model.base import LinearModel
    from chainid.model.laws import ViscousLaw
    from chainid.records.files import write_records
    from chainid.records.simulate import paper_plan, simulate

    recs = simulate(paper_plan(), LinearModel(1e4), ViscousLaw([C]), n_cycles=4, samples_per_cycle=100,
                    ramp_rate=None)
    return write_records(tmp_path_factory.mktemp("id") / "d.csv", recs)


def test_identify_text_report_by_hand(data, capsys):
    """The model line (linear spring, m = 0 kg); one table row per test with c_e = 300 N·s/mm and F_ac = c ω A;
    the kept cycles 1-3 of 4 (the first dropped) and the window T..4T per test; the steady-cycle statement per test; the viscous law c = 300, its standard error 0, cond(X) = cond(G) = 1 for
    a column of ones, dof = 9 − 1 = 8, the residuals per test; the ranking headed by the true (viscous) law."""
    from chainid.records.simulate import paper_plan

    rc = main(["identify", str(data), "--model", "linear", "--k", "10000", "--law", "viscous", "--quiet"])
    out = capsys.readouterr().out.splitlines()
    assert rc == 0
    assert out[0] == "model: linear, mass m = 0 kg"
    head = out[1].split()
    assert head[:4] == ["test", "omega", "rad/s", "x0"] and set(out[2]) <= {"-", " "}
    plan = paper_plan()
    rows = [ln.split() for ln in out[3:12]]
    for s, r in zip(plan, rows):
        assert r[0] == s.test
        assert float(r[1]) == pytest.approx(s.omega, rel=1e-4) and float(r[3]) == pytest.approx(s.A, rel=1e-3)
        assert float(r[8]) == pytest.approx(C * s.omega * s.A, rel=1e-3)  # F_ac
        assert float(r[9]) == pytest.approx(C, rel=1e-3)  # c_e
        T = 2 * math.pi / s.omega  # 4 cycles from t = 0, the first dropped: cycles 1-3, window T..4T
        assert r[13:] == ["1-3", "(3)", f"{T:.4g}-{4 * T:.4g}"]
    assert out[12] == "steady cycles kept:"
    assert [ln.split(":")[0] for ln in out[13:22]] == [f"  {s.test}" for s in plan]
    i = out.index("damping law viscous: c_e = c")
    assert out[i + 1].split() == ["param", "lstsq", "std", "err", "normal", "eq.", "(Eq.", "23)"]
    p = out[i + 3].split()
    assert p[0] == "c" and float(p[1]) == pytest.approx(C, rel=1e-3) and float(p[3]) == pytest.approx(C, rel=1e-3)
    assert float(p[2]) < 1.0  # noise-free: the spread of c_e over the tests is tiny
    assert out[i + 4].startswith("cond(X) = 1, cond(G = X'X) = 1, RMSE = ") and out[i + 4].endswith(", dof = 8")
    assert out[i + 5].startswith("residuals [N.s/mm]: " + f"{plan[0].test}: ")
    assert out[i + 5].count(": ") == 1 + 9
    j = out.index("laws ranked by leave-one-out RMSE:")
    assert out[j + 1].split() == ["law", "params", "RMSE", "N.s/mm", "LOO", "RMSE", "N.s/mm"]
    ranked = [ln.split() for ln in out[j + 3:j + 9]]
    assert ranked[0][:2] == ["viscous", "1"] and {r[0] for r in ranked[-2:]} == {"hysteretic", "coulomb"}
    loo = [float(r[-1]) for r in ranked]
    # ranked by LOO RMSE, errors at round-off (below 1e-9 of c_e) being ties (fewer parameters first)
    key = [max(v, 1e-9 * C) for v in loo]
    assert key == sorted(key) and loo[-1] > 100.0  # Coulomb's 1/(ωA) misses a constant c by far
