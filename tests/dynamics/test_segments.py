"""Segment tensions (chainid.dynamics.segments) with Jenkins, Dahl and viscous elements and the benchmark's floor
springs, and their Newton tangent, by hand.  Units mm, N, s."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.dynamics import ChainLine


def _seg_arrays(N, n_el):
    return dict(y=np.zeros((N, n_el)), dv=np.zeros(N), T=np.zeros(N), Fk=np.zeros(N), ks=np.zeros(N), cs=np.zeros(N))


@pytest.mark.slow
def test_segment_tensions_and_newton_tangent_with_jenkins_and_dahl_by_hand():
    """segments.tensions on two segments (e = 0.501 mm after a step of +0.001 mm; dampers 5 N·s/mm; per segment
    a Jenkins element f = 10 N, stick travel 0.01 mm, k = 1000 N/mm, unstressed at the start, and a Dahl element
    F_h = 20 N, x_h = 0.1 mm from z = 0).  By hand: the Jenkins element sticks, z = 1000·0.001 = 1 N, tangent
    1000; Dahl z = 20(1 − e^(−0.01)), tangent (F_h/x_h)(1 − z/F_h); T = F_k(e) + c·ė + Σz; the Newton tangent
    k_e(e) + Σ tangents, damping c; dissipation: Dahl's (work − stored) + the trapezoidal damper work.
    A third call with the second segment slack (e = −0.01 mm) and its elements stressed (Jenkins 2 N, Dahl 5 N):
    it carries nothing, its tangent and damping are 0, the elements are released (y = e, z = 0) and their stored
    energy ½k w² (1000·0.002²/2 + 200·0.025²/2) is dissipated.
    Bugs caught: the sticking test of the tangent, the Dahl tangent's sign or factor, the release."""
    from chainid.dynamics.segments import tensions
    from chainid.generated.stiffness_paper import force, stiffness

    cl, ch = ChainLine(n_links=32, n_masses=2).segment_coefficients()
    hf, hx = np.array([[10.0, 20.0]] * 2), np.array([[0.01, 0.1]] * 2)
    hd = np.array([[0, 1]] * 2, dtype=np.int64)
    cd = np.array([5.0, 5.0])
    us, u = np.zeros(3), np.array([0.002, 0.001, 0.0])
    v = np.array([3.0, 1.0, 0.0])
    epre = np.array([0.5, 0.5])
    ys = np.array([[0.5, 0.0], [0.5, 0.0]])
    out = _seg_arrays(2, 2)
    dD, peak, low = tensions(u, v, us, epre, cl, ch, cd, hf, hx, hd, ys, np.zeros(2), out["y"], out["dv"], out["T"],
                             out["Fk"], out["ks"], out["cs"], 0, True)
    zd = 20.0 * (1.0 - math.exp(-0.01))
    dahl_loss = (20.0 * 0.001 - 20.0 * 0.1 * (1.0 - math.exp(-0.01))) - zd * zd * 0.1 / 40.0
    for j, rate in ((0, 2.0), (1, 1.0)):
        Fk = force(0.501, cl[j], ch[j])
        assert out["T"][j] == pytest.approx(Fk + 5.0 * rate + 1.0 + zd, rel=1e-12)
        assert out["ks"][j] == pytest.approx(stiffness(0.501, cl[j], ch[j]) + 1000.0 + 200.0 * (1.0 - zd / 20.0),
                                             rel=1e-12)
        assert out["cs"][j] == 5.0 and out["dv"][j] == pytest.approx(5.0 * rate, rel=1e-12)
        assert out["y"][j, 0] == 0.5 and out["y"][j, 1] == pytest.approx(zd, rel=1e-12)
    assert dD == pytest.approx(2 * dahl_loss + 0.5 * 10.0 * 0.001 + 0.5 * 5.0 * 0.001, rel=1e-9)
    assert (peak, low) == (out["T"].max(), out["T"].min())
    # the second segment slack at the end of the step, its elements stressed at the start
    u2 = np.array([0.002, 0.001, 0.511])  # e_2 = 0.5 + 0.001 − 0.511 = −0.01
    ys2 = np.array([[0.5, 0.0], [0.5 - 0.002, 5.0]])  # segment 2 starts at e = 0.5: Jenkins stretched 0.002 mm
    out = _seg_arrays(2, 2)
    dv_start = np.array([0.0, 7.0])
    dD, peak, low = tensions(u2, v, us, epre, cl, ch, cd, hf, hx, hd, ys2, dv_start, out["y"], out["dv"], out["T"],
                             out["Fk"], out["ks"], out["cs"], 0, True)
    assert out["T"][1] == 0.0 and out["ks"][1] == 0.0 and out["cs"][1] == 0.0 and low == 0.0
    assert out["y"][1, 0] == pytest.approx(-0.01, abs=1e-15) and out["y"][1, 1] == 0.0
    de2 = 0.001 - 0.511
    Fk2 = force(-0.01, cl[1], ch[1])
    released = 0.5 * 1000.0 * 0.002 ** 2 + 0.5 * 200.0 * (5.0 * 0.1 / 20.0) ** 2
    assert out["dv"][1] == pytest.approx(-Fk2, abs=1e-12)
    assert dD == pytest.approx(dahl_loss + 0.5 * 10.0 * 0.001 + released + 0.5 * (7.0 - Fk2) * de2, rel=1e-9)


def test_viscous_only_segments_clip_at_zero_and_go_slack_by_hand():
    """The explicit scheme's viscous-only path: T = F_k(e) + c·ė when e > 0 and that is > 0, else 0 (a damper
    cannot push; a slack segment carries nothing); the damper force stored is T − F_k; peak and lowest tension."""
    from chainid.dynamics.segments import tensions
    from chainid.generated.stiffness_paper import force

    cl, ch = ChainLine(n_links=48, n_masses=3).segment_coefficients()
    epre = np.array([0.3, 0.3, 0.3])
    u = np.array([0.0, 0.0, 0.0, 0.4])  # e = 0.3, 0.3, −0.1
    v = np.array([0.0, 0.0, 1e6, 0.0])  # ė = 0, −1e6 (the damper would push), 1e6 (slack anyway)
    cd = np.full(3, 2.0)
    out = _seg_arrays(3, 0)
    empty = np.zeros((3, 0))
    dD, peak, low = tensions(u, v, np.zeros(4), epre, cl, ch, cd, empty, empty, np.zeros((3, 0), dtype=np.int64),
                             empty, np.zeros(3), out["y"], out["dv"], out["T"], out["Fk"], out["ks"], out["cs"], 0,
                             False)
    F0 = force(0.3, cl[0], ch[0])
    assert out["T"].tolist() == [pytest.approx(F0, rel=1e-12), 0.0, 0.0]
    assert out["dv"][0] == pytest.approx(0.0, abs=1e-9) and out["dv"][1] == pytest.approx(-force(0.3, cl[1], ch[1]))
    assert peak == pytest.approx(F0, rel=1e-12) and low == 0.0


def test_benchmark_floor_springs_by_hand():
    """The benchmark floors of the segment law (``kind`` 1: T = cbrt(e)/c_lin, ``kind`` 2: T = e/c_lin, both 0
    for e <= 0; e_j = e_pre,j + u_j − u_{j+1}) against hand numbers on three segments.
    Bugs caught: a wrong neighbour node in e, the slack branch, the cube root."""
    from chainid.dynamics.segments import tensions

    u = np.array([0.0, -8.0, -9.0, -2.0])
    epre = np.array([0.0, 0.0, 0.0])  # e = 8, 1, −7 mm
    cl = np.array([2.0, 0.5, 1.0])
    n = 3
    empty = np.zeros((n, 0))
    for kind, hand in ((1, [2.0 / 2.0, 1.0 / 0.5, 0.0]), (2, [8.0 / 2.0, 1.0 / 0.5, 0.0])):
        T, Fk, dv = np.zeros(n), np.zeros(n), np.zeros(n)
        _, peak, low = tensions(u, np.zeros(4), u, epre, cl, cl, np.zeros(n), empty, empty,
                                np.zeros((n, 0), dtype=np.int64), empty, np.zeros(n), empty.copy(), dv, T, Fk,
                                np.zeros(n), np.zeros(n), kind, False)
        np.testing.assert_allclose(T, hand, rtol=1e-12, atol=0)
        assert (peak, low) == (max(hand), 0.0)
