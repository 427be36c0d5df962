"""``max_work`` bounds the work a dynamics run actually does, not only its estimate: a stiff hysteretic element
makes the implicit scheme reject and halve its sub-steps far beyond the estimate, and such a run stops at the
limit with an error naming it and the option to raise it (``--max-work``), instead of running on for an hour.

The same line with a soft element (its estimate the same: steps × nodes) completes within the same limit: the
bound is on the work done, not on the kind of run.
"""
from __future__ import annotations

import pytest

from chainid.cli import main
from chainid.dynamics import ChainLine, Drive, simulate
from chainid.dynamics.simulation import estimate

LIMIT = 2e7  # node-steps


def _line(k_N_per_mm: float, f_N: float) -> ChainLine:
    return ChainLine(n_links=400, n_masses=40, pretension_N=5000.0, hysteresis=((k_N_per_mm, f_N),))


def test_a_stiff_implicit_run_stops_at_the_work_limit():
    line = _line(1e9, 50.0)
    with pytest.raises(ValueError) as e:
        simulate(line, Drive("ramp", v=1000.0, t_ramp=2.0), 0.5, scheme="implicit", max_work=LIMIT)
    msg = str(e.value)
    assert msg.startswith("the run stopped at t = ") and "over max_work = 2e+07 node-steps" in msg
    assert "raise --max-work (max_work)" in msg
    stopped_at = float(msg.split("the run stopped at t = ")[1].split(" s")[0])
    assert 0 < stopped_at < 0.5
    # the estimate alone let it start: the pre-check is below the limit
    est = float(msg.split("the estimate was ")[1].split(")")[0])
    assert est < LIMIT


def test_a_soft_run_with_the_same_estimate_completes():
    line = _line(1e5, 500.0)
    res = simulate(line, Drive("ramp", v=1000.0, t_ramp=2.0), 0.5, scheme="implicit", max_work=LIMIT)
    assert res.t[-1] == pytest.approx(0.5) and 0 < res.work <= LIMIT
    assert estimate(line, res.n_steps, 500, "implicit")["node_steps"] < LIMIT


def test_the_cli_names_the_option(capsys):
    rc = main(["dynamics", "--scheme", "implicit", "--hysteresis", "1e9:50", "--links", "400", "--masses", "40",
               "--t-end", "0.5", "--max-work", "2e7"])
    err = [ln for ln in capsys.readouterr().err.splitlines() if "error" in ln]
    assert rc == 2 and len(err) == 1
    assert err[0].startswith("chainid dynamics: error: the run stopped at t = ") and "raise --max-work" in err[0]
