"""Library effects in a chain line of several segments: series scaling, energy balance, and Stribeck at rest.

References: the one-segment specimen, whose force law is pinned against each effect's closed form in
test_segment_effects.py (a chain of 4 segments of a 16-link specimen, driven slowly, must carry the specimen's
force at the same total elongation: the series rule r = n_s/n_ref on every travel, stiffness and speed); the
energy balance W = ΔE_kin + ΔE_stored + D and the sign of the dissipation rate of each element (friction, Dahl,
Stribeck, Bouc–Wen with r >= 0.5: never negative); Stribeck friction holding a load between its kinetic and static
force at an elastic equilibrium solved by hand (Eq. 15 by bisection + the stick spring), and coming to rest
without creep or chatter after slipping.  Units mm, N, s, kg.
"""
import math
import warnings

import numpy as np
import pytest

import paper_forms
from chainid.dynamics import ChainLine, Drive, LoadStep, simulate, stable_step

CL, CH = paper_forms.coefficients()
F0 = 2000.0
XF0 = CL * F0 + CH * F0 ** (2 / 3)  # the specimen's elongation at the pretension (Eq. 15)

EFFECTS = {
    "stiffness_level+compliance": dict(ea_scale=2.5, compliance=2e-6),
    "slack": dict(slack=0.05),
    "contact_law": dict(hertz_scale=1.5, contact_exponent=0.9),
    "backlash": dict(backlash_mm=0.06),
    "deadband": dict(deadband=(3e3, 0.1, 1.5, XF0)),
    "friction": dict(hysteresis=((4000.0, 100.0),)),
    "hysteresis": dict(dahl=((120.0, 0.05),)),
    "stribeck": dict(stribeck=((80.0, 60.0, 6.0, 15.0),)),
    "bouc_wen": dict(bouc_wen=((150.0, 0.04, 2.5, 0.6),)),
}


@pytest.mark.parametrize("name", list(EFFECTS))
def test_four_segments_carry_the_specimens_force(name):
    """4 segments of 4 links of a 16-link specimen (ω = 20 rad/s, A = 0.3 mm: 1e-3 of the first natural frequency;
    c = 10 N·s/mm of the specimen keeps the nodes from ringing and outweighs the Stribeck slope dF_s·0.86/v_s, so
    no stick-slip) carry, at the drive, the one-segment specimen's force at the same elongation to 0.2 % of the
    force range (measured <= 7e-4), and their static elongations add up to the specimen's: every travel of the
    segments is n_s/n_ref = 1/4 of the specimen's.  Without the series rule (r = 1) the errors are 2.5 % (link
    term, compliance) to 19 % (play).  The dead band is held to 1 % (measured 0.7 %, 3.7 % without the rule): a
    segment's contact compliance counts its own contacts (4, 4, 4, 3 of the specimen's 15), so its elongation at a
    force is not exactly 1/4 of the specimen's, and the stops of a dead band engage a little earlier or later."""
    kw = EFFECTS[name]
    w, A = 20.0, 0.3
    t_end = 1.25 * 2 * math.pi / w
    one = ChainLine(n_links=16, n_masses=1, pretension_N=F0, far_end="fixed", lumping="drive", damping=10.0, **kw)
    four = ChainLine(n_links=16, n_masses=4, pretension_N=F0, far_end="fixed", damping=10.0, **kw)
    dt = t_end / (500 * math.ceil(t_end / (0.9 * stable_step(four)) / 500))  # one step and output grid for both
    r1 = simulate(one, Drive("sine", A=A, omega=w), t_end, dt=dt, n_out=500)
    r4 = simulate(four, Drive("sine", A=A, omega=w), t_end, dt=dt, n_out=500)
    scale = np.ptp(r1.tension[:, 0])
    assert scale > 1000.0 and np.array_equal(r1.t, r4.t)
    on = r1.t > 0.1 * 2 * math.pi / w  # after the start-up transient (the nodes start at rest, the drive does not)
    tol = 1e-2 if name == "deadband" else 2e-3
    np.testing.assert_allclose(r4.tension[on, 0], r1.tension[on, 0], rtol=0, atol=tol * scale)
    np.testing.assert_allclose(four.pretension_elongation().sum(), one.pretension_elongation()[0], rtol=1e-9)
    assert r4.energy_balance()["relative_error"] < 1e-3


@pytest.mark.parametrize("name, passive", [("friction", True), ("hysteresis", True), ("stribeck", True),
                                           ("bouc_wen", True), ("bouc_wen_r05", True), ("deadband", None),
                                           ("contact_law", None), ("slack", None), ("backlash", False)])
def test_dynamic_chain_keeps_its_energy_balance(name, passive):
    """10 segments of 10 links, 5 kN, driven at 300 rad/s for 5 cycles: balance within 1e-3 (explicit scheme, the
    step refined on the balance up to 3 times) with every effect; the dissipation never decreases for the passive elements (friction, Dahl, Stribeck, Bouc–Wen
    with r = 0.6 and r = 0.5) beyond the Bouc–Wen table's accuracy; the conservative springs (dead band, contact
    law, slack) dissipate nothing (no damper); the library's play returns energy (its dissipation goes negative:
    here it excites the line until segments go slack, peaks 15× the pretension, and the balance still holds at
    dt/8; the other runs need no refinement)."""
    kw = dict(EFFECTS.get(name, {}))
    if name == "bouc_wen_r05":
        kw = dict(bouc_wen=((150.0, 0.04, 2.0, 0.5),))
    if name == "deadband":
        kw = dict(deadband=(3e3, 0.1, 1.5, 0.0))
    line = ChainLine(n_links=100, n_masses=10, pretension_N=5000.0, far_end="fixed", **kw)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # the play's snap loads: refined (checked below)
        res = simulate(line, Drive("sine", A=0.3, omega=300.0), 5 * 2 * math.pi / 300.0, n_out=2000, refine=3)
    eb = res.energy_balance()
    assert eb["relative_error"] < 1e-3 and (res.refinements == 0) == (passive is not False)
    d = np.diff(res.dissipated)
    if passive is not False:
        assert res.tension.min() > 0
    if passive:
        assert d.min() >= -1e-5 * 150.0 * 0.04 and eb["dissipated"] > 0.01 * eb["scale"]
    elif passive is None:
        assert np.all(res.dissipated == 0.0)
    else:
        assert d.min() < 0 and eb["dissipated"] < 0


def _stick_equilibrium(dF_load, k_st):
    """e with F(e) + k_st·(e − XF0) = F0 + dF_load (Eq. 15 by bisection): the elastic rest of a stuck slider."""
    lo, hi = XF0, XF0 + 1.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        F = 0.0
        a, b = 0.0, 1e6
        for _ in range(200):
            F = 0.5 * (a + b)
            if CL * F + CH * F ** (2 / 3) < mid:
                a = F
            else:
                b = F
        if F + k_st * (mid - XF0) < F0 + dF_load:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def test_stribeck_holds_a_load_between_kinetic_and_static_without_creep():
    """A 10 kg take-up mass on one segment with Stribeck friction (F_c = 50 N, F_s = 200 N, v_s = 20 mm/s; stick
    spring the link, 1/c_lin) and c = 20 N·s/mm, under a load step of 150 N at t = 0 (above the kinetic force, below
    the static): the slider holds, the mass comes to rest at the elastic equilibrium F(e) + k_st·(e − e_pre) =
    F0 + 150 N (by hand) and stays there (a velocity-regularised sign would creep at any load above F_c)."""
    k_st = 1.0 / CL
    line = ChainLine(n_links=16, n_masses=1, pretension_N=F0, far_end="tensioner", lumping="drive",
                     tail_mass_kg=10.0, damping=20.0, stribeck=((50.0, 150.0, 20.0, 0.0),),
                     loads=(LoadStep(1, 150.0, 0.0),))
    res = simulate(line, Drive("none"), 0.05, n_out=1000)
    e_rest = _stick_equilibrium(150.0, k_st)
    late = res.t > 0.025
    np.testing.assert_allclose(-res.u[late, 1], e_rest - XF0, rtol=1e-6)
    assert np.ptp(res.u[late, 1]) < 1e-9 and np.abs(res.v[late, 1]).max() < 1e-6
    np.testing.assert_allclose(res.tension[late, 0], F0 + 150.0, rtol=1e-9)
    assert res.energy_balance()["relative_error"] < 1e-3


@pytest.mark.parametrize("scheme", ["explicit", "implicit"])
def test_stribeck_slips_then_rests_without_chatter(scheme):
    """The same take-up under 400 N (above the static force 200 N): the slider slips and the mass, overdamped while
    sliding (c = 20 N·s/mm against the chain's 5.2 kN/mm and 10 kg), creeps to rest without ever reversing (no
    chatter: one sign of the velocity, its magnitude decaying) where the friction reaches its static force as the
    speed vanishes: F(e) = F0 + 400 − 200 N, Eq. 15 by hand; the dissipation never decreased, balance within 1e-3."""
    line = ChainLine(n_links=16, n_masses=1, pretension_N=F0, far_end="tensioner", lumping="drive",
                     tail_mass_kg=10.0, damping=20.0, stribeck=((50.0, 150.0, 20.0, 0.0),),
                     loads=(LoadStep(1, 400.0, 0.0),))
    res = simulate(line, Drive("none"), 0.1, n_out=2000, scheme=scheme)
    F_rest = F0 + 400.0 - 200.0
    np.testing.assert_allclose(-res.u[-1, 1], CL * F_rest + CH * F_rest ** (2 / 3) - XF0, rtol=1e-6)
    assert res.tension[-1, 0] == pytest.approx(F0 + 400.0, rel=1e-9)
    v = res.v[1:, 1]
    assert v.max() < 1e-7 * np.abs(v).max()  # never reverses (but for the elastic settle of the stick at 1e-8 mm/s)
    late = (res.t[1:] > 0.01) & (np.abs(v) > 1e-6)
    assert late.sum() > 500 and np.all(np.diff(np.abs(v[late])) <= 0) and abs(v[-1]) < 1e-8
    assert np.diff(res.dissipated).min() >= 0.0 and res.energy_balance()["relative_error"] < 1e-3
