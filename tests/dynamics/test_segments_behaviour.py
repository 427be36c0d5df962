"""Segment tensions and stored energy of the extended spring (chainid.dynamics.segments.segment_tensions and
segment_energy with the spring table): a linear contact spring (β = 1: F = a/(c_lin + c_h)) shifted by a slack and
a linear dead band (p = 1: F_d = k_d·(|u| − g)), so every number is a hand computation.  Units mm, N, s."""
from __future__ import annotations

import numpy as np
import pytest

from chainid.dynamics.segments import segment_energy, segment_tensions

CL, CH, S = 0.01, 0.02, 0.1  # β = 1: F = (e − s)/0.03 N for e > s
KD, G = 100.0, 0.05  # dead band centred at x_c = 0: F_d = 100·(e − 0.05) for e > 0.05
NO_Q, NO_TABS = np.zeros((3, 0, 3)), np.zeros((0, 2, 2))


def _table(n, kd=KD, xc=0.0):
    return np.tile([1.0, S, kd, G, 1.0, xc], (n, 1))


def _run(u, v, us, cd, sp, dvs=None, tangent=True, hf=None, hx=None, hd=None, ys=None, k0=0.0):
    n = len(u) - 1
    hf = np.zeros((n, 0)) if hf is None else hf
    hx = np.zeros((n, 0)) if hx is None else hx
    hd = np.zeros((n, 0), dtype=np.int64) if hd is None else hd
    ys = np.zeros(hf.shape) if ys is None else ys
    out = dict(y=np.zeros(hf.shape), dv=np.zeros(n), T=np.zeros(n), Fk=np.zeros(n), ks=np.full(n, k0),
               cs=np.full(n, k0))
    dD, peak, low = segment_tensions(np.asarray(u), np.asarray(v), np.asarray(us), np.zeros(n), np.full(n, CL),
                                     np.full(n, CH), np.full(n, cd), hf, hx, hd, np.zeros(hf.shape + (3,)), sp,
                                     NO_TABS, True, ys, np.zeros(n) if dvs is None else dvs, out["y"], out["dv"],
                                     out["T"], out["Fk"], out["ks"], out["cs"], 0, tangent)
    return dD, peak, low, out


def test_a_dead_band_alone_keeps_a_segment_taut_while_its_spring_is_slack():
    """Elongations e = 0.05, 0.08, 0.3 mm (u = 0.43, 0.38, 0.3, 0 from rest; node 3 moves at −1 mm/s; dampers
    2 N·s/mm).  Segment 1: spring slack (a = −0.05), band at its edge → T = 0.  Segment 2: spring slack (a = −0.02)
    but the band carries 100·0.03 = 3 N → T = 3 N, tangent 100 N/mm, damping 2.  Segment 3: a = 0.2 → 0.2/0.03 N,
    band 100·0.25 = 25 N, damper 2·1 = 2 N → T = 20/3 + 27 N, tangent 1/0.03 + 100 N/mm.  Elastic forces Fk = 0, 3,
    20/3 + 25; dissipation the damper's trapezoid ½·(0 + 2)·0.3 = 0.3 N·mm (by hand).
    Bugs caught: taut only when the spring AND the band pull, the band's tangent dropped, its centre column."""
    u, v = [0.43, 0.38, 0.3, 0.0], [0.0, 0.0, 0.0, -1.0]
    dD, peak, low, out = _run(u, v, np.zeros(4), 2.0, _table(3))
    np.testing.assert_allclose(out["T"], [0.0, 3.0, 20 / 3 + 27.0], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(out["Fk"], [0.0, 3.0, 20 / 3 + 25.0], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(out["ks"], [0.0, 100.0, 1 / 0.03 + 100.0], rtol=1e-12)
    assert out["cs"].tolist() == [0.0, 2.0, 2.0]
    np.testing.assert_allclose(out["dv"], [0.0, 0.0, 2.0], atol=1e-12)
    assert dD == pytest.approx(0.3, rel=1e-12)
    assert peak == pytest.approx(20 / 3 + 27.0, rel=1e-12) and low == 0.0


def test_a_shifted_dead_band_and_the_newton_outputs_without_tangent():
    """The band centred at x_c = 0.2 mm: at e = 0.3 it is inside (|0.1| − 0.05 → 0.05 mm: 5 N), at e = 0.12 it
    pushes the other way (u = −0.08: −3 N) and the spring is slack (a = 0.02 → 0.02/0.03 N, minus 3: the sum
    −2.33 N cannot pull): T = 0.  Without ``tangent`` the tangent outputs are left alone (their nan start).
    Bugs caught: x_c not subtracted, the sign of the band below its centre, tangents written without asking."""
    dD, peak, low, out = _run([0.42, 0.12, 0.0], [0.0, 0.0, 0.0], np.zeros(3), 0.0, _table(2, xc=0.2)[:2],
                              tangent=False, k0=np.nan)
    np.testing.assert_allclose(out["T"], [0.2 / 0.03 + 5.0, 0.0], rtol=1e-12)
    np.testing.assert_allclose(out["Fk"], [0.2 / 0.03 + 5.0, 0.02 / 0.03 - 3.0], rtol=1e-12)
    np.testing.assert_allclose(out["dv"], [0.0, -(0.02 / 0.03 - 3.0)], rtol=1e-12)
    assert np.isnan(out["ks"]).all() and np.isnan(out["cs"]).all()


def test_stored_energy_of_shifted_springs_dead_bands_and_a_held_play():
    """segment_energy with the spring table: U = a²/(2·0.03) for a = e − s > 0 plus the band's k_d·(|u| − g)²/2.
    e = 0.05, 0.08, 0.3 mm: 0 + 0, 0 + 100·0.03²/2, 0.2²/0.06 + 100·0.25²/2 (by hand).  With a play (kind 4) in
    column 0 holding its output at 0.25 mm while e = 0.3, the spring's argument is 0.25 − 0.1 = 0.15 (not e − s),
    and a Jenkins element (f 10 N, stick 0.1 mm, slider at 0.28) stores 10/0.1·0.02²/2.
    Bugs caught: the play's output ignored (argument e − s), the band's potential dropped, the slack not shifted."""
    u = np.array([0.43, 0.38, 0.3, 0.0])
    n = 3
    empty = np.zeros((n, 0))
    U = segment_energy(u, np.zeros(n), np.full(n, CL), np.full(n, CH), empty, empty, np.zeros((n, 0), dtype=np.int64),
                       _table(n), True, empty)
    assert U == pytest.approx(100 * 0.03 ** 2 / 2 + 0.2 ** 2 / 0.06 + 100 * 0.25 ** 2 / 2, rel=1e-12)
    hf, hx = np.array([[0.0, 10.0]]), np.array([[0.2, 0.1]])
    hd, y = np.array([[4, 0]], dtype=np.int64), np.array([[0.25, 0.28]])
    U = segment_energy(np.array([0.3, 0.0]), np.zeros(1), np.array([CL]), np.array([CH]), hf, hx, hd,
                       _table(1, kd=0.0), True, y)
    assert U == pytest.approx(0.15 ** 2 / 0.06 + 0.5 * 100.0 * 0.02 ** 2, rel=1e-12)


def test_a_slack_segment_releases_its_jenkins_slider_with_the_extended_spring():
    """Extended spring, one Jenkins element (f 10 N, stick 0.1 mm: 100 N/mm) per segment, slider 0.02 mm behind e at
    the start (2 N).  The segment shortens from e = 0.3 to 0.04 mm (below the slack 0.1 and the band's reach): it
    carries nothing, the slider is put at e = 0.04 and its stored 100·0.02²/2 = 0.02 N·mm is dissipated; dv is
    −(F_s + F_d) at the end = 0, so the damper's trapezoid adds nothing (by hand).
    Bugs caught: the released slider kept, the stored energy not counted, a ``>`` of the release test flipped."""
    hf, hx = np.array([[10.0]]), np.array([[0.1]])
    hd = np.zeros((1, 1), dtype=np.int64)
    ys = np.array([[0.28]])
    dD, peak, low, out = _run([0.04, 0.0], [0.0, 0.0], np.array([0.3, 0.0]), 0.0, _table(1), hf=hf, hx=hx, hd=hd,
                              ys=ys)
    assert out["T"].tolist() == [0.0] and out["y"][0, 0] == pytest.approx(0.04, rel=1e-15)
    assert out["ks"].tolist() == [0.0] and out["dv"].tolist() == [0.0]
    assert dD == pytest.approx(0.5 * 100.0 * 0.02 ** 2, rel=1e-9)
    assert (peak, low) == (0.0, 0.0)
