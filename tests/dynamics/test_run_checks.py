"""The checks of a dynamics run: energy balance, refinement of slack runs, limits of work and memory, input types,
Newton and modes against independent numbers.  Units mm, N, s, kg; energies N·mm."""
from __future__ import annotations

import math
import re
import warnings

import numpy as np
import pytest

from chainid.chain.spec import default_chain
from chainid.dynamics import ChainLine, Drive, SimulationError, simulate
from chainid.dynamics.energy import balance
from chainid.dynamics.modes import modes, tangent_system
from chainid.model import kernels


# ------------------------------------------------------------------ energy balance: worst point, not last
def test_balance_reports_the_worst_point_not_the_last():
    """A residual of 3 N·mm in the middle that is gone at the end: reported as 3/100, at t = 0.2 s."""
    t = np.array([0.0, 0.1, 0.2, 0.3])
    W = np.array([0.0, 50.0, 100.0, 100.0])
    kin = np.array([0.0, 50.0, 97.0, 100.0])  # W − ΔE_kin = 0, 0, 3, 0
    z = np.zeros(4)
    eb = balance(W, kin, z, z, t)
    assert eb["residual"] == 0.0
    assert eb["worst_residual"] == 3.0 and eb["worst_t_s"] == 0.2
    assert eb["relative_error"] == pytest.approx(3.0 / 100.0, rel=1e-15)


def test_balance_of_a_free_vibration_is_measured():
    """No work in (W ≡ 0): the scale is the energy exchanged, so an error still shows (was 0 by construction)."""
    z = np.zeros(3)
    eb = balance(z, np.array([10.0, 0.0, 10.5]), np.array([0.0, 10.0, 0.0]), z)
    assert eb["scale"] == pytest.approx(10.0) and eb["relative_error"] == pytest.approx(0.05)
    nan = balance(np.array([0.0, np.nan]), np.zeros(2), np.zeros(2), np.zeros(2))
    assert nan["finite"] is False and math.isnan(nan["relative_error"])


# ------------------------------------------------------------------ near-standstill resistance branch
def test_resistance_near_standstill_is_viscous_R_over_eps():
    """A free node creeping at |v| < ε decays as exp(−t/τ), τ = ε·m/(1e3·R) (the viscous branch R·v/ε)."""
    line = ChainLine(n_links=10, n_masses=1, pretension_N=0.0, far_end="tensioner", tail_mass_kg=2.0,
                     resistance_N=3.0, resistance_v_eps=1.0)
    m1 = line.node_masses()[1]
    tau = 1.0 * m1 / (1e3 * 3.0)  # s (R applies to node 1 alone: node 0 is the drive)
    u0 = np.array([0.0, 5.0])  # mm: segment 5 mm slack (no spring force)
    res = simulate(line, Drive("none"), 2 * tau, dt=tau / 2000, initial_u=u0, initial_v=np.array([0.0, 0.8]),
                   n_out=100)
    assert line.resistance_per_node()[1] == pytest.approx(3.0)
    assert res.tension.max() == 0.0
    np.testing.assert_allclose(res.v[:, 1], 0.8 * np.exp(-res.t / tau), rtol=2e-3)


# ------------------------------------------------------------------ modes
def test_tensioner_stiffness_enters_the_mode_matrix():
    """One segment, tensioner end with take-up spring k_t: ω² = 1e3·(k_e + k_t)/m_1, k_e from dx/dF by hand."""
    chain = default_chain()
    F0, kt = 8_000.0, 700.0
    line = ChainLine(n_links=chain.n, n_masses=1, chain=chain, pretension_N=F0, tensioner_stiffness=kt,
                     tail_mass_kg=1.5)
    cl, ch = kernels.coefficients(chain)
    ke = 1.0 / (cl + (2.0 / 3.0) * ch * F0 ** (-1.0 / 3.0))  # N/mm: x = c_lin F + c_h F^(2/3)
    m1 = 0.5 * chain.mass_per_m * chain.n * chain.pitch * 1e-3 + 1.5
    assert modes(line).omega[0] == pytest.approx(math.sqrt(1e3 * (ke + kt) / m1), rel=1e-9)
    no_kt = ChainLine(n_links=chain.n, n_masses=1, chain=chain, pretension_N=F0, tail_mass_kg=1.5)
    assert modes(no_kt).omega[0] == pytest.approx(math.sqrt(1e3 * ke / m1), rel=1e-9)


@pytest.mark.parametrize("far_end", ["fixed", "tensioner"])
def test_tridiagonal_modes_match_dense_eigh(far_end):
    line = ChainLine(n_links=83, n_masses=9, pretension_N=3_000.0, far_end=far_end, tensioner_stiffness=250.0,
                     tail_mass_kg=0.7)
    M, K, _ = tangent_system(line)
    s = 1 / np.sqrt(M)
    lam, y = np.linalg.eigh(1e3 * s[:, None] * K * s[None, :])
    md = modes(line, n_modes=3)
    np.testing.assert_allclose(md.omega, np.sqrt(lam[:3]), rtol=1e-10)
    phi = s[:, None] * y[:, :3]
    phi /= np.max(np.abs(phi), axis=0)
    np.testing.assert_allclose(np.abs(md.shapes), np.abs(phi), atol=1e-10)


def test_modes_of_20000_masses_are_fast_and_match_the_string():
    """20 000 masses (a dense eigh would need 3.2 GB): a taut uniform chain, drive held, constant-force
    tensioner end, is a fixed-free string: f_k = (2k − 1)·c/(4L), c = √(k_e·ℓ_s/ρ) (lumping error < 1e-3)."""
    import time
    line = ChainLine(n_links=40_000, n_masses=20_000, pretension_N=5_000.0)
    t0 = time.perf_counter()
    md = modes(line, n_modes=2)
    assert time.perf_counter() - t0 < 20.0
    cl, ch = line.segment_coefficients()
    F0 = 5_000.0
    ke = 1.0 / (cl[0] + (2.0 / 3.0) * ch[0] * F0 ** (-1.0 / 3.0))
    c = math.sqrt(ke * line.segment_lengths()[0] / (line.chain.mass_per_m * 1e-3) * 1e3)  # mm/s
    assert md.frequency_hz[0] == pytest.approx(c / (4 * line.length_mm), rel=1e-3)
    assert md.frequency_hz[1] == pytest.approx(3 * c / (4 * line.length_mm), rel=1e-3)


# ------------------------------------------------------------------ limits and numbers
def _small():
    return ChainLine(n_links=40, n_masses=4, pretension_N=1_000.0)


@pytest.mark.parametrize("kw, match", [
    (dict(t_end=1e9), "max_work"),
    (dict(t_end=0.01, dt=1e-12, scheme="implicit"), "max_work"),
    (dict(t_end=0.01, n_out=10 ** 9, max_work=None), "max_memory"),
])
def test_work_and_memory_are_refused_before_running(kw, match):
    with pytest.raises(ValueError, match=match):
        simulate(_small(), Drive("ramp", v=100.0), **kw)


def test_huge_damping_is_refused_not_an_overflow():
    line = ChainLine(n_links=40, n_masses=4, pretension_N=1_000.0, damping=1e9)
    with pytest.raises(ValueError, match="max_work"):
        simulate(line, Drive("ramp", v=100.0), 1.0)


def test_numpy_numbers_accepted_bool_refused():
    res = simulate(_small(), Drive("ramp", v=100.0), np.float32(0.01), dt=np.float64(1e-4), n_out=np.int64(10))
    assert res.t[-1] == pytest.approx(0.01, rel=1e-6)
    for kw in (dict(t_end=True), dict(t_end=0.01, dt=True), dict(t_end=0.01, n_out=True)):
        with pytest.raises(ValueError, match="t_end|dt|n_out"):
            simulate(_small(), Drive("ramp", v=100.0), **kw)


# ------------------------------------------------------------------ Newton, checks, refinement
def _slack_polygon(pretension=500.0, damping=0.0):
    return (ChainLine(n_links=200, n_masses=20, pretension_N=pretension, damping=damping),
            Drive("polygon", v=1500.0, t_ramp=0.2, z=6))


def test_coarse_implicit_snap_is_flagged_not_returned_silently():
    """Large implicit steps on a slack polygon drive: never a silent blow-up; strict refuses it."""
    line, d = _slack_polygon()
    with pytest.warns(RuntimeWarning, match="not resolved by the time step dt = 0.005 s"), \
            pytest.warns(RuntimeWarning, match="energy balance error"):
        res = simulate(line, d, 1.0, scheme="implicit", dt=5e-3)
    assert res.warnings and res.energy_balance()["relative_error"] > 1e-3
    with pytest.raises(SimulationError, match="strict"):
        simulate(line, d, 1.0, scheme="implicit", dt=5e-3, strict=True)


def test_refined_schemes_agree_on_a_damped_slack_polygon_drive():
    """Damped chain that goes slack (T = 0 somewhere): refined explicit and implicit peaks within 2 %."""
    line, d = _slack_polygon(pretension=100.0, damping=2.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        a = simulate(line, d, 1.0, refine=6)
        b = simulate(line, d, 1.0, scheme="implicit", refine=6)
    assert a.tension.min() == 0.0  # it does go slack
    assert a.peak_change <= 0.02 and b.peak_change <= 0.02
    assert b.peak_tension == pytest.approx(a.peak_tension, rel=0.02)
    assert a.energy_balance()["relative_error"] < 1e-3 and b.energy_balance()["relative_error"] < 1e-3


def test_taut_runs_are_not_refined_slack_runs_are_checked():
    """The peak check under halving applies where snap loads can occur (a segment carried nothing)."""
    taut = simulate(ChainLine(n_links=100, n_masses=10, pretension_N=5_000.0), Drive("ramp", v=200.0, t_ramp=0.05),
                    0.1, refine=5)
    assert taut.slack_substeps == 0 and taut.refinements == 0 and not taut.warnings
    line, d = _slack_polygon(pretension=100.0, damping=2.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        slack = simulate(line, d, 0.5, refine=5)
    assert slack.slack_substeps > 0 and slack.refinements >= 1 and slack.peak_change <= 0.02


def test_a_too_small_peak_force_is_an_error_or_refined_never_a_blow_up():
    """peak_force = 1 N sets a step above the real stable step: no 1e192 N result (was exit 0)."""
    line = ChainLine(n_links=400, n_masses=40, pretension_N=5_000.0)
    d = Drive("ramp", v=1000.0, t_ramp=0.2)
    with pytest.raises(SimulationError, match="non-finite.*peak_force = 1 N"):
        simulate(line, d, 0.5, peak_force=1.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        res = simulate(line, d, 0.5, peak_force=1.0, refine=4)
    assert res.refinements >= 1 and res.energy_balance()["relative_error"] < 1e-3
    assert 5_000.0 < res.peak_tension < 10_000.0


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


@pytest.mark.parametrize("scheme", ["explicit", "implicit"])
def test_a_pretensioned_line_with_no_drive_stays_at_rest(scheme):
    """Equilibrium: every segment at the pretension, the tensioner pulling the free last node with the same force,
    no drive: no node moves and every tension stays the pretension (a force of even 1 N left over at the free end
    at t = 0 would move its node by ~h·t/2·F/m)."""
    line = ChainLine(n_links=40, n_masses=4, pretension_N=1000.0, far_end="tensioner")
    res = simulate(line, Drive("none"), 0.2, scheme=scheme)
    assert np.max(np.abs(res.u)) < 1e-9  # mm
    np.testing.assert_allclose(res.tension, 1000.0, rtol=1e-9)


def test_the_peak_change_under_halving_is_relative_to_the_peak_also_below_one_newton():
    """``peak_change`` is |peak(dt/2) − peak(dt)| / peak(dt/2) (SimResult docstring), for a peak of any size: a
    fixed-end line at 0.05 N pretension shaken by 0.4 µm at 30 Hz goes slack and snaps at a peak of 0.27 N.  One
    refinement gives the change between the run at the default step and at half of it, run here apart."""
    line = ChainLine(n_links=20, n_masses=4, pretension_N=0.05, far_end="fixed")
    d = Drive("sine", A=0.0004, omega=2 * math.pi * 30)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        whole = simulate(line, d, 0.2)
        half = simulate(line, d, 0.2, dt=whole.dt / 2)
        refined = simulate(line, d, 0.2, refine=1)
    assert whole.slack_substeps > 0 and refined.refinements == 1 and half.peak_tension < 1.0
    assert refined.peak_change == pytest.approx(abs(half.peak_tension - whole.peak_tension) / half.peak_tension,
                                                rel=1e-12)


@pytest.mark.parametrize("kw", [dict(t_end=0.0), dict(t_end=-0.5), dict(t_end=0.01, dt=0.0), dict(t_end=0.01, dt=-0.5)])
def test_a_zero_or_negative_time_is_refused_with_its_name(kw):
    name = "dt" if "dt" in kw else "t_end"
    with pytest.raises(ValueError, match=re.escape(f"{name} = {kw[name]!r} is invalid: valid range > 0 s")):
        simulate(_small(), Drive("ramp", v=100.0), **kw)


def test_a_newton_failure_at_the_shortest_sub_step_names_that_sub_step():
    """A stiff Bouc–Wen element (F_y = 500 N yielding over 1 µm) under a fast sine with implicit steps of 1 ms and one
    halving allowed: Newton fails at dt/2 too, and the error gives that sub-step, 1 ms / 2¹ = 0.0005 s."""
    line = ChainLine(n_links=40, n_masses=4, pretension_N=50.0, bouc_wen=[[500.0, 0.001, 2.0, 0.5]])
    with pytest.raises(SimulationError, match=re.escape("did not converge even at dt/2 = 0.0005 s (dt = 0.001 s)")):
        simulate(line, Drive("sine", A=5.0, omega=300.0), 0.05, dt=1e-3, scheme="implicit", substep_levels=1)


# ------------------------------------------------------------------ input checks named exactly
@pytest.mark.parametrize("kw, message", [
    (dict(max_work=0), "max_work = 0 is invalid: valid range > 0 (or None)"),
    (dict(max_work=True), "max_work = True is invalid: valid range > 0 (or None)"),
    (dict(max_memory=-1.0), "max_memory = -1.0 is invalid: valid range > 0 (or None)"),
    (dict(substep_levels=-1), "substep_levels = -1 is invalid: valid range an int 0 .. 20"),
    (dict(substep_levels=2.0), "substep_levels = 2.0 is invalid: valid range an int 0 .. 20"),
    (dict(refine=-1), "refine = -1 is invalid: valid range an int 0 .. 10"),
    (dict(scheme="Explicit"), "scheme = 'Explicit' is invalid: valid range one of ['explicit', 'implicit']"),
    (dict(initial_v=np.array([0.0, 0.0, np.nan, 0.0, 0.0])),
     "initial_v = 'array of shape (5,)' is invalid: valid range finite values, shape (5,) (one per node)"),
])
def test_run_options_outside_their_range_are_refused_by_name(kw, message):
    """The limits are numbers > 0 or None (0 and a bool refused), the sub-step levels and refinements ints from 0,
    the scheme one of two names, the initial speeds finite: each refused before any work with the option's name,
    value and range.  Bugs caught: ``lim is not None`` → ``is None``, ``0 <=`` → ``-1 <=``, the finiteness test of
    the initial state joined by ``and``."""
    with pytest.raises(ValueError) as exc:
        simulate(_small(), Drive("ramp", v=100.0), 0.01, **kw)
    assert str(exc.value) == message


def test_line_and_drive_must_be_of_their_types():
    """simulate's first two arguments: a ChainLine and a Drive, each refused by type name otherwise."""
    with pytest.raises(ValueError) as exc:
        simulate("chain", Drive("ramp", v=100.0), 0.01)
    assert str(exc.value) == "line = 'str' is invalid: valid range a ChainLine"
    with pytest.raises(ValueError) as exc:
        simulate(_small(), "ramp", 0.01)
    assert str(exc.value) == "drive = 'str' is invalid: valid range a Drive"


def test_the_ends_of_the_option_ranges_run():
    """refine = 10 and substep_levels = 0, and an explicit dt equal to the stable step (0 < dt <= dt_stable): all
    valid, a taut 10 ms ramp runs to t_end.  Bugs caught: ``refine <= 10`` → ``< 10``, ``0 <= substep_levels`` →
    ``0 <``, ``dt > dts`` → ``dt >= dts``."""
    from chainid.dynamics import stable_step

    line = _small()
    res = simulate(line, Drive("ramp", v=100.0, t_ramp=0.005), 0.01, refine=10, substep_levels=0)
    assert res.t[-1] == pytest.approx(0.01, rel=1e-12) and res.refinements == 0
    dts = stable_step(line)
    res = simulate(line, Drive("ramp", v=100.0, t_ramp=0.005), 0.01, dt=dts, n_out=100_000)  # every step stored
    assert res.dt <= dts and res.dt == pytest.approx(0.01 / math.ceil(0.01 / dts - 1e-9), rel=1e-12)


def test_a_fixed_far_end_holds_its_node_whatever_the_initial_state_says():
    """With a fixed far end node N is anchored: an initial displacement of 5 mm and speed 3 mm/s given for it are
    ignored (held at 0 throughout); the free nodes start where they are told (0.01, 0.02, 0.03 mm).
    Bug caught: ``far_end == "fixed"`` → ``!=`` (the anchored node would start displaced)."""
    import warnings

    line = ChainLine(n_links=40, n_masses=4, pretension_N=1_000.0, far_end="fixed")
    u0 = np.array([0.0, 0.01, 0.02, 0.03, 5.0])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # the balance of a free vibration at 0.9·dt_stable
        res = simulate(line, Drive("none"), 0.005, initial_u=u0, initial_v=np.array([0.0, 0.0, 0.0, 0.0, 3.0]),
                       n_out=10)
    assert np.all(res.u[:, -1] == 0.0) and np.all(res.v[:, -1] == 0.0)
    np.testing.assert_allclose(res.u[0, :4], u0[:4], rtol=0, atol=0)


# ------------------------------------------------------------------ the limits' messages by hand
def test_the_work_refusal_quotes_steps_nodes_and_seconds_by_hand():
    """4 segments (5 nodes), dt = 3 µs for t_end = 1 s: 3.33e5 steps, 5 × 3.33e5 = 1.67e6 node-steps explicit,
    1.67e6/3e7 = 0.0556 s at the nominal speed; implicit 8× that: 1.33e7 node-steps, 0.444 s (by hand); refused over
    max_work = 1000.  Bugs caught: the steps, the node count, the seconds or the implicit cost garbled in the
    message, its digits."""
    line = _small()
    with pytest.raises(ValueError) as exc:
        simulate(line, Drive("none"), 1.0, dt=3e-6, max_work=1e3)
    assert str(exc.value).startswith("the run would take about 1.67e+06 node-steps (3.33e+05 steps of dt = 3e-06 s "
                                     "for t_end = 1 s, 5 nodes; about 0.0556 s), over max_work = 1e+03 node-steps")
    with pytest.raises(ValueError) as exc:
        simulate(line, Drive("none"), 1.0, dt=3e-6, max_work=1e3, scheme="implicit")
    assert str(exc.value).startswith("the run would take about 1.33e+07 node-steps (3.33e+05 steps of dt = 3e-06 s "
                                     "for t_end = 1 s, 5 nodes; about 0.444 s)")


def test_the_memory_refusal_quotes_the_stored_samples_and_gib():
    """A run of 10 steps (t_end = 10 ms, dt = 1 ms) stores 10 + 1 samples even with n_out = 500 (never more samples
    than steps, plus t = 0), of 5 nodes; over max_memory = 1000 bytes = 9.31e-07 GiB (1000/2³⁰) it is refused
    quoting the estimate in GiB (its bytes / 2³⁰).  Bugs caught: min → max of n_out and the steps, the GiB unit."""
    from chainid.dynamics.simulation import estimate

    line = _small()
    with pytest.raises(ValueError) as exc:
        simulate(line, Drive("none"), 0.01, dt=1e-3, scheme="implicit", max_memory=1000)
    gib = estimate(line, 10, 11, "implicit")["bytes"] / 2**30
    assert str(exc.value).startswith(f"the run would need about {gib:.3g} GiB (11 output samples x 5 nodes), over "
                                     "max_memory = 9.31e-07 GiB: valid range <= the limit")


def test_the_memory_estimate_counts_every_element_kind_once_per_segment():
    """estimate()'s bytes without steps or outputs grow by the same amount for one element of any kind (Jenkins,
    Coulomb, Dahl, Stribeck, Bouc–Wen, play: each a column of the same per-segment tables), twice that for two,
    in proportion to the segments (8 segments: twice 4), and a plain line counts none; per element and segment 8
    floats of 8 bytes, counted by hand: the tables hf, hx, hd and hq's three columns that simulate hands to the
    loop (``core_arguments``), and the two copies of the element state the loop keeps (``integrators.run``).
    Bugs caught: a kind left out of the count, the play counted without backlash (``> 0`` → ``>= 0``), the element
    term not proportional to segments × elements."""
    from chainid.dynamics.simulation import estimate

    def extra(N, **kw):
        base = estimate(ChainLine(n_links=16, n_masses=N, pretension_N=1_000.0), 0, 0)["bytes"]
        return estimate(ChainLine(n_links=16, n_masses=N, pretension_N=1_000.0, **kw), 0, 0)["bytes"] - base

    kinds = [dict(hysteresis=((2_000.0, 100.0),)), dict(coulomb_N=50.0), dict(dahl=((30.0, 0.2),)),
             dict(stribeck=((80.0, 60.0, 2.0, 15.0),)), dict(bouc_wen=((150.0, 0.04, 2.5, 0.6),)),
             dict(backlash_mm=0.08)]
    d = extra(4, **kinds[0])
    line = ChainLine(n_links=16, n_masses=4, pretension_N=1_000.0, **kinds[0])
    hf, hx, hd, hq, _ = line.segment_element_arrays()
    assert hf.size + hx.size + hd.size + hq.size == 6 * 4 * 1  # the tables: 6 values per element and segment
    assert d == 8 * (hf.size + hx.size + hd.size + hq.size + 2 * hf.size)  # and the loop's two state copies
    for kw in kinds[1:]:
        assert extra(4, **kw) == d, kw
    assert extra(4, dahl=((30.0, 0.2), (10.0, 0.1))) == 2 * d
    assert extra(8, **kinds[0]) == 2 * d


def test_the_memory_estimate_covers_the_arrays_handed_to_the_integrator():
    """Without outputs, the estimate's bytes are at least those of the arrays simulate hands to the numba loop (the
    initial state, masses, coefficients, tables, resistance: 14 floats per node here), for 1000 segments with and
    without a Dahl element.  Bug caught: the per-node work term ``40 * nn`` → ``40 + nn``."""
    from chainid.dynamics.simulation import core_arguments, estimate

    for kw in (dict(), dict(dahl=((30.0, 0.2),))):
        line = ChainLine(n_links=2_000, n_masses=1_000, pretension_N=1_000.0, **kw)
        args, _ = core_arguments(line, Drive("none"), 1e-5, 10, 10)
        held = sum(a.nbytes for a in args if isinstance(a, np.ndarray))
        assert estimate(line, 10, 0)["bytes"] >= held


# ------------------------------------------------------------------ the result's bookkeeping
def test_the_result_of_an_explicit_run_counts_whole_steps_and_places_the_nodes():
    """An explicit run takes every step whole: substeps = n_steps, none rejected, the shortest sub-step is dt, and
    its work is free nodes × sub-steps (SimResult docstring; a tensioner end: 4 free nodes); the node positions
    are 0, 250, 500, 750, 1000 mm (4 segments of 5 links of 50 mm, by hand).
    Bugs caught: the shortest sub-step's scaling by dt, the work's cost factor, the positions' cumulative sum."""
    line = ChainLine(n_links=20, n_masses=4, pretension_N=1_000.0)
    res = simulate(line, Drive("ramp", v=100.0, t_ramp=0.005), 0.01, n_out=10)
    assert res.positions.tolist() == [0.0, 250.0, 500.0, 750.0, 1000.0]
    assert res.substeps == res.n_steps and res.rejected == 0 and res.explicit_fallbacks == 0
    assert res.shortest_substep_s == pytest.approx(res.dt, rel=1e-15)
    assert res.work == 4.0 * res.n_steps


def test_the_summary_reports_the_results_own_numbers():
    """summary() is the JSON form of the result: each key carries the field of its name (peak, static, dynamic
    factor, steps, the step and stable step, the scheme, sub-step counts, the balance) and t_end_s the requested
    t_end (10 ms), as a plain float."""
    res = simulate(_small(), Drive("ramp", v=100.0, t_ramp=0.005), 0.01, n_out=10)
    s = res.summary()
    assert s["t_end_s"] == pytest.approx(0.01, rel=1e-12) and type(s["t_end_s"]) is float
    assert (s["peak_tension_N"], s["static_tension_N"], s["dynamic_factor"]) == (
        res.peak_tension, res.static_tension, res.dynamic_factor)
    assert (s["dt_s"], s["dt_stable_s"], s["scheme"], s["n_steps"]) == (res.dt, res.dt_stable, "explicit", res.n_steps)
    assert (s["substeps"], s["rejected_substeps"], s["shortest_substep_s"], s["refinements"]) == (
        res.substeps, res.rejected, res.shortest_substep_s, 0)
    assert s["energy_N_mm"] == res.energy_balance() and s["warnings"] == res.warnings
    assert math.isnan(s["peak_change_last_halving"])


def test_a_polygon_drive_refers_to_the_running_tension():
    """The dynamic factor of a polygon drive (like a ramp: the chain runs) refers to the steady running tension,
    pretension + resistance = 1000 + 200 N (tensioner end), not the pretension.
    Bug caught: "polygon" dropped from the running drives."""
    import warnings

    line = ChainLine(n_links=40, n_masses=4, pretension_N=1_000.0, resistance_N=200.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # the coarse step's balance is not under test
        res = simulate(line, Drive("polygon", v=50.0, t_ramp=0.005, z=8), 0.01, n_out=10, peak_force=3_000.0)
    assert res.static_tension == 1_200.0 and res.dynamic_factor == pytest.approx(res.peak_tension / 1_200.0)


def test_a_peak_above_peak_force_warns_only_when_the_step_exceeds_the_stable_step_there():
    """A 500 mm/s speed step on 4 segments of 10 links at 1 kN (tensioner end) with peak_force = 1 kN: the step
    0.9·dt_stable(1 kN) is above the stable step at the peak reached (Gershgorin by hand: ω² the largest of
    2e3·(k_i + k_(i+1))/m_i over the inner nodes and 2e3·k_4/m_4 at the tensioner node, with the segment tangents
    k_e = 1/(c_lin + ⅔·c_h·F^(−1/3)) at the peak, dt = 2/ω), so a warning names the peak, the step and
    that stable step and asks for peak_force >= the peak.  With peak_force = 3 kN the peak (4.2 kN) is exceeded but
    the step is below the stable step there: no such warning; the implicit scheme has no stable step: none either
    (at dt = 1 ms, above the stable step at its peak).
    Bugs caught: either comparison flipped, the scheme test dropped."""
    import warnings

    line = ChainLine(n_links=40, n_masses=4, pretension_N=1_000.0)
    cl, ch = line.segment_coefficients()
    m = line.node_masses()
    d = Drive("ramp", v=500.0, t_ramp=0.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        res = simulate(line, d, 0.05, peak_force=1_000.0, n_out=10)
        high = simulate(line, d, 0.05, peak_force=3_000.0, n_out=10)
        imp = simulate(line, d, 0.05, peak_force=1_000.0, n_out=10, scheme="implicit", dt=1e-3)
    P = res.peak_tension
    k = 1.0 / (cl + (2.0 / 3.0) * ch * P ** (-1.0 / 3.0))
    w2 = max([2e3 * (k[i - 1] + k[i]) / m[i] for i in (1, 2, 3)] + [2e3 * k[3] / m[4]])
    dts_peak = 2.0 / math.sqrt(w2)
    assert P > 1_000.0 and res.dt > dts_peak
    msg = [w for w in res.warnings if w.startswith("peak tension")]
    assert msg == [f"peak tension {P:.4g} N exceeded peak_force = 1000 N and dt = {res.dt:.3g} s is above the stable "
                   f"step {dts_peak:.3g} s there: rerun with peak_force >= {P:.4g} N"]
    assert high.peak_tension > 3_000.0 and not [w for w in high.warnings if w.startswith("peak tension")]
    assert imp.peak_tension > 1_000.0 and imp.dt > dts_peak
    assert not [w for w in imp.warnings if w.startswith("peak tension")]


def test_the_refinement_message_quotes_the_first_and_the_final_step():
    """A coarse explicit run (dt = 0.3 ms for t_end = 10 ms: 36 steps of 10/36 ms, see the step-grid test) misses the
    energy balance; with refine = 4 it is halved once from the step actually used (72 steps of 10/72 ms = 0.139 ms,
    by hand) and the message gives both: "dt 0.0003 s -> 0.000139 s".
    Bug caught: the halving taken from the requested step instead of the one used (0.15 ms → 70 steps)."""
    import warnings

    line = ChainLine(n_links=40, n_masses=4, pretension_N=1_000.0, resistance_N=200.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        res = simulate(line, Drive("ramp", v=50.0, t_ramp=0.005), 0.01, dt=3e-4, n_out=10, peak_force=3_000.0,
                       refine=4)
    assert res.refinements == 1 and res.n_steps == 72
    assert res.warnings[0] == "step refined 1 time(s) (energy balance and peak under halving): dt 0.0003 s -> " \
                              "0.000139 s"
