"""chainid.dynamics: the lumped chain against independent references (units mm, N, s, kg)."""
import math

import numpy as np
import pytest

from chainid.model import kernels
from chainid.dynamics import ChainLine, Drive, LoadStep, drive_motion, simulate, stable_step
from chainid.dynamics.modes import modes
from chainid.model.base import ChainModel
from chainid.records.simulate import TestSpec, simulate_test
from chainid.chain.spec import default_chain


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
