"""Parameter sweeps (chainid.dynamics.sweeps): the product order of the cases, the base case's own values by default,
and a serial sweep of lines at rest whose drive-end tension is their pretension (a static state stays static).
Units mm, N, s."""
from __future__ import annotations

import numpy as np
import pytest

from chainid.dynamics import ChainLine, Drive
from chainid.dynamics.sweeps import as_table, sweep, sweep_cases


def test_cases_are_the_product_with_the_pretension_slowest_and_n_fastest():
    """pretensions (100, 200) × speeds (0, 50) × N (2, 4): 8 cases in the order (100, 0, 2), (100, 0, 4),
    (100, 50, 2), …, (200, 50, 4); each case's line and drive carry its values, the time is a float and the
    simulate keywords are passed on.  Bugs caught: the product's order, a swept value not put into the line or the
    drive, the keywords dropped."""
    line = ChainLine(n_links=8, n_masses=2, pretension_N=10.0, damping=1.0)
    drive = Drive("ramp", v=5.0, t_ramp=0.1)
    cases = sweep_cases(line, drive, 1, pretensions=[100, 200], speeds=[0, 50], n_masses=[2, 4], n_out=7)
    want = [(p, v, n) for p in (100.0, 200.0) for v in (0.0, 50.0) for n in (2, 4)]
    assert [(c["pretension_N"], c["v"], c["n_masses"]) for c in cases] == want
    for c, (p, v, n) in zip(cases, want):
        assert (c["line"].pretension_N, c["line"].n_masses, c["drive"].v) == (p, n, v)
        assert c["line"].damping == 1.0 and c["drive"].t_ramp == 0.1 and c["drive"].law == "ramp"
        assert c["t_end"] == 1.0 and isinstance(c["t_end"], float) and c["sim"] == {"n_out": 7}


def test_without_swept_values_the_base_case_is_the_one_case():
    """No swept list: one case with the line's pretension 10 N, the drive's 5 mm/s and the line's N = 2.  A swept N
    beyond the links is refused by ChainLine naming n_masses.  Bug caught: a default taken from the wrong field."""
    line = ChainLine(n_links=8, n_masses=2, pretension_N=10.0)
    (case,) = sweep_cases(line, Drive("ramp", v=5.0), 0.5)
    assert (case["pretension_N"], case["v"], case["n_masses"]) == (10.0, 5.0, 2)
    assert case["line"] == line and case["drive"] == Drive("ramp", v=5.0)
    with pytest.raises(ValueError, match=r"^n_masses = 9 is invalid: valid range 1 .. n_links = 8"):
        sweep_cases(line, Drive("ramp", v=5.0), 0.5, n_masses=[9])


def test_a_serial_sweep_of_lines_at_rest_keeps_each_pretension():
    """Lines held at the drive (law none) in their pre-tensioned static state stay there: for pretensions 500 and
    1500 N (× N = 2, 3) the drive-end mean tension over the last quarter is the pretension and its ripple 0
    (tolerance 1e-6 of the pretension); the rows come back in product order with the swept values; as_table's
    default columns are (pretension, v, N, peak, dynamic factor, ripple).
    Bugs caught: the swept pretension not used, the rows out of order, the default keys of the table."""
    line = ChainLine(n_links=6, n_masses=2, pretension_N=100.0)
    rows = sweep(line, Drive("none"), 0.01, pretensions=[500.0, 1_500.0], n_masses=[2, 3], scheduler="serial",
                 progress=False, n_out=40)
    assert [(r["pretension_N"], r["n_masses"]) for r in rows] == [(500.0, 2), (500.0, 3), (1_500.0, 2), (1_500.0, 3)]
    for r in rows:
        P = r["pretension_N"]
        assert r["drive_tension_mean_N"] == pytest.approx(P, rel=1e-6)
        assert abs(r["drive_tension_ripple_N"]) <= 1e-6 * P
        assert r["peak_tension_N"] == pytest.approx(P, rel=1e-6)
    tab = as_table(rows)
    assert tab.shape == (4, 6)
    np.testing.assert_array_equal(tab[:, :3], [[500.0, 0.0, 2.0], [500.0, 0.0, 3.0], [1_500.0, 0.0, 2.0],
                                               [1_500.0, 0.0, 3.0]])
    np.testing.assert_allclose(tab[:, 3], [500.0, 500.0, 1_500.0, 1_500.0], rtol=1e-6)
    np.testing.assert_allclose(tab[:, 5], 0.0, atol=1.5e-3)
