"""The report's Table 1 analysis (chainid.report.table1), by hand from Table 1 as printed in the paper (typed here)
and the docstring's rules: ω = (π/10)·column, W = π·F_ac·A, the A-slope over tests 3, 6–9, the ω-slope over tests
2–5, test 1 shown apart.  Units mm, N, rad/s, N·mm."""
from __future__ import annotations

import math

import numpy as np
import pytest

from stand_ins import LinearSpring

# Table 1 as printed (test, ω column, x0 mm, A mm, F_ac N, c_e N·s/mm)
TABLE1 = [(1, 1, 2.2, 0.25, 8000, 5095.5), (2, 4, 2.2, 0.25, 1100, 3503.2), (3, 6, 2.2, 0.25, 1335, 2834.4),
          (4, 8, 2.2, 0.25, 1465, 2332.8), (5, 10, 2.2, 0.25, 1542, 1964.3), (6, 6, 2.15, 0.2, 985, 2614.1),
          (7, 6, 2.25, 0.3, 1643, 2906.9), (8, 6, 2.3, 0.35, 2017, 3058.8), (9, 6, 2.35, 0.4, 2329, 3090.5)]


def _loglog_slope(x, y):
    return float(np.polyfit(np.log(x), np.log(y), 1)[0])


def test_table1_distances_test1_slopes_and_loss_factors_by_hand():
    """The distance of (slope_A, slope_ω) to each reference form (viscous (2, 1), hysteretic (2, 0), Coulomb (1, 0),
    micro-slip (3, 0)); test 1's ω-slope over tests 1–5 as printed and with its F_ac from its c_e (c_e·ω·A); the
    loss factor η = F_ac/(k_e(x0)·A) per test (k_e = 1e4 N/mm here); which tests each fit uses."""
    from chainid.report.table1 import table1_analysis

    t = table1_analysis(LinearSpring(1e4))
    test, col, x0, A, Fac, ce = (np.array(c, dtype=float) for c in zip(*TABLE1))
    w = col * math.pi / 10
    W = math.pi * Fac * A
    iA, iw = np.isin(test, [3, 6, 7, 8, 9]), np.isin(test, [2, 3, 4, 5])
    sA, sw = _loglog_slope(A[iA], W[iA]), _loglog_slope(w[iw], W[iw])
    assert (t["slope_A"], t["slope_omega"]) == (pytest.approx(sA, rel=1e-12), pytest.approx(sw, rel=1e-12))
    forms = {"viscous": (2, 1), "hysteretic": (2, 0), "Coulomb": (1, 0), "micro-slip": (3, 0)}
    assert t["distance_to_forms"] == pytest.approx({k: math.hypot(a - sA, b - sw) for k, (a, b) in forms.items()},
                                                   rel=1e-12)
    i15 = test <= 5
    assert t["test1"]["slope_omega_tests_1_5_as_printed"] == pytest.approx(_loglog_slope(w[i15], W[i15]), rel=1e-12)
    W1 = W.copy()
    W1[0] = math.pi * (ce[0] * w[0] * A[0]) * A[0]
    assert t["test1"]["slope_omega_tests_1_5_with_F_ac_from_c_e"] == pytest.approx(_loglog_slope(w[i15], W1[i15]),
                                                                                   rel=1e-12)
    assert t["test1"]["F_ac_N"] == 8000.0 and t["test1"]["omega_rad_s"] == pytest.approx(math.pi / 10, rel=1e-12)
    rows = t["tests"]
    np.testing.assert_allclose([r["loss_factor"] for r in rows], Fac / (1e4 * A), rtol=1e-12)
    np.testing.assert_allclose([r["W_Nmm"] for r in rows], W, rtol=1e-12)
    assert [r["test"] for r in rows if r["in_A_fit"]] == t["tests_A"] == [3, 6, 7, 8, 9]
    assert [r["test"] for r in rows if r["in_omega_fit"]] == t["tests_omega"] == [2, 3, 4, 5]
    c = np.polyfit(np.log(A[iA]), np.log(ce[iA]), 1)[0]
    assert t["c_e_exponent_A"] == pytest.approx(c, rel=1e-12)


def test_the_joint_energy_slopes_are_those_of_tests_2_to_9_by_hand():
    """``joint``: log W = a·log A + b·log ω + c by least squares over tests 2–9 (test 1 left out, as the docstring
    says), solved here from the printed table.  Seed-29 survivor: ``test >= 2`` → ``test != 2`` (test 1 in, test 2
    out) went through every test."""
    from chainid.report.table1 import table1_analysis

    t = table1_analysis(LinearSpring(1e4))
    test, col, x0, A, Fac, ce = (np.array(c, dtype=float) for c in zip(*TABLE1))
    keep = test >= 2
    X = np.column_stack([np.log(A[keep]), np.log(col[keep] * math.pi / 10), np.ones(int(keep.sum()))])
    a, b, _ = np.linalg.lstsq(X, np.log(math.pi * Fac[keep] * A[keep]), rcond=None)[0]
    assert t["joint"]["slope_A"] == pytest.approx(a, rel=1e-9)
    assert t["joint"]["slope_omega"] == pytest.approx(b, rel=1e-9)
