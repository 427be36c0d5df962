"""Pins of the dynamics package's bounds and closed forms (issue 20 §5): ChainLine's and Drive's refusals at each
field's bound, their derived numbers, the stable step, the drive motions, a segment model's effects and simulate's
step grid, each against hand numbers or the documented message.
Units: mm, mm/s, N, kg, s.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.dynamics import ChainLine, Drive, LoadStep, simulate
from model_texts import SPECIMEN


@pytest.mark.parametrize("kw, message", [
    (dict(n_masses=True), "n_masses = True is invalid: valid range an int >= 1"),
    (dict(n_links=True), "n_links = True is invalid: valid range an int >= 1"),
    (dict(n_masses=11), "n_masses = 11 is invalid: valid range 1 .. n_links = 10 (a segment holds >= 1 link)"),
    (dict(tensioner_stiffness=-1e-9), "tensioner_stiffness = -1e-09 is invalid: valid range >= 0 (finite)"),
    (dict(tail_mass_kg=float("inf")), "tail_mass_kg = inf is invalid: valid range >= 0 (finite)"),
    (dict(damping=-1.0), "damping = -1.0 is invalid: valid range >= 0 (finite)"),
    (dict(resistance_N=float("nan")), "resistance_N = nan is invalid: valid range >= 0 (finite)"),
    (dict(resistance_v_eps=0.0), "resistance_v_eps = 0.0 is invalid: valid range > 0 mm/s"),
    (dict(lumping="tail"), "lumping = 'tail' is invalid: valid range one of ['half', 'drive']"),
    (dict(damping_ref_links=0), "damping_ref_links = 0 is invalid: valid range an int >= 1"),
    (dict(dahl=((10.0, 0.0),)), "dahl = (10.0, 0.0) is invalid: valid range pairs (F_h > 0 N, x_h > 0 mm)"),
    (dict(coulomb_N=True), "coulomb_N = True is invalid: valid range >= 0 N (finite)"),
    (dict(loads=(LoadStep(0, 10.0, 0.0),)), "loads.node = 0 is invalid: valid range 1 .. n_masses = 2"),
    (dict(loads=(LoadStep(3, 10.0, 0.0),)), "loads.node = 3 is invalid: valid range 1 .. n_masses = 2"),
    (dict(loads=(LoadStep(2, 10.0, -0.1),)), "valid range finite force_N [N] and t_on >= 0 s"),
    (dict(loads=(LoadStep(2, float("nan"), 0.0),)), "valid range finite force_N [N] and t_on >= 0 s"),
    (dict(lumping="drive"), "tail_mass_kg = 0.0 is invalid: valid range > 0 kg with lumping='drive' and a "
                            "tensioner far end"),
])
def test_chain_line_refuses_each_field_at_its_bound(kw, message):
    """Each field of ChainLine outside its documented range is refused with the field, the value and the range
    (n_links = 10, n_masses = 2 unless given); the bound itself is accepted (see the next test)."""
    args = dict(n_links=10, n_masses=2) | kw
    with pytest.raises(ValueError) as exc:
        ChainLine(**args)
    assert message in str(exc.value)


def test_chain_line_accepts_its_bounds_and_its_derived_numbers_by_hand():
    """The bounds themselves are valid (n_masses = n_links, zeros, loads on node N at t_on = 0, one reference
    link, drive lumping with a tail mass or a fixed end); a massless chain is refused; from_length rounds to
    whole links of the 50 mm pitch, at least one; the steady-running drive tension is pretension + resistance
    with a tensioner end and the pretension with a fixed end."""
    ChainLine(n_links=10, n_masses=10, tensioner_stiffness=0.0, tail_mass_kg=0.0, damping=0.0, resistance_N=0.0,
              damping_ref_links=1, loads=(LoadStep(10, 5.0, 0.0),), coulomb_N=0.0)
    ChainLine(n_links=10, n_masses=2, lumping="drive", tail_mass_kg=1e-3)
    ChainLine(n_links=10, n_masses=2, lumping="drive", far_end="fixed")
    line = ChainLine(n_links=10, n_masses=2)
    with pytest.raises(ValueError, match=r"chain.mass_per_m = 0.0 is invalid: valid range > 0 kg/m"):
        ChainLine(n_links=10, n_masses=2, chain=line.chain.replace(mass_per_m=0.0))
    assert ChainLine.from_length(20.0, 1).n_links == 1  # 0.4 links -> at least one
    assert ChainLine.from_length(1_030.0, 2).n_links == 21 and ChainLine.from_length(1_070.0, 2).n_links == 21
    t = ChainLine(n_links=10, n_masses=2, pretension_N=800.0, resistance_N=150.0)
    assert t.static_tension_at_speed() == 950.0
    f = ChainLine(n_links=10, n_masses=2, pretension_N=800.0, resistance_N=150.0, far_end="fixed")
    assert f.static_tension_at_speed() == 800.0


def test_viscous_equivalent_refuses_an_operating_point_outside_its_range():
    """ω > 0 rad/s, A > 0 mm, x0 >= 0 mm (x0 = 0 accepted; a zero c_e is valid), each refusal naming the field,
    the value and the range."""
    from chainid.dynamics.model import viscous_equivalent

    assert viscous_equivalent(0.0, 1e-9, 1e-9, 0.0) == 0.0
    for args, message in (((0.0, 0.5, 2.0), "omega = 0.0 is invalid: valid range > 0 rad/s"),
                          ((float("inf"), 0.5, 2.0), "omega = inf is invalid: valid range > 0 rad/s"),
                          ((10.0, 0.0, 2.0), "A = 0.0 is invalid: valid range > 0 mm"),
                          ((10.0, 0.5, -1e-9), "x0 = -1e-09 is invalid: valid range >= 0 mm")):
        with pytest.raises(ValueError) as exc:
            viscous_equivalent(5.0, *args)
        assert str(exc.value) == message
    with pytest.raises(ValueError, match=r"c_e = -1.0 is invalid: valid range >= 0 N·s/mm"):
        viscous_equivalent(-1.0, 10.0, 0.5, 2.0)


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


def test_ramp_and_sine_drive_motion_closed_forms():
    """The start-up ramp (cosine speed ramp over t_r): u = ½v(t − sin(πt/t_r)/(π/t_r)), u̇ = ½v(1 − cos(πt/t_r)),
    ü = ½v(π/t_r)·sin(πt/t_r) for 0 < t < t_r; then u = v(t − t_r/2), u̇ = v, ü = 0; nothing before t = 0; with
    t_r = 0 a step to v.  The sine: u = A sin ωt, u̇ = Aω cos ωt, ü = −Aω² sin ωt.  "none" holds still.
    Bugs caught: the ramp's phase boundaries (t <= 0, t < t_r), its half factor, the sine's derivatives."""
    from chainid.dynamics.drives import drive_motion

    v, tr = 400.0, 0.5
    w = math.pi / tr
    t = np.array([-0.1, 0.0, 0.1, 0.25, 0.5, 0.8])
    u, ud, udd = drive_motion(Drive("ramp", v=v, t_ramp=tr), t, 50.0)
    hu = [0.0, 0.0] + [0.5 * v * (s - math.sin(w * s) / w) for s in (0.1, 0.25)] + [v * (s - tr / 2) for s in (0.5, 0.8)]
    hv = [0.0, 0.0] + [0.5 * v * (1 - math.cos(w * s)) for s in (0.1, 0.25)] + [v, v]
    ha = [0.0, 0.0] + [0.5 * v * w * math.sin(w * s) for s in (0.1, 0.25)] + [0.0, 0.0]
    np.testing.assert_allclose(u, hu, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(ud, hv, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(udd, ha, rtol=1e-12, atol=1e-9)
    u, ud, udd = drive_motion(Drive("ramp", v=v, t_ramp=0.0), np.array([0.0, 0.3]), 50.0)
    np.testing.assert_allclose(np.c_[u, ud, udd], [[0.0, 0.0, 0.0], [120.0, v, 0.0]], atol=1e-12)
    A, om = 2.0, 30.0
    t = np.array([0.0, 0.01, 0.07])
    u, ud, udd = drive_motion(Drive("sine", A=A, omega=om), t, 50.0)
    np.testing.assert_allclose(u, A * np.sin(om * t), atol=1e-12)
    np.testing.assert_allclose(ud, A * om * np.cos(om * t), atol=1e-9)
    np.testing.assert_allclose(udd, -A * om * om * np.sin(om * t), atol=1e-9)
    assert np.all(np.c_[drive_motion(Drive("none", v=5.0), t, 50.0)] == 0.0)


@pytest.mark.parametrize("kw, message", [
    (dict(v=-1.0), "drive v = -1.0 is invalid: valid range >= 0 mm/s"),
    (dict(t_ramp=float("nan")), "drive t_ramp = nan is invalid: valid range >= 0 s"),
    (dict(A=-0.1), "drive A = -0.1 is invalid: valid range >= 0 mm"),
    (dict(omega=0.0), "drive omega = 0.0 is invalid: valid range > 0 rad/s"),
    (dict(z=2), "drive z = 2 is invalid: valid range an int >= 3 teeth"),
    (dict(z=3.5), "drive z = 3.5 is invalid: valid range an int >= 3 teeth"),
    (dict(pitch=0.0), "drive pitch = 0.0 is invalid: valid range > 0 mm"),
])
def test_drive_refuses_each_field_at_its_bound(kw, message):
    """Each Drive field outside its range is refused naming field, value and range; the bounds pass."""
    Drive("polygon", v=0.0, t_ramp=0.0, A=0.0, omega=1e-9, z=3, pitch=1e-9)
    with pytest.raises(ValueError) as exc:
        Drive("polygon", **kw)
    assert str(exc.value) == message




def _segment_model(tmp_path, text, name="m.toml"):
    from chainid.dynamics.segment_model import segment_kwargs

    p = tmp_path / name
    p.write_text(SPECIMEN + text)
    return p, segment_kwargs


def test_segment_model_effects_and_time_domain_forms_by_hand(tmp_path):
    """A model file's effects and damping forms as segment elements (the module's table), by hand:
    friction F_c = 100 N, x_s = 0.05 mm, mu = 0.01 at 2000 N pretension → a Jenkins element of slip force
    100 + 0.01·2000 = 120 N and stiffness 120/0.05 = 2400 N/mm (below the 16-link specimen's link stiffness
    1/c_lin, Eq. 15 typed in tests/paper_forms.py), with a note; a hysteresis effect → a Dahl element (F_h, x_h),
    x_h 0.05 mm by default, none for F_h = 0; damping dahl (F_h, x_h), viscous c, none; a stick stiffer than the
    link → the Coulomb element with a note; a second such stick is refused; an unsupported effect or a negative c
    is refused naming it.
    Bugs caught: mu·pretension dropped, the stiffness bound inverted, defaults changed, branches swapped."""
    import paper_forms

    k_link = 1.0 / paper_forms.coefficients()[0]
    assert 2400.0 < k_link
    fr = '[[effects]]\nname = "friction"\n[effects.params]\nF_c = {F_c}\nx_s = {x_s}\nmu = {mu}\n'
    dahl = '[[effects]]\nname = "hysteresis"\n[effects.params]\nF_h = {F_h}\n'
    p, seg = _segment_model(tmp_path, fr.format(F_c=100.0, x_s=0.05, mu=0.01) + dahl.format(F_h=30.0) + dahl.format(F_h=0.0)
                            + '[damping]\nform = "dahl"\n[damping.params]\nF_h = 20.0\nx_h = 0.5\n')
    kw, notes = seg(p, pretension_N=2000.0)
    assert kw["hysteresis"] == ((2400.0, 120.0),) and kw["dahl"] == ((30.0, 0.05), (20.0, 0.5))
    assert kw["coulomb_N"] == 0.0 and kw["damping"] == 0.0 and kw["damping_ref_links"] == 16
    assert len(notes) == 1 and "mu = 0.01" in notes[0] and "slip force 120 N" in notes[0]
    p, seg = _segment_model(tmp_path, fr.format(F_c=50.0, x_s=50.0 / k_link * 1.001, mu=0.0)
                            + '[damping]\nform = "viscous"\n[damping.params]\nc = 7.5\n')
    kw, notes = seg(p)
    (k, f), = kw["hysteresis"]  # just below the link stiffness: a Jenkins element
    assert k == pytest.approx(k_link / 1.001, rel=1e-9) and f == 50.0 and kw["coulomb_N"] == 0.0
    assert kw["damping"] == 7.5 and notes == []
    p, seg = _segment_model(tmp_path, fr.format(F_c=50.0, x_s=50.0 / k_link * 0.999, mu=0.0)
                            + '[damping]\nform = "none"\n')
    kw, notes = seg(p)
    assert kw["hysteresis"] == () and kw["coulomb_N"] == 50.0 and kw["damping"] == 0.0
    assert len(notes) == 1 and "stiffer than the link" in notes[0] and "Coulomb friction 50 N" in notes[0]
    p, seg = _segment_model(tmp_path, fr.format(F_c=50.0, x_s=0.0, mu=0.0)
                            + '[damping]\nform = "coulomb"\n[damping.params]\nF_c = 20.0\nx_s = 0.0\n')
    with pytest.raises(ValueError, match="a second Coulomb element with a \\(near-\\)rigid stick; valid: one"):
        seg(p)
    p, seg = _segment_model(tmp_path, '[[effects]]\nname = "hardening"\n[effects.params]\nk3 = 2.0\n'
                            '[damping]\nform = "none"\n')
    with pytest.raises(ValueError, match="effect 'hardening' is not supported by dynamics segments: a chain base has "
                                         "no linear spring to harden"):
        seg(p)
    p, seg = _segment_model(tmp_path, '[damping]\nform = "viscous"\n[damping.params]\nc = -1.0\n')
    with pytest.raises(ValueError, match=r"c = -1 N·s/mm is invalid: valid range >= 0"):
        seg(p)


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
