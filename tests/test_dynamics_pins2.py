"""More pins of the dynamics package (issue 20 §5, own mutation seeds of mutH), each against a closed form.
Units: mm, mm/s, N, kg, s."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.dynamics import ChainLine, Drive, simulate


def _one_mass(M, scheme):
    """One segment (one link) held at the drive, a tensioner carriage of M kg on node 1: a one-degree-of-freedom
    oscillator of mass m_1 = M + ½·(segment mass) and stiffness k_e(T) + k_t."""
    line = ChainLine(n_links=1, n_masses=1, pretension_N=2_000.0, tensioner_stiffness=300.0, tail_mass_kg=M)
    cl, ch = line.segment_coefficients()
    k = 1.0 / (cl[0] + (2.0 / 3.0) * ch[0] * 2_000.0 ** (-1.0 / 3.0)) + 300.0  # tangent at the pretension [N/mm]
    m1 = line.node_masses()[1]
    w = math.sqrt(1e3 * k / m1)
    u0 = 1e-4  # small: the kernel's curvature shifts the frequency by O(u0·k'/k), here < 1e-5
    res = simulate(line, Drive("none"), 4 * 2 * math.pi / w, n_out=400, scheme=scheme,
                   initial_u=np.array([0.0, u0]), dt=2 * math.pi / w / 400 if scheme == "implicit" else None)
    return res, u0, w, m1


@pytest.mark.parametrize("scheme", ["explicit", "implicit"])
def test_a_heavy_carriage_oscillates_at_sqrt_k_over_m(scheme):
    """u_1(t) = u0·cos(ωt) with ω = sqrt(1e3·(k_e + k_t)/m_1) (a = 1e3·f/m mm/s² for f in N and m in kg), m_1 =
    399.9 + 0.1 = 400 kg, where 1e3/m_1 = 2.5 is not a whole number.  Four periods: the displacement against the
    closed form within 1 % of u0 (step error of Verlet at T/400 and of the trapezoidal rule: < 0.1 %).
    Bug caught: the inverse mass 1e3/m made a floor division (1e3 // 400 = 2: ω 11 % low)."""
    res, u0, w, m1 = _one_mass(399.9, scheme)
    assert m1 == pytest.approx(400.0, rel=1e-12)
    np.testing.assert_allclose(res.u[:, 1], u0 * np.cos(w * res.t), atol=0.01 * u0)


def test_implicit_newton_on_the_exact_tangent_needs_a_few_iterations_and_no_halving():
    """A taut chain (8 segments at 5 kN, tensioner 200 N/mm; a 0.02 mm 20 Hz drive keeps every tension within
    5 kN ± 25 N) at 20 × the explicit stable step: Newton's method on the exact tridiagonal tangent converges
    quadratically, so every step is accepted whole (no rejected or halved sub-step) within a handful of iterations
    (the module's "2-4 iterations"; at most 6 allowed here).  A wrong tangent (a dropped off-diagonal coupling
    term) converges linearly at best: steps are rejected and halved.
    Bug caught: the super-diagonal's spring term taken only beyond the last segment (`i >= N`)."""
    from chainid.dynamics import stable_step
    from chainid.dynamics.integrators import run
    from chainid.dynamics.simulation import core_arguments

    line = ChainLine(n_links=40, n_masses=8, pretension_N=5_000.0, tensioner_stiffness=200.0)
    dt = 20 * stable_step(line)
    drive = Drive("sine", A=0.02, omega=2 * math.pi * 20)
    args, outs = core_arguments(line, drive, dt, 400, 4)
    status, _ = run(True, *args, *outs)
    stats = outs[-1]
    assert status == 0 and outs[1].min() > 4_950.0 and outs[1].max() < 5_050.0  # taut throughout
    assert (stats[0], stats[1]) == (400, 0) and stats[3] == 1.0  # 400 whole steps accepted, none rejected
    assert 1 <= stats[2] <= 6  # the largest Newton iteration count of any step
    res = simulate(line, drive, 400 * dt, dt=dt, scheme="implicit", n_out=100)
    assert res.rejected == 0 and res.substeps == res.n_steps


@pytest.mark.parametrize("scheme", ["explicit", "implicit"])
def test_drive_force_is_the_drive_node_inertia_plus_the_first_tension(scheme):
    """SimResult.drive_force = m_0·a_0·1e-3 + T_1 [N] (the force the drive applies to node 0), with the sine drive's
    a_0 = −A ω² sin(ωt) by hand and m_0 = ½ × a segment of 5 links × 50 mm × 4 kg/m = 0.5 kg; at t = 0 it is the
    pretension (5 kN).  Bug caught: the inertia term's sign, units or the drive's acceleration garbled."""
    line = ChainLine(n_links=20, n_masses=4, pretension_N=5_000.0)
    A, w = 0.2, 2 * math.pi * 40
    res = simulate(line, Drive("sine", A=A, omega=w), 0.1, n_out=50, scheme=scheme)
    m0 = line.node_masses()[0]
    assert m0 == pytest.approx(0.5 * 5 * 50.0 * line.chain.mass_per_m * 1e-3, rel=1e-12)
    want = 1e-3 * m0 * (-A * w * w * np.sin(w * res.t)) + res.tension[:, 0]
    np.testing.assert_allclose(res.drive_force, want, rtol=1e-12, atol=1e-9)
    assert res.drive_force[0] == pytest.approx(5_000.0, rel=1e-12)
    assert np.ptp(1e-3 * m0 * A * w * w * np.sin(w * res.t)) > 1.0  # the inertia term is not negligible here


def _seg_arrays(N, n_el):
    return dict(y=np.zeros((N, n_el)), dv=np.zeros(N), T=np.zeros(N), Fk=np.zeros(N), ks=np.zeros(N), cs=np.zeros(N))


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


def test_elastic_energy_is_the_integral_of_the_kernel_force():
    """U(e) = ∫₀^e F_k de' (scipy's quad over the generated kernel) for a segment of 16 links at 0.05–1 mm; 0 when
    slack; the array form sums the segments.  Bug caught: a coefficient of the closed form (½ c_lin, ⅗ c_hertz)."""
    from scipy.integrate import quad

    from chainid.dynamics.energy import elastic_energy, elastic_energy_array
    from chainid.generated.stiffness_paper import force

    cl, ch = ChainLine(n_links=16, n_masses=1).segment_coefficients()
    for e in (0.05, 0.3, 1.0):
        ref = quad(lambda s: force(s, cl[0], ch[0]), 0.0, e, epsabs=0, epsrel=1e-12, limit=200)[0]
        assert elastic_energy(e, cl[0], ch[0]) == pytest.approx(ref, rel=1e-9)
    assert elastic_energy(-0.2, cl[0], ch[0]) == 0.0
    arr = elastic_energy_array(np.array([0.3, -0.1, 1.0]), np.repeat(cl, 3), np.repeat(ch, 3))
    assert arr == pytest.approx(elastic_energy(0.3, cl[0], ch[0]) + elastic_energy(1.0, cl[0], ch[0]), rel=1e-12)


def test_balance_scale_index_and_a_run_where_nothing_happens():
    """The scale is the largest of |W|, |ΔE_kin|, |ΔE_el| and |D| over the run (here D = 40 N·mm leads); without
    times the worst point is given by its output index; nothing happening (all zero) is a relative error of 0."""
    from chainid.dynamics.energy import balance

    W = np.array([0.0, 20.0, 30.0])
    kin = np.array([5.0, 5.0, 5.0])
    el = np.array([1.0, -9.0, -11.0])  # ΔE_el = 0, −10, −12
    D = np.array([0.0, 29.0, 40.0])  # residual W − ΔE_kin − ΔE_el − D = 0, 1, 2
    eb = balance(W, kin, el, D)
    assert eb["scale"] == 40.0 and eb["worst_residual"] == 2.0 and eb["worst_t_s"] == 2.0
    assert eb["relative_error"] == pytest.approx(2.0 / 40.0, rel=1e-15)
    assert (eb["work_in"], eb["kinetic"], eb["elastic"], eb["dissipated"]) == (30.0, 0.0, -12.0, 40.0)
    z = np.zeros(3)
    still = balance(z, z + 7.0, z + 3.0, z, np.array([0.0, 1.0, 2.0]))
    assert still["relative_error"] == 0.0 and still["scale"] == 0.0 and still["finite"] is True


def test_mode_shapes_normalised_positive_at_their_largest_and_placed_at_the_free_nodes():
    """modes(): each shape solves 1e3·K φ = ω² M φ (the dense tangent system), is scaled to max |φ| = 1 with that
    largest entry +1; the free nodes of a tensioner line of 4 segments of 5 links are 1..4 at 250, 500, 750,
    1000 mm (50 mm pitch; a fixed end drops node 4); f = ω/2π; n_modes beyond the free nodes gives them all;
    n_modes must be an int >= 1."""
    from chainid.dynamics.modes import modes, tangent_system

    line = ChainLine(n_links=20, n_masses=4, pretension_N=2_000.0, tensioner_stiffness=50.0)
    md = modes(line)
    M, K, nodes = tangent_system(line)
    for j in range(4):
        phi, w = md.shapes[:, j], md.omega[j]
        np.testing.assert_allclose(1e3 * K @ phi, w * w * M * phi, rtol=1e-9, atol=1e-9 * w * w * M.max())
        assert np.max(np.abs(phi)) == pytest.approx(1.0, rel=1e-15) and phi[np.argmax(np.abs(phi))] == 1.0
    assert md.nodes.tolist() == [1, 2, 3, 4] and md.positions.tolist() == [250.0, 500.0, 750.0, 1000.0]
    np.testing.assert_allclose(md.frequency_hz, md.omega / (2 * math.pi), rtol=1e-15)
    assert np.all(np.diff(md.omega) > 0)
    assert modes(line, n_modes=9).omega.size == 4 and modes(line, n_modes=2).shapes.shape == (4, 2)
    fixed = modes(ChainLine(n_links=20, n_masses=4, pretension_N=2_000.0, far_end="fixed"))
    assert fixed.nodes.tolist() == [1, 2, 3] and fixed.positions.tolist() == [250.0, 500.0, 750.0]
    for bad in (0, 2.0, True):
        with pytest.raises(ValueError, match=rf"^n_modes = {bad!r} is invalid: valid range None or an int >= 1$"):
            modes(line, n_modes=bad)


# ---------------------------------------------------------------- survivors of the blind seed-23 run
@pytest.mark.parametrize("far_end", ["fixed", "tensioner"])
def test_resistance_is_shared_over_the_moving_nodes_by_mass(far_end):
    """R_i ∝ the lumped mass of each moving node, summing to R: node 0 (the drive's) carries none, and a fixed far
    end (it does not move) none either.  4 segments, half lumping, tail mass 2 kg: masses m/2, m, m, m, m/2 + 2
    (m = one segment's mass); R = 100 N.  Bug caught: ``far_end == "fixed"`` → ``< "fixed"`` (a fixed end's
    node kept its share)."""
    from chainid.dynamics import ChainLine

    line = ChainLine(n_links=8, n_masses=4, far_end=far_end, resistance_N=100.0, tail_mass_kg=2.0)
    ms = line.chain.mass_per_m * line.segment_lengths()[0] * 1e-3
    w = np.array([0.0, ms, ms, ms, 0.5 * ms + 2.0])
    if far_end == "fixed":
        w[-1] = 0.0
    np.testing.assert_allclose(line.resistance_per_node(), 100.0 * w / w.sum(), rtol=1e-12)
    assert line.resistance_per_node().sum() == pytest.approx(100.0, rel=1e-12)


def test_work_estimate_counts_an_implicit_node_step_as_eight_explicit():
    """``estimate``: node-steps = steps × nodes, × IMPLICIT_COST = 8 for the implicit scheme (its docstring:
    Newton's 2–4 iterations of kernel, tangent and solve), seconds at 3e7 node-steps/s; 1000 steps of a
    5-segment line (6 nodes): 6000 explicit, 48 000 implicit.  Bug caught: the cost 8 → 7."""
    from chainid.dynamics import ChainLine
    from chainid.dynamics.simulation import estimate

    line = ChainLine(n_links=10, n_masses=5)
    assert estimate(line, 1000, 10)["node_steps"] == 6000.0
    imp = estimate(line, 1000, 10, scheme="implicit")
    assert imp["node_steps"] == 48_000.0 and imp["seconds"] == pytest.approx(48_000.0 / 3e7, rel=1e-12)


def test_an_explicit_step_above_the_stable_one_names_the_load_it_was_computed_at():
    """``simulate(..., scheme="explicit", dt=...)`` with dt at twice the stable step is refused before any work,
    the message giving the valid range and the load the stable step belongs to: "at peak_force = 5000 N" when a
    peak force is given, "at any load" when not.  Bug caught (seed 25): the text's ``%`` → ``|`` (a TypeError
    traceback instead of the one-line error, only when a peak force is given)."""
    from chainid.dynamics.simulation import stable_step

    line = ChainLine(n_links=40, n_masses=8, pretension_N=2_000.0)
    for peak, text in ((5000.0, "peak_force = 5000 N"), (None, "any load")):
        dts = stable_step(line, peak)
        with pytest.raises(ValueError, match=rf"0 < dt <= {dts:.6g} s \(the explicit stable step at {text}\); use a "
                                             r"smaller dt or scheme='implicit'"):
            simulate(line, Drive("none"), 1.0, dt=2.0 * dts, scheme="explicit", peak_force=peak)
