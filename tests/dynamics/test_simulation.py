"""chainid.dynamics.simulate: the lumped chain against independent references (the kernel, eigh, the energy balance,
a one-mass oscillator), step grids and defaults, the stable step, the drive force.  Units mm, N, s, kg."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.chain.spec import default_chain
from chainid.dynamics import ChainLine, Drive, LoadStep, drive_motion, simulate, stable_step
from chainid.dynamics.modes import modes
from chainid.model import kernels
from chainid.model.base import ChainModel
from chainid.records.simulate import TestSpec, simulate_test


def test_segments_sum_to_the_whole_chain_kernel():
    """Segments in series have exactly the compliance of the whole chain (spec with n = n_links), any N."""
    chain = default_chain()
    line = ChainLine(n_links=47, n_masses=5, chain=chain, pretension_N=1.0)
    c_lin, c_h = line.segment_coefficients()
    cl_all, ch_all = kernels.coefficients(chain.replace(n=47))
    assert list(line.links_per_segment()) == [10, 10, 9, 9, 9]
    assert c_lin.sum() == pytest.approx(cl_all, rel=1e-12)
    assert c_h.sum() == pytest.approx(ch_all, rel=1e-12)
    F = 12_000.0  # N: the series elongation at F equals the whole chain's x(F)
    x_seg = c_lin * F + c_h * F ** (2 / 3)
    assert x_seg.sum() == pytest.approx(kernels.displacement(F, chain.replace(n=47)), rel=1e-12)
    # mass: 47 links of 50 mm at 4 kg/m = 9.4 kg, whatever the lumping
    assert line.node_masses().sum() == pytest.approx(47 * 50e-3 * 4.0, rel=1e-12)


@pytest.mark.slow
def test_variants_share_the_kernel_math():
    """The integrators call stiffness_paper's scalar kernels with a variant's coefficients: same math."""
    from chainid.generated import stiffness_inner_bend as ib
    from chainid.generated import stiffness_paper as pa
    x = np.linspace(-0.1, 3.0, 31)
    c = kernels.coefficients(default_chain(), "inner_bend")
    np.testing.assert_array_equal(ib.force_array(x, *c), pa.force_array(x, *c))


def test_one_segment_reproduces_the_paper_test_model():
    """N = 1, harmonic drive, fixed far end, whole mass at the drive: F = m·ẍ + F_k(x) + c_e·ẋ (chainid simulate)."""
    chain = default_chain()  # 16 links, 3.2 kg
    w, x0, A, c_e = 2.5, 0.8, 0.3, 40.0  # rad/s, mm, mm, N·s/mm
    F0 = float(kernels.force(x0, chain))
    line = ChainLine(n_links=16, n_masses=1, chain=chain, pretension_N=F0, far_end="fixed", lumping="drive",
                     damping=c_e)
    T = 2 * math.pi / w
    res = simulate(line, Drive("sine", A=A, omega=w), 6 * T, n_out=1200)
    rec = simulate_test(TestSpec("t", w, x0, A), ChainModel(chain), c_e, n_cycles=6, samples_per_cycle=200)
    assert res.t.size == 1201 and rec.t.size == 1200
    np.testing.assert_allclose(res.t[:1200], rec.t, rtol=0, atol=1e-9)
    # from t > 0: simulate_test's first sample (t = 0) takes ẋ = 0 before the oscillation starts
    np.testing.assert_allclose(res.drive_force[1:1200], rec.F[1:], rtol=0, atol=1e-8 * np.max(np.abs(rec.F)))


def _modal_frequency(q, t):
    """Frequency [Hz] of a sampled oscillation from its first and last upward zero crossings (interpolated)."""
    s = np.sign(q)
    idx = np.nonzero((s[:-1] < 0) & (s[1:] >= 0))[0]
    tc = t[idx] - q[idx] * (t[idx + 1] - t[idx]) / (q[idx + 1] - q[idx])
    return (tc.size - 1) / (tc[-1] - tc[0])


@pytest.mark.parametrize("scheme", ["explicit", "implicit"])
def test_small_oscillations_match_eigh(scheme):
    """Free vibration about a pretension of modes 1 and 2: simulated frequencies = eigh within 0.5 %."""
    line = ChainLine(n_links=60, n_masses=6, pretension_N=20_000.0, far_end="fixed")
    md = modes(line)
    M = line.node_masses()[md.nodes]
    u0 = np.zeros(line.n_nodes)
    u0[md.nodes] = 1e-3 * (md.shapes[:, 0] + md.shapes[:, 1])  # mm, tiny vs e_pre ~ 1 mm
    f1 = md.frequency_hz[0]
    dt = 0.02 / (2 * math.pi * md.frequency_hz[-1])  # (ω_max·dt = 0.02: dispersion ~ 2e-5)
    res = simulate(line, Drive("none"), 25 / f1, dt=dt, scheme=scheme, n_out=8000, initial_u=u0)
    U = res.u[:, md.nodes]
    for k in (0, 1):
        q = U @ (M * md.shapes[:, k])  # mass-weighted projection on mode k
        assert _modal_frequency(q, res.t) == pytest.approx(md.frequency_hz[k], rel=5e-3)
    assert md.frequency_hz[1] > 1.5 * md.frequency_hz[0]


def test_energy_balance_without_damping():
    line = ChainLine(n_links=200, n_masses=20, pretension_N=3_000.0, far_end="tensioner", tensioner_stiffness=5.0,
                     loads=(LoadStep(node=12, force_N=2_000.0, t_on=0.05),))
    # the residual is the scheme's O(dt²) shadow-energy error (the load step's jump dominates): 7.6e-4 at
    # 0.9·dt_stable, 1.7e-8 at dt = 2 µs; half the stable step keeps it well inside the 1e-3 requirement
    res = simulate(line, Drive("ramp", v=800.0, t_ramp=0.05), 0.2, peak_force=20_000.0, safety=0.45)
    eb = res.energy_balance()
    assert eb["dissipated"] == 0.0
    assert eb["work_in"] > 1e4  # N·mm: the drive did work
    assert eb["relative_error"] < 1e-3


def test_energy_balance_with_damping_and_damper_work():
    """Dissipation = ∫ Σ c_j ė_j² dt computed independently from the stored node speeds (no clipping here)."""
    line = ChainLine(n_links=100, n_masses=10, pretension_N=5_000.0, far_end="fixed", damping=20.0)
    w = 300.0  # rad/s, below the first natural frequency (696 rad/s)
    res = simulate(line, Drive("sine", A=0.2, omega=w), 10 * 2 * math.pi / w, n_out=100000)
    eb = res.energy_balance()
    assert res.tension.min() > 0  # taut throughout: the damper law is plain viscous
    assert eb["dissipated"] > 0.9 * eb["work_in"] > 0  # 10 whole cycles: the work in is dissipated
    assert eb["relative_error"] < 1e-3
    c = line.segment_damping()
    edot = res.v[:, :-1] - res.v[:, 1:]
    P = (c[None, :] * edot ** 2).sum(axis=1)
    D_indep = np.sum(0.5 * (P[1:] + P[:-1]) * np.diff(res.t))
    assert res.dissipated[-1] == pytest.approx(D_indep, rel=1e-3)


def _slack_line(damping):
    return ChainLine(n_links=100, n_masses=10, pretension_N=0.0, far_end="tensioner", tensioner_stiffness=200.0,
                     damping=damping)


def test_slack_start_picks_up_tension_without_blow_up():
    """Chain started 1 mm slack per segment, spring take-up: no compression, tension picks up and settles."""
    line = _slack_line(20.0)
    u0 = 1.0 * np.arange(line.n_nodes)  # mm: every segment 1 mm short of taut (e = -1 mm)
    res = simulate(line, Drive("ramp", v=500.0, t_ramp=0.0), 0.2, initial_u=u0, peak_force=50_000.0)
    e = line.pretension_elongation()[None, :] + res.u[:, :-1] - res.u[:, 1:]
    assert np.all(e[0] == -1.0) and res.tension[0].max() == 0.0
    assert np.all(np.isfinite(res.tension)) and res.tension.min() >= 0.0
    assert np.all(res.tension[e <= 0] == 0.0)  # a slack segment carries nothing, never compression
    # settled: every segment carries the take-up spring force k_t·u_N (quasi-static, 1 %)
    np.testing.assert_allclose(res.tension[-1], 200.0 * res.u[-1, -1], rtol=1e-2)
    assert res.tension[-1].min() > 10_000.0


def test_slack_start_peak_within_the_energy_bound():
    """Without damping T = F_k, and no segment can store more than the work done: U(T_peak) <= max W_in."""
    from scipy.optimize import brentq
    line = _slack_line(0.0)
    u0 = 1.0 * np.arange(line.n_nodes)
    res = simulate(line, Drive("ramp", v=500.0, t_ramp=0.0), 0.1, initial_u=u0, peak_force=50_000.0, n_out=5000)
    c_lin, c_h = line.segment_coefficients()
    j = int(np.argmax(res.tension.max(axis=0)))

    def U(F):  # N·mm: ∫ F dx of x = c_lin F + c_h F^(2/3), by hand
        return F * (c_lin[j] * F + c_h[j] * F ** (2 / 3)) - c_lin[j] * F ** 2 / 2 - 0.6 * c_h[j] * F ** (5 / 3)

    F_bound = brentq(lambda F: U(F) - res.work_in.max(), 0.0, 1e7)
    assert 1_000.0 < res.peak_tension <= F_bound


def test_polygon_drive_kinematics():
    """Chordal action: u advances one pitch per p/v, mean speed v, speed ratio 1/cos(π/z), v = du/dt."""
    p, z, v = 50.0, 8, 400.0
    d = Drive("polygon", v=v, z=z, pitch=p)
    P = p / v
    t = np.linspace(0.3, 0.3 + P, 4001)
    u, vel, acc = drive_motion(d, t, p)
    assert u[-1] - u[0] == pytest.approx(p, rel=1e-12)
    assert vel.max() / vel.min() == pytest.approx(1 / math.cos(math.pi / z), rel=1e-5)
    assert vel.max() == pytest.approx(v * (math.pi / z) / math.sin(math.pi / z), rel=1e-6)
    np.testing.assert_allclose(np.gradient(u, t)[5:-5], vel[5:-5], rtol=1e-4)
    u2, _, _ = drive_motion(d, t + P, p)
    np.testing.assert_allclose(u2 - u, p, rtol=1e-12)


@pytest.mark.parametrize("make, field", [
    (lambda: ChainLine(n_links=10, n_masses=0), "n_masses"),
    (lambda: ChainLine.from_length(-200.0, 4), "length_mm"),
    (lambda: Drive("trapezoid"), "law"),
    (lambda: ChainLine(n_links=10, n_masses=2, far_end="free"), "far_end"),
    (lambda: ChainLine(n_links=10, n_masses=2, pretension_N=-1.0), "pretension_N"),
    (lambda: simulate(ChainLine(n_links=10, n_masses=2), Drive("ramp", v=1.0), -1.0), "t_end"),
])
def test_bad_input(make, field):
    with pytest.raises(ValueError, match=field):
        make()


def test_explicit_step_above_stable_is_refused():
    line = ChainLine(n_links=40, n_masses=8, pretension_N=1_000.0)
    dts = stable_step(line)
    with pytest.raises(ValueError, match=r"dt = .*valid range 0 < dt <="):
        simulate(line, Drive("ramp", v=100.0), 0.01, dt=1.5 * dts)
    res = simulate(line, Drive("ramp", v=100.0), 0.01, dt=1.5 * dts, scheme="implicit")  # the stiff option
    assert np.all(np.isfinite(res.tension))


def test_stable_step_is_the_linear_chain_limit():
    """Uniform chain, tensioner end: ω_max ≤ 2·√(1e3·k/m) (Gershgorin), so dt = 2/ω_max = √(m/(1e3 k))."""
    line = ChainLine(n_links=100, n_masses=10, pretension_N=0.0)
    k = 1 / line.segment_coefficients()[0][0]
    m = line.node_masses()[1]
    assert stable_step(line) == pytest.approx(math.sqrt(m / (1e3 * k)), rel=1e-12)


def test_steady_running_tension_carries_the_resistance():
    """Running at speed: T_j = pretension + the resistance of the nodes behind segment j (statics, 1 %)."""
    line = ChainLine(n_links=200, n_masses=20, pretension_N=2_000.0, resistance_N=3_000.0, damping=20.0)
    res = simulate(line, Drive("ramp", v=500.0, t_ramp=0.2), 1.5, peak_force=10_000.0)
    R = line.resistance_per_node()
    expected = line.pretension_N + np.cumsum(R[::-1])[::-1][1:]  # segment j pulls nodes j+1..N
    assert expected[0] == pytest.approx(2_000.0 + 3_000.0)
    np.testing.assert_allclose(res.tension[-1], expected, rtol=1e-2)
    assert res.v[-1, 1:] == pytest.approx(np.full(line.n_masses, 500.0), rel=1e-2)
    assert res.energy_balance()["relative_error"] < 1e-3
    assert res.dynamic_factor == pytest.approx(res.peak_tension / 5_000.0)


def test_implicit_and_explicit_agree_on_a_start_up():
    line = ChainLine(n_links=100, n_masses=10, pretension_N=1_000.0, resistance_N=500.0, damping=10.0)
    d = Drive("ramp", v=300.0, t_ramp=0.05)
    a = simulate(line, d, 0.2, peak_force=5_000.0, n_out=20)
    b = simulate(line, d, 0.2, scheme="implicit", dt=a.dt, n_out=20)
    np.testing.assert_allclose(b.tension, a.tension, rtol=0, atol=1e-2 * a.peak_tension)
    assert b.energy_balance()["relative_error"] < 1e-3


@pytest.mark.slow
def test_cli_dynamics_json_and_plots(tmp_path, capsys):
    import json

    from chainid.cli import main
    out = tmp_path / "dyn.json"
    argv = ["dynamics", "--links", "100", "--masses", "10", "--pretension", "1000", "--speed", "200",
            "--t-ramp", "0.05", "--t-end", "0.1", "--json", str(out), "--plots", str(tmp_path / "figs"), "--quiet"]
    assert main(argv) == 0
    doc = json.loads(out.read_text())
    assert doc["summary"]["peak_tension_N"] >= 1000.0 and len(doc["modes"]["frequency_hz"]) == 4
    assert sorted(p.name for p in (tmp_path / "figs").iterdir()) == [
        "dynamics_drive_tension.png", "dynamics_heatmap.png", "dynamics_modes.png"]
    before = out.read_text()
    assert main(argv) == 2  # exists, no --force: refused before any work, file untouched
    assert "exists" in capsys.readouterr().err and out.read_text() == before
    assert main(["dynamics", "--masses", "0"]) == 2
    assert "n_masses = 0" in capsys.readouterr().err


def test_sweep_product_order_serial():
    from chainid.dynamics.sweeps import sweep
    line = ChainLine(n_links=60, n_masses=6, pretension_N=1_000.0)
    rows = sweep(line, Drive("ramp", v=100.0, t_ramp=0.02), 0.05, pretensions=[1_000.0, 2_000.0],
                 speeds=[100.0, 200.0], n_masses=[3, 6], scheduler="serial", progress=False, peak_force=5_000.0)
    assert [(r["pretension_N"], r["v"], r["n_masses"]) for r in rows] == [
        (p, v, n) for p in (1_000.0, 2_000.0) for v in (100.0, 200.0) for n in (3, 6)]
    assert all(r["peak_tension_N"] >= r["pretension_N"] for r in rows)


def test_stable_step_with_peak_force_damping_dahl_and_tensioner_spring_by_hand():
    """Two segments of two links, tensioner end with k_t = 500 N/mm, c_e = 30 N·s/mm of the 16-link specimen, one
    Dahl element (F_h = 40 N, x_h = 0.08 mm), peak 5 kN: by hand, segment tangent k_j = 1/(c_lin,j + ⅔·c_h,j·F^(-1/3))
    plus the Dahl element at a reversal 2F_h/(x_h·2/16); dampers c_j = 30·16/2; node 1: ω² = 2e3(k_1 + k_2)/m_1,
    2e3(c_1 + c_2)/m_1; node 2 (the tensioner): 2e3(k_2 + k_t/2)/m_2, 2e3·c_2/m_2; with the largest of each,
    ζ = λ_c/(2ω) and dt = (2/ω)(√(1+ζ²) − ζ).  A fixed end drops node 2.
    Bugs caught: the peak-force tangent, the Dahl factor 2, the tensioner's k_t/2, the damping's ζ."""
    from chainid.dynamics import stable_step

    line = ChainLine(n_links=4, n_masses=2, pretension_N=1_000.0, tensioner_stiffness=500.0, damping=30.0,
                     dahl=((40.0, 0.08),))
    cl, ch = line.segment_coefficients()
    F = 5_000.0
    k = 1.0 / (cl + (2.0 / 3.0) * ch * F ** (-1.0 / 3.0)) + 2.0 * 40.0 / (0.08 * 2 / 16)
    c = np.full(2, 30.0 * 16 / 2)
    m = line.node_masses()

    def dt_of(nodes):
        w2 = max(2e3 * (k[i - 1] + (k[i] if i < 2 else 250.0)) / m[i] for i in nodes)
        lam = max(2e3 * (c[i - 1] + (c[i] if i < 2 else 0.0)) / m[i] for i in nodes)
        w = math.sqrt(w2)
        z = lam / (2 * w)
        return 2 / w * (math.sqrt(1 + z * z) - z)

    assert stable_step(line, peak_force=F) == pytest.approx(dt_of((1, 2)), rel=1e-12)
    fixed = ChainLine(n_links=4, n_masses=2, pretension_N=1_000.0, far_end="fixed", damping=30.0,
                      dahl=((40.0, 0.08),))
    assert stable_step(fixed, peak_force=F) == pytest.approx(dt_of((1,)), rel=1e-12)
    assert stable_step(ChainLine(n_links=4, n_masses=1, far_end="fixed")) == math.inf


def test_simulate_step_grid_defaults_static_reference_and_bounds():
    """simulate's documented step and output grid, by hand: dt = 3e-4 s for t_end = 0.01 s is 33.3 steps → 34,
    stored every ceil(34/10) = 4th step with n_out = 10, so 36 steps of 0.01/36 s and 10 samples ending at t_end;
    default dt 0.9·dt_stable (explicit) or min(10·dt_stable, t_end/1000) (implicit), at most t_end/n_out; the static
    reference is the running tension for ramp/polygon drives and the pretension otherwise (dynamic factor nan at 0);
    bounds of safety, n_out, substep_levels, refine and the initial state's shape.
    Bugs caught: the grid's rounding, the defaults' constants, the static rule, the bounds."""
    import warnings

    from chainid.dynamics import stable_step

    line = ChainLine(n_links=40, n_masses=4, pretension_N=1_000.0, resistance_N=200.0)
    ramp = Drive("ramp", v=50.0, t_ramp=0.005)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # a coarse step: the balance warning is not under test
        res = simulate(line, ramp, 0.01, dt=3e-4, n_out=10, peak_force=3_000.0)
    assert res.n_steps == 36 and res.dt == pytest.approx(0.01 / 36, rel=1e-12)
    np.testing.assert_allclose(res.t, np.arange(10) * 4 * 0.01 / 36, rtol=1e-12, atol=1e-15)
    assert res.static_tension == 1_200.0 and res.dynamic_factor == pytest.approx(res.peak_tension / 1_200.0)
    dts = stable_step(line)
    res = simulate(line, ramp, 0.05, n_out=2)  # 0.9·dts is below 0.05/2
    assert res.dt == pytest.approx(0.05 / math.ceil(0.05 / (0.9 * dts) - 1e-9), rel=1e-12)
    res = simulate(line, ramp, 0.01, n_out=20, scheme="implicit")
    assert res.dt == pytest.approx(min(10 * dts, 0.01 / 1000), rel=1e-9)
    res = simulate(line, ramp, 0.05, n_out=2, safety=0.5)
    assert res.dt == pytest.approx(0.05 / math.ceil(0.05 / (0.5 * dts) - 1e-9), rel=1e-12)
    sine = simulate(line, Drive("sine", A=0.01, omega=100.0), 0.005, n_out=5)
    assert sine.static_tension == 1_000.0
    slack = simulate(ChainLine(n_links=40, n_masses=4), Drive("sine", A=0.01, omega=100.0), 0.005, n_out=5)
    assert slack.static_tension == 0.0 and math.isnan(slack.dynamic_factor)
    for kw, message in ((dict(safety=1.0001), "safety = 1.0001 is invalid: valid range 0 < safety <= 1"),
                        (dict(n_out=1), "n_out = 1 is invalid: valid range an int >= 2"),
                        (dict(substep_levels=21), "substep_levels = 21 is invalid: valid range an int 0 .. 20"),
                        (dict(refine=11), "refine = 11 is invalid: valid range an int 0 .. 10"),
                        (dict(initial_u=np.zeros(4)), "initial_u = 'array of shape (4,)' is invalid: valid range "
                                                      "finite values, shape (5,) (one per node)")):
        with pytest.raises(ValueError) as exc:
            simulate(line, ramp, 0.01, **kw)
        assert str(exc.value) == message


def test_default_output_is_500_steps_besides_t0():
    """simulate stores at most n_out = 500 samples besides t = 0 by default (documented); a run much shorter than
    the stable step takes exactly t_end/500 per step, so the output is t = k·t_end/500, k = 0 … 500."""
    line = ChainLine(n_links=20, n_masses=2, pretension_N=1000.0)
    res = simulate(line, Drive("none"), 1e-6)
    np.testing.assert_allclose(res.t, np.arange(501) * 1e-6 / 500, rtol=1e-9, atol=1e-18)
    assert simulate(line, Drive("none"), 1e-6, n_out=7).t.size == 8


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


def test_memory_estimate_per_stored_sample_covers_the_result_it_returns():
    """``estimate``'s bytes grow by the outputs of a stored sample: at least what the returned SimResult holds per
    sample (t, drive force and 4 energies, a tension per segment, u and v per node: 8·(2·nodes + segments + 6)
    bytes), and not more than half as much again (the run's own buffers per stored sample)."""
    from chainid.dynamics import ChainLine
    from chainid.dynamics.simulation import estimate

    line = ChainLine(n_links=40, n_masses=4, pretension_N=1_000.0)
    res = simulate(line, Drive("ramp", v=100.0), 0.01, dt=1e-4, n_out=10)
    n = res.t.size
    held = sum(v.nbytes for v in vars(res).values() if isinstance(v, np.ndarray) and v.shape[0] == n) / n
    assert held == 8 * (2 * line.n_nodes + line.n_masses + 6)
    per = estimate(line, 100, 2000)["bytes"] - estimate(line, 100, 1000)["bytes"]
    assert held <= per / 1000 <= 1.5 * held


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


def test_stable_step_with_a_contact_exponent_and_a_take_up_spring_by_hand():
    """Two segments, contact exponent β = 1.4 (x = c_lin·F + c_h·F^β, the last segment one contact short), peak
    force 2 kN, tensioner end with a take-up spring k_t = 5 N/mm, no damping: each segment's tangent
    k_j = 1/(c_lin,j + β·c_h,j·F^(β−1)), and Gershgorin over the free nodes gives
    ω² = max(2e3·(k_0 + k_1)/m_1, 2e3·(k_1 + k_t/2)/m_2) [1/s²] (m in kg, k in N/mm), dt = 2/ω."""
    for tail in (0.0, 1e-3):  # with a 1 g tail mass the last row, with half the take-up spring, is the larger
        line = ChainLine(n_links=10, n_masses=2, pretension_N=500.0, contact_exponent=1.4, tensioner_stiffness=5.0,
                         tail_mass_kg=tail)
        c_lin, c_h = line.segment_coefficients()
        k = 1.0 / (c_lin + 1.4 * c_h * 2000.0 ** 0.4)
        m = line.node_masses()
        rows = [2e3 * (k[0] + k[1]) / m[1], 2e3 * (k[1] + 2.5) / m[2]]
        assert rows[1] > rows[0] if tail else True
        assert stable_step(line, peak_force=2000.0) == pytest.approx(2.0 / math.sqrt(max(rows)), rel=1e-12)


def test_stable_step_of_a_damped_line_by_hand():
    """Two segments of 6 and 5 links with dampers c_j = c_e·n_ref/n_s = 2.3125·16/6 and 2.3125·16/5 N·s/mm (6.17 and
    7.4), node masses 1.1 and 0.8 kg (a 0.3 kg tail), tensioner end:
    Gershgorin on the damping as on the stiffness, λ_c = max(2e3·(c_0 + c_1)/m_1, 2e3·c_1/m_2) [1/s] (the take-up
    spring has no damper), ζ = λ_c/(2ω), dt = (2/ω)(√(1 + ζ²) − ζ) with ω from the load-independent bound
    k = 1/c_lin."""
    line = ChainLine(n_links=11, n_masses=2, pretension_N=500.0, damping=2.3125, tail_mass_kg=0.3)
    c = line.segment_damping()
    assert c.tolist() == pytest.approx([2.3125 * 16 / 6, 7.4])
    k = 1.0 / line.segment_coefficients()[0]
    m = line.node_masses()
    w = math.sqrt(max(2e3 * (k[0] + k[1]) / m[1], 2e3 * k[1] / m[2]))
    zeta = max(2e3 * (c[0] + c[1]) / m[1], 2e3 * c[1] / m[2]) / (2.0 * w)
    assert zeta > 1e-3  # the damping shortens the step measurably
    assert stable_step(line) == pytest.approx((2.0 / w) * (math.sqrt(1.0 + zeta**2) - zeta), rel=1e-9)


def test_stable_step_of_a_dead_band_at_twice_the_static_load_by_hand():
    """A dead band (k_d = 400 N/mm^1.5 of the 16-link specimen, p = 1.5) stiffens without bound, so without
    peak_force stable_step takes its tangent where it carries twice the static load: F_ref = 2·(pretension +
    resistance + Σ|load steps|) = 2·(1000 + 200 + |−300|) = 3000 N on a tensioner line, and 2·max(0, 1 N) = 2 N on
    an unloaded one; with peak_force = 5 kN, there.  By hand, on two segments of 8 links (r = 1/2): k_d,seg =
    400·2^1.5, its tangent k_d·p·(F/k_d)^((p−1)/p), added to the load-independent 1/c_lin (or the Hertz tangent at the
    peak force); Gershgorin over node 1 (2e3·(k_1 + k_2)/m_1) and the tensioner node (2e3·k_2/m_2), dt = 2/ω.
    Bugs caught: the factor 2, the |load| (a negative load step), the 1 N floor, resistance or loads dropped."""
    kd = 400.0 * 2.0 ** 1.5

    def hand(line, F_ref, spring_k):
        k = spring_k + kd * 1.5 * (F_ref / kd) ** (0.5 / 1.5)
        m = line.node_masses()
        w2 = max(2e3 * (k[0] + k[1]) / m[1], 2e3 * k[1] / m[2])
        return 2.0 / math.sqrt(w2)

    loaded = ChainLine(n_links=16, n_masses=2, pretension_N=1_000.0, resistance_N=200.0,
                       loads=(LoadStep(2, -300.0, 0.1),), deadband=(400.0, 0.05, 1.5, 0.0))
    cl, ch = loaded.segment_coefficients()
    assert stable_step(loaded) == pytest.approx(hand(loaded, 3_000.0, 1.0 / cl), rel=1e-12)
    bare = ChainLine(n_links=16, n_masses=2, deadband=(400.0, 0.05, 1.5, 0.0))
    assert stable_step(bare) == pytest.approx(hand(bare, 2.0, 1.0 / cl), rel=1e-12)
    k_peak = 1.0 / (cl + (2.0 / 3.0) * ch * 5_000.0 ** (-1.0 / 3.0))
    assert stable_step(loaded, peak_force=5_000.0) == pytest.approx(hand(loaded, 5_000.0, k_peak), rel=1e-12)
