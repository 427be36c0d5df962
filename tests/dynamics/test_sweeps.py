"""Sweeps of dynamics runs (chainid.dynamics.sweeps): the ripple over the last quarter, the table in key order."""
from __future__ import annotations

import numpy as np
import pytest

from chainid.dynamics import ChainLine, Drive, simulate


def test_sweep_case_ripple_is_over_the_last_quarter_and_the_table_is_in_key_order():
    """A sweep case's drive-end ripple [N] and mean [N] are those of the last quarter of the run (the documented
    t >= 0.75·t_end), computed here from a direct :func:`simulate` of the same line; ``as_table`` gives the rows
    in key order; an empty swept list is refused by name.
    Bugs caught: the quarter's bound, ripple as min − max, the table's keys or rows swapped."""
    from chainid.dynamics.sweeps import as_table, run_case, sweep_cases

    line = ChainLine(n_links=40, n_masses=4, pretension_N=1_000.0)
    drive = Drive("sine", A=0.5, omega=300.0)
    cases = sweep_cases(line, drive, 0.04, pretensions=[1_500.0], peak_force=4_000.0)
    assert len(cases) == 1 and cases[0]["n_masses"] == 4 and cases[0]["v"] == 0.0
    row = run_case(cases[0])
    res = simulate(ChainLine(n_links=40, n_masses=4, pretension_N=1_500.0), drive, 0.04, peak_force=4_000.0)
    T0 = res.tension[:, 0]
    tail = T0[res.t >= 0.03 - 1e-12]
    assert tail.size < T0.size // 3  # the quarter, not the whole run
    assert row["drive_tension_ripple_N"] == pytest.approx(tail.max() - tail.min(), rel=1e-12)
    assert row["drive_tension_ripple_N"] > 0 and row["drive_tension_ripple_N"] < T0.max() - T0.min()
    assert row["drive_tension_mean_N"] == pytest.approx(tail.mean(), rel=1e-12)
    tab = as_table([row, dict(row, pretension_N=2.0)], keys=("pretension_N", "n_masses"))
    np.testing.assert_array_equal(tab, [[1_500.0, 4.0], [2.0, 4.0]])
    for name in ("pretensions", "speeds", "n_masses"):
        with pytest.raises(ValueError, match=f"{name} = \\[\\] is invalid"):
            sweep_cases(line, drive, 0.04, **{name: []})
