"""Pins of the moving resistance f = −R·clip(v/ε, −1, 1) in both integrators' helpers (issue 20 §5).

``_external`` (the implicit scheme's force) and ``_resist`` (the explicit scheme's closed-form backward-Euler
update) are checked against hand numbers; each test fails under the bug its docstring names.
Units: mm, mm/s, N, kg, s.
"""
from __future__ import annotations

import numpy as np
import pytest

from chainid.dynamics.integrators import _external, _resist
from chainid.dynamics import ChainLine, Drive, simulate


def test_external_resistance_viscous_below_eps_coulomb_above():
    """R = 10 N, ε = 1 mm/s: v = 0.5 → −5 N (viscous branch), 2 → −10 N, −3 → +10 N (saturated), 0 → 0.
    Bugs caught: either clip bound changed or dropped, the sign, v/ε made v·ε."""
    v = np.array([0.0, 0.5, 2.0, -3.0, -0.25])
    u = np.zeros(5)
    res = np.array([0.0, 10.0, 10.0, 10.0, 10.0])
    fe = np.zeros(5)
    none_i, none_f = np.zeros(0, dtype=np.int64), np.zeros(0)
    _external(0.0, u, v, res, 1.0, none_i, none_f, none_f, False, 0.0, 0.0, fe, True)
    np.testing.assert_allclose(fe, [0.0, -5.0, -10.0, 10.0, 2.5], rtol=0, atol=1e-12)
    _external(0.0, u, v, res, 2.0, none_i, none_f, none_f, False, 0.0, 0.0, fe, True)  # ε = 2 mm/s
    np.testing.assert_allclose(fe, [0.0, -2.5, -10.0, 10.0, 1.25], rtol=0, atol=1e-12)


def test_external_tensioner_and_load_steps():
    """Tensioner: −(F_t + k_t·u_N) on the last node; a load step acts from t_on on (t >= t_on).
    Bugs caught: k_t dropped, the load's switch-on made strict or inverted."""
    u = np.array([0.0, 0.0, 2.0])
    v = np.zeros(3)
    fe = np.zeros(3)
    _external(0.1, u, v, np.zeros(3), 1.0, np.array([1], dtype=np.int64), np.array([50.0]), np.array([0.1]),
              True, 300.0, 40.0, fe, True)
    np.testing.assert_allclose(fe, [0.0, -50.0, -(300.0 + 40.0 * 2.0)], atol=1e-12)
    _external(0.0999, u, v, np.zeros(3), 1.0, np.array([1], dtype=np.int64), np.array([50.0]), np.array([0.1]),
              True, 300.0, 0.0, fe, True)
    np.testing.assert_allclose(fe, [0.0, 0.0, -300.0], atol=1e-12)


def test_resist_closed_form_update():
    """α = dt·1e3·R/m = 1e-4·1e3·1/2 = 0.05 mm/s.  v* = 0.2: w = 0.2/(1 + 0.05/1) (viscous);
    v* = 5: w = 4.95 (Coulomb); v* = −0.1: w = −0.1/1.05.  The returned work is ½·m·(w² − v*²)·1e-3 summed.
    Node 0 (the drive) is left alone.  Bugs caught: the branch test, α's factors, the sign of the saturated
    step, the node range."""
    v = np.array([7.0, 0.2, 5.0, -0.1])
    m = np.array([1.0, 2.0, 2.0, 2.0])
    res = np.array([1.0, 1.0, 1.0, 1.0])
    w_expect = np.array([7.0, 0.2 / 1.05, 4.95, -0.1 / 1.05])
    dW = _resist(v, m, res, 1.0, 1e-4, 3)
    np.testing.assert_allclose(v, w_expect, rtol=1e-14)
    expect = sum(0.5e-3 * mm * (w * w - vs * vs) for mm, w, vs in zip(m[1:], w_expect[1:], [0.2, 5.0, -0.1]))
    assert dW == pytest.approx(expect, rel=1e-12)
    v2 = np.array([0.0, -5.0])
    _resist(v2, np.array([1.0, 2.0]), np.array([0.0, 1.0]), 1.0, 1e-4, 1)
    assert v2[1] == pytest.approx(-4.95, rel=1e-14)


def test_implicit_scheme_creeps_viscously_near_standstill():
    """The implicit scheme uses _external: a free node creeping at |v| < ε decays as exp(−t/τ), τ = ε·m/(1e3·R).
    Bug caught: the viscous branch of _external (only the explicit scheme's _resist was covered)."""
    line = ChainLine(n_links=10, n_masses=1, pretension_N=0.0, far_end="tensioner", tail_mass_kg=2.0,
                     resistance_N=3.0, resistance_v_eps=1.0)
    m1 = line.node_masses()[1]
    tau = m1 / (1e3 * 3.0)
    res = simulate(line, Drive("none"), 2 * tau, dt=tau / 2000, scheme="implicit", initial_u=np.array([0.0, 5.0]),
                   initial_v=np.array([0.0, 0.8]), n_out=100)
    np.testing.assert_allclose(res.v[:, 1], 0.8 * np.exp(-res.t / tau), rtol=2e-3)


def test_polygon_drive_acceleration_is_the_derivative_of_velocity():
    """Chordal action at constant sprocket speed: a = R cos φ θ̈ − R sin φ θ̇² with θ̈ = 0, i.e. a = dv/dt
    (numerical derivative, away from the tooth changes); at φ = 0 the acceleration is 0.
    Bug caught: θ̇² garbled (θ̇/θ̇)."""
    import math

    from chainid.dynamics.drives import drive_motion

    p, z, v = 50.0, 8, 400.0
    d = Drive("polygon", v=v, z=z, pitch=p)
    t = np.linspace(0.3, 0.3 + p / v, 4001)
    u, vel, acc = drive_motion(d, t, p)
    dv = np.gradient(vel, t)
    R = p / (2 * math.sin(math.pi / z))
    thd = 2 * math.pi / (z * p) * v
    assert np.max(np.abs(acc)) == pytest.approx(R * math.sin(math.pi / z) * thd ** 2, rel=1e-4)  # at φ = ±π/z
    amax = np.max(np.abs(acc))
    smooth = np.abs(np.gradient(acc)) < 0.05 * amax  # not at a tooth change (a jumps from −a_max to +a_max)
    smooth[:5] = smooth[-5:] = False
    np.testing.assert_allclose(acc[smooth], dv[smooth], rtol=2e-3, atol=1e-3 * amax)


def test_balance_of_a_non_finite_run_reports_the_last_residual():
    """A run whose energy went non-finite mid-way: ``finite`` False, ``residual`` the last value (3 N·mm here),
    not an earlier one.  Bug caught: res[1] for res[-1]."""
    import math

    from chainid.dynamics.energy import balance

    z = np.zeros(4)
    eb = balance(np.array([0.0, 1.0, np.nan, 3.0]), z, z, z)
    assert eb["finite"] is False and eb["residual"] == 3.0 and math.isnan(eb["relative_error"])


@pytest.mark.parametrize("kw", [dict(hysteresis=((3_000.0, 200.0),)), dict(dahl=((200.0, 0.05),))])
def test_slack_release_of_hysteretic_elements_keeps_the_balance(kw):
    """A sine drive larger than the pretension's elongation makes segments go slack every cycle; the energy held
    in a Jenkins element (½·(F/x)·(e − y)²) or a Dahl element (½·(F_h/x_h)·(z·x_h/F_h)²) at release is
    dissipated.  With slack events the scheme's balance error at the default step is 6.0e-3 (Jenkins) and
    4.1e-3 (Dahl), falling with dt (3.4e-3 / 2.4e-3 at safety 0.1; simulate warns, as it should, above 1e-3);
    with the two release energies swapped it is 3.0e-2 and 1.0.  Hence the bound 1e-2.
    Bug caught: the release energies of the two element kinds swapped."""
    import math
    import warnings

    line = ChainLine(n_links=100, n_masses=10, pretension_N=500.0, far_end="fixed", **kw)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # the 1e-3 convergence warning (see above)
        res = simulate(line, Drive("sine", A=1.5, omega=300.0), 6 * 2 * math.pi / 300.0, n_out=2000)
    eb = res.energy_balance()
    assert res.tension.min() == 0.0  # segments went slack
    assert eb["relative_error"] < 1e-2


def test_viscous_equivalent_of_a_law_at_the_operating_point():
    """A law object is evaluated at (ω, A, x0): Eq. 21 with α = (0.01, 0.2, 3, 4, 5) at ω = 10, A = 0.5 gives
    c_e = 1 + 2 + 0.75 + 2 + 5 = 10.75 N·s/mm (by hand); a number is taken as c_e itself.
    Bug caught: the law's first (only) value not the one taken."""
    from chainid.dynamics.model import viscous_equivalent
    from chainid.model.laws import PolynomialLaw

    assert viscous_equivalent(PolynomialLaw([0.01, 0.2, 3.0, 4.0, 5.0]), 10.0, 0.5, 2.0) == pytest.approx(10.75,
                                                                                                        rel=1e-12)
    assert viscous_equivalent(7, 10.0, 0.5, 2.0) == 7.0
    with pytest.raises(ValueError, match="c_e"):
        viscous_equivalent(PolynomialLaw([0.0, 0.0, 0.0, 0.0, -1.0]), 10.0, 0.5, 2.0)


def test_default_output_is_500_steps_besides_t0():
    """simulate stores at most n_out = 500 samples besides t = 0 by default (documented); a run much shorter than
    the stable step takes exactly t_end/500 per step, so the output is t = k·t_end/500, k = 0 … 500."""
    line = ChainLine(n_links=20, n_masses=2, pretension_N=1000.0)
    res = simulate(line, Drive("none"), 1e-6)
    np.testing.assert_allclose(res.t, np.arange(501) * 1e-6 / 500, rtol=1e-9, atol=1e-18)
    assert simulate(line, Drive("none"), 1e-6, n_out=7).t.size == 8


def test_figures_show_the_result_in_kN_and_m():
    """The heat map is segment tension [kN] at segment mid-points [m]; the drive plot has segment 1's tension,
    the drive force and the static level in kN with the peak and dynamic factor in the title; the mode plot
    starts each shape at the drive (0 at 0 m) and labels its frequency (hand-made result, 2 segments)."""
    from types import SimpleNamespace

    import matplotlib.pyplot as plt

    from chainid.dynamics.plots import plot_drive_tension, plot_heatmap, plot_modes

    res = SimpleNamespace(t=np.array([0.0, 0.1, 0.2]), positions=np.array([0.0, 1000.0, 3000.0]),
                          tension=np.array([[1e3, 2e3], [3e3, 4e3], [5e3, 6e3]]), drive_force=np.array([0.0, 7e3, 8e3]),
                          static_tension=2500.0, peak_tension=6000.0, dynamic_factor=2.4)
    fig = plot_heatmap(res)
    mesh = fig.axes[0].collections[0]
    np.testing.assert_allclose(np.asarray(mesh.get_array()).reshape(2, 3), res.tension.T * 1e-3)
    # cells centred on the mid-points 0.5 and 2 m (half their spacing, 0.75 m, either side)
    assert fig.axes[0].get_ylim() == (pytest.approx(-0.25), pytest.approx(2.75))
    plt.close(fig)
    fig = plot_drive_tension(res)
    ax = fig.axes[0]
    seg, drive, static = ax.lines
    np.testing.assert_allclose(seg.get_ydata(), [1.0, 3.0, 5.0])
    np.testing.assert_allclose(drive.get_ydata(), [0.0, 7.0, 8.0])
    assert static.get_ydata()[0] == pytest.approx(2.5)
    assert ax.get_title() == "Drive-end tension (peak 6 kN, dynamic factor 2.4)"
    plt.close(fig)
    res.static_tension = 0.0  # no steady level: no line
    fig = plot_drive_tension(res)
    assert len(fig.axes[0].lines) == 2
    plt.close(fig)
    md = SimpleNamespace(positions=np.array([1000.0, 2000.0]), omega=np.array([10.0, 20.0, 30.0]),
                         shapes=np.array([[0.5, 1.0, 0.2], [1.0, -1.0, 0.3]]), frequency_hz=np.array([1.6, 3.2, 4.8]))
    fig = plot_modes(md, n=2)
    lines = fig.axes[0].lines
    assert len(lines) == 2 and [ln.get_label() for ln in lines] == ["mode 1: 1.6 Hz", "mode 2: 3.2 Hz"]
    np.testing.assert_allclose(lines[1].get_xdata(), [0.0, 1.0, 2.0])
    np.testing.assert_allclose(lines[1].get_ydata(), [0.0, 1.0, -1.0])
    plt.close(fig)


def test_node_masses_half_and_drive_lumping_with_a_tail_mass():
    """20 links of the built-in chain in 4 segments of 5 links: each segment m_s = mass_per_m·5·pitch·1e-3 kg.
    `half`: m_s/2 at the ends, m_s inside; `drive`: m_s on each drive-side node; the tail mass 5 kg on the far-end
    node only (by hand)."""
    from chainid.chain.spec import default_chain

    c = default_chain()
    ms = c.mass_per_m * 5 * c.pitch * 1e-3
    half = ChainLine(n_links=20, n_masses=4, tail_mass_kg=5.0).node_masses()
    np.testing.assert_allclose(half, [ms / 2, ms, ms, ms, ms / 2 + 5.0], rtol=1e-12)
    drive = ChainLine(n_links=20, n_masses=4, tail_mass_kg=5.0, lumping="drive").node_masses()
    np.testing.assert_allclose(drive, [ms, ms, ms, ms, 5.0], rtol=1e-12)


def test_slack_substeps_and_fallbacks_are_counted_apart():
    """A slack line (20 N pretension, 1 mm at 60 rad/s) goes slack in many sub-steps; without dampers the explicit
    scheme never needs its implicit fallback (documented: Newton stuck at a damper jump), so that count is 0."""
    import warnings

    line = ChainLine(n_links=40, n_masses=4, pretension_N=20.0, far_end="fixed")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # the energy-balance check of this coarse run
        res = simulate(line, Drive("sine", A=1.0, omega=60.0), 0.2)
    assert res.slack_substeps > 0 and res.explicit_fallbacks == 0
    s = res.summary()
    assert s["slack_substeps"] == res.slack_substeps and s["explicit_fallback_substeps"] == 0


@pytest.mark.parametrize("z", [3, 6, 11])
def test_drive_max_speed_closed_form_and_sampled(z):
    """Largest drive speed [mm/s]: a polygon of z teeth at mean speed v̄ moves its chain at R·θ̇·cos φ with
    R = p/(2 sin(π/z)), θ̇ = 2π v̄/(z p), so at most v̄·(π/z)/sin(π/z) (z = 6: π/3 / ½ = 2.0944 v̄); a sine at A·ω,
    a ramp at v.  Checked against the closed form and against the drive's own motion sampled over one tooth
    period after the ramp (another method).  Polygon period p/v̄ [s], inf at v̄ = 0.
    Bugs caught: the polygon's sin(π/z) argument, the sine's A·ω, the ramp's v."""
    from chainid.dynamics.drives import drive_motion

    v, pitch = 1000.0, 50.0
    d = Drive(law="polygon", v=v, t_ramp=0.0, z=z)
    hand = v * (np.pi / z) / np.sin(np.pi / z)
    assert d.max_speed(pitch) == pytest.approx(hand, rel=1e-12)
    period = d.polygon_period(pitch)
    assert period == pytest.approx(pitch / v, rel=1e-12)
    t = np.linspace(2.0 * period, 3.0 * period, 4001)
    _, speed, _ = drive_motion(d, t, pitch)
    assert speed.max() == pytest.approx(hand, rel=1e-6)
    assert Drive(law="polygon", v=0.0, z=z).polygon_period(pitch) == np.inf
    assert Drive(law="polygon", v=v, z=z, pitch=20.0).polygon_period(pitch) == pytest.approx(0.02, rel=1e-12)
    assert Drive(law="sine", A=3.0, omega=7.0).max_speed(pitch) == pytest.approx(21.0, rel=1e-12)
    assert Drive(law="ramp", v=250.0, t_ramp=1.0).max_speed(pitch) == 250.0


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


def test_unconverged_peak_warning_quotes_the_run_at_twice_the_step():
    """With ``refine = 1`` a slack polygon drive (undamped, P = 500 N, z = 6) whose peak is not converged stops
    after one halving, and its warning quotes the final peak at dt and the peak of the run at 2·dt, which is
    checked here against a separate run at that step without refinement (another run, not the refined one's
    state); the change is |p(dt) − p(2dt)| / p(dt).
    Bugs caught: the refinement loop running past its last attempt (the "twice that step" peak became the final
    one)."""
    import re
    import warnings

    line = ChainLine(n_links=200, n_masses=20, pretension_N=500.0)
    d = Drive("polygon", v=1500.0, t_ramp=0.2, z=6)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        res = simulate(line, d, 0.5, refine=1)
        coarse = simulate(line, d, 0.5, dt=2.0 * res.dt, refine=0)
    assert res.refinements == 1
    msg = next(m for m in res.warnings if m.startswith("peak tension not converged"))
    got = re.search(r": (\S+) N at dt = (\S+) s vs (\S+) N at twice that step \((\S+) % > 2 %\)", msg)
    assert got, msg
    p1, h, p0, pct = (float(g) for g in got.groups())
    assert p1 == pytest.approx(res.peak_tension, rel=1e-5) and h == pytest.approx(res.dt, rel=1e-2)
    assert p0 == pytest.approx(coarse.peak_tension, rel=1e-5) and abs(p0 - p1) > 0.02 * p1
    assert pct == pytest.approx(100 * abs(coarse.peak_tension - res.peak_tension) / res.peak_tension, rel=1e-2)


def test_energy_balance_of_a_non_finite_run_reports_the_final_changes():
    """A run whose energies turn non-finite still reports the final work and the final changes of the stored
    energies (kinetic 1 → 3 → 6: +5 N·mm; elastic 2 → 2 → 7: +5), with nan for the worst residual and its scale.
    Bug caught: the kinetic change read at the second-to-last output."""
    from chainid.dynamics.energy import balance

    eb = balance(np.array([0.0, 1.0, np.inf]), np.array([1.0, 3.0, 6.0]), np.array([2.0, 2.0, 7.0]),
                 np.array([0.0, 1.0, 2.0]), np.array([0.0, 0.1, 0.2]))
    assert eb["finite"] is False and eb["work_in"] == np.inf
    assert (eb["kinetic"], eb["elastic"], eb["dissipated"]) == (5.0, 5.0, 2.0)
    assert all(np.isnan(eb[k]) for k in ("worst_residual", "worst_t_s", "relative_error", "scale"))


def test_modes_of_a_line_without_a_free_node_are_empty():
    """One segment with a fixed far end has no free node: every array of the modes is empty (the documented
    "empty arrays when no node is free"), for any n_modes."""
    from chainid.dynamics.modes import modes

    line = ChainLine(n_links=10, n_masses=1, pretension_N=1_000.0, far_end="fixed")
    for n in (None, 3):
        md = modes(line, n_modes=n)
        assert md.omega.shape == (0,) and md.frequency_hz.shape == (0,) and md.shapes.shape == (0, 0)
        assert md.nodes.shape == (0,) and md.positions.shape == (0,)
