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
