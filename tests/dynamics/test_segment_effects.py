"""Each library effect in a chain-line segment against its closed form on the same path.

One segment of the paper's 16-link specimen between the drive (drive lumping) and a fixed far end has no free node:
its elongation is exactly the drive's path x(t) = e_pre + A·sin(ωt), so its tension is the effect's force law on
that path, with no inertia at all.  Independent references: the spring of Eq. 15 typed by hand
(tests/paper_forms.py, inverted by bisection here), and each effect's closed form typed here from the effect
library's definitions (docs: /work/briefs/effects_spec.md): the play of a dead band after each reversal, the Dahl
branches, a Bouc–Wen ODE solved by scipy, the Stribeck law outside its stick, the dead band's power law.
Units mm, N, s, kg.
"""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import paper_forms
from chainid.dynamics import ChainLine, Drive, simulate

CL, CH = paper_forms.coefficients()  # the 16-link specimen: x = CL·F + CH·F^(2/3)
F0 = 2000.0  # N pretension
A, W = 0.3, 2.0  # mm, rad/s
T = 2 * math.pi / W


def f_hand(x, cl=CL, ch=CH, beta=2.0 / 3.0):
    """Inverse of x = cl·F + ch·F^β by bisection [N] (0 for x <= 0); vectorised over x."""
    x = np.atleast_1d(np.asarray(x, float))
    out = np.zeros_like(x)
    for i, xi in enumerate(x):
        if xi <= 0:
            continue
        lo, hi = 0.0, 1.0
        while cl * hi + ch * hi ** beta < xi:
            hi *= 2
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if cl * mid + ch * mid ** beta < xi:
                lo = mid
            else:
                hi = mid
        out[i] = 0.5 * (lo + hi)
    return out


def run_specimen(cycles=2, scheme="explicit", **kw):
    """The one-segment specimen under x = e_pre + A·sin(ωt); returns (result, path x [mm], ẋ [mm/s], e_pre)."""
    line = ChainLine(n_links=16, n_masses=1, pretension_N=F0, far_end="fixed", lumping="drive", **kw)
    res = simulate(line, Drive("sine", A=A, omega=W), cycles * T, dt=T / 4000, n_out=cycles * 4000, scheme=scheme)
    e0 = float(line.pretension_elongation()[0])
    t = res.t
    return res, e0 + A * np.sin(W * t), A * W * np.cos(W * t), e0


def test_a_play_element_stores_no_energy_of_its_own():
    """At the pretension F0, before the first reversal, the specimen with backlash stores the spring's energy alone:
    U(F0) = ∫ F dx for x = CL·F + CH·F^(2/3), i.e. CL·F0²/2 + (2/5)·CH·F0^(5/3) (the play element itself holds
    none, so the stored energy is the plain specimen's to rounding)."""
    res, *_ = run_specimen(backlash_mm=0.06)
    U = CL * F0**2 / 2 + 0.4 * CH * F0 ** (5 / 3)
    assert res.elastic[0] == pytest.approx(U, rel=1e-9)


def test_stiffness_level_scales_the_link_term():
    """ea_scale = 2.5 (effect stiffness_level): the spring is x = CL/2.5·F + CH·F^(2/3) (Eq. 15 by hand) along the
    whole path, and the static tangent at the pretension is 1/(CL/2.5 + ⅔·CH·F0^(−1/3)), with the link term's
    stiffness 2.5× the unmodified one."""
    res, x, _, e0 = run_specimen(ea_scale=2.5)
    assert e0 == pytest.approx(CL / 2.5 * F0 + CH * F0 ** (2 / 3), rel=1e-12)
    np.testing.assert_allclose(res.tension[:, 0], f_hand(x, cl=CL / 2.5), rtol=1e-9)
    line = ChainLine(n_links=16, n_masses=1, pretension_N=F0, far_end="fixed", ea_scale=2.5)
    assert line.static_tangent()[0] == pytest.approx(1 / (CL / 2.5 + 2 / 3 * CH * F0 ** (-1 / 3)), rel=1e-9)
    assert res.energy_balance()["relative_error"] < 1e-6 and res.dissipated[-1] == 0.0


@pytest.mark.parametrize("kw, cl, ch, beta, s", [
    (dict(hertz_scale=1.5, contact_exponent=0.9), CL, 1.5 * CH * 1e4 ** (2 / 3 - 0.9), 0.9, 0.0),  # contact_law
    (dict(compliance=2e-6), CL + 2e-6, CH, 2 / 3, 0.0),  # machine_compliance (mm/N)
    (dict(slack=0.05), CL, CH, 2 / 3, 0.05),  # slack: the spring carries load from x = s
])
def test_contact_law_compliance_and_slack_change_the_spring(kw, cl, ch, beta, s):
    """The stiffness-side effects as the spring x − s = cl·F + ch·F^β (ChainModel's coefficients: a contact law
    keeps δ at F_ref = 1e4 N), on the path and in the static elongation at the pretension."""
    res, x, _, e0 = run_specimen(**kw)
    assert e0 == pytest.approx(s + cl * F0 + ch * F0 ** beta, rel=1e-10)
    np.testing.assert_allclose(res.tension[:, 0], f_hand(x - s, cl, ch, beta), rtol=1e-9)
    assert res.energy_balance()["relative_error"] < 1e-5


def _play_path(x, h):
    """The play output of x with half-width h, started centred (y = x[0]), by its definition on each sample."""
    y = np.empty_like(x)
    yi = x[0]
    for i, xi in enumerate(x):
        yi = min(max(yi, xi - h), xi + h)
        y[i] = yi
    return y


def test_backlash_holds_the_force_over_the_dead_band_after_a_reversal():
    """backlash b = 0.06 mm: the spring acts on the play output, so after each reversal the force does not change
    until x has travelled b; on the sine: y = max(e0, x − b/2) rising first, then y = x_top − b/2 held for
    x >= x_top − b after the top, etc.  Per steady cycle the play returns b·(F_top − F_bottom) (the library's play
    is not passive): the dissipation over the second cycle is −b·(F(x_top − b/2) − F(x_bot + b/2))."""
    b = 0.06
    res, x, xd, e0 = run_specimen(backlash_mm=b)
    Th = res.tension[:, 0]
    top, bot = e0 + A, e0 - A
    first = res.t <= T / 4
    np.testing.assert_allclose(Th[first], f_hand(np.maximum(e0, x[first] - b / 2)), rtol=1e-9)
    after_top = (res.t > T / 4) & (res.t < 3 * T / 4)
    np.testing.assert_allclose(Th[after_top], f_hand(np.minimum(top - b / 2, x[after_top] + b / 2)), rtol=1e-6)
    band = after_top & (x > top - b + 1e-4)  # the dead band after the top: the force is held exactly
    assert band.sum() > 50 and np.ptp(Th[band]) == 0.0
    np.testing.assert_allclose(Th, f_hand(_play_path(x, b / 2)), rtol=1e-6)
    i1 = int(np.argmin(np.abs(res.t - T)))
    loss = res.dissipated[-1] - res.dissipated[i1]
    want = -b * (f_hand(top - b / 2)[0] - f_hand(bot + b / 2)[0])
    assert loss == pytest.approx(want, rel=1e-3)
    assert res.energy_balance()["relative_error"] < 1e-5


def test_deadband_force_is_zero_inside_the_band_and_a_power_law_outside():
    """deadband k_d = 3e3 N/mm^1.5, g = 0.1 mm, p = 1.5, centre x_c = x(F0) + 0.05 mm: the force beyond the spring
    is 0 for |x − x_c| <= g and k_d·sgn(u)·(|u| − g)^1.5 outside (both sides are reached); the static elongation
    is the spring's alone (inside the band).  With x_c = x(F0) − 0.2 mm the band is engaged at rest: the static
    elongation solves F(e) + k_d·(e − x_c − g)^1.5 = F0 (bisection here)."""
    kd, g, p = 3e3, 0.1, 1.5
    xF0 = CL * F0 + CH * F0 ** (2 / 3)
    xc = xF0 + 0.05
    res, x, _, e0 = run_specimen(deadband=(kd, g, p, xc))
    assert e0 == pytest.approx(xF0, rel=1e-12)
    extra = res.tension[:, 0] - f_hand(x)
    u = x - xc
    inside = np.abs(u) <= g
    assert inside.sum() > 100 and (u > g).sum() > 100 and (u < -g).sum() > 100
    np.testing.assert_allclose(extra[inside], 0.0, atol=1e-9 * F0)
    hand = kd * np.sign(u) * np.maximum(np.abs(u) - g, 0.0) ** p
    np.testing.assert_allclose(extra[~inside], hand[~inside], rtol=1e-8, atol=1e-9 * F0)
    assert res.energy_balance()["relative_error"] < 1e-5 and res.dissipated[-1] == 0.0
    xc2 = xF0 - 0.2
    lo, hi = 0.0, 2 * xF0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if f_hand(mid)[0] + kd * max(mid - xc2 - g, 0.0) ** p < F0:
            lo = mid
        else:
            hi = mid
    line = ChainLine(n_links=16, n_masses=1, pretension_N=F0, far_end="fixed", deadband=(kd, g, p, xc2))
    assert line.pretension_elongation()[0] == pytest.approx(lo, rel=1e-9)
    assert lo < xF0 - 1e-3  # the engaged stops carry part of the pretension


def _dahl_path(x, F_h, x_h):
    """Dahl force on the sine path from z = 0 at x[0], branch by branch: z = s·F_h + (z_r − s·F_h)·e^(−|x − x_r|/x_h)
    from the last reversal (x_r, z_r), s the direction."""
    z = np.empty_like(x)
    xr, zr, s = x[0], 0.0, 1.0
    for i, xi in enumerate(x):
        if i > 0 and (xi - x[i - 1]) * s < 0:  # a reversal between the samples: the branch ends at the sample
            xr, zr, s = x[i - 1], z[i - 1], -s
        z[i] = s * F_h + (zr - s * F_h) * math.exp(-abs(xi - xr) / x_h)
    return z


@pytest.mark.parametrize("scheme", ["explicit", "implicit"])
def test_bouc_wen_with_n1_r1_is_dahl(scheme):
    """Bouc–Wen with n = 1, r = 1 (F_y = 150 N, x_y = 0.05 mm) on the segment: its force is the Dahl model's
    exponential branches (typed here) to the accuracy of the operator's travel table (measured 5e-6·F_y); the loss
    per step is never negative beyond the table's accuracy (1e-5·F_y·x_y)."""
    F_y, x_y = 150.0, 0.05
    res, x, _, _ = run_specimen(scheme=scheme, bouc_wen=((F_y, x_y, 1.0, 1.0),))
    extra = res.tension[:, 0] - f_hand(x)
    np.testing.assert_allclose(extra, _dahl_path(x, F_y, x_y), rtol=0, atol=1e-5 * F_y)
    d = np.diff(res.dissipated)
    assert d.min() >= -1e-5 * F_y * x_y and res.energy_balance()["relative_error"] < 1e-5


def test_bouc_wen_shape_against_an_ode_solver():
    """Bouc–Wen n = 2.5, r = 0.6 (F_y = 150 N, x_y = 0.04 mm): the segment's force beyond the spring is F_y·z with
    z the solution of dz/dt = (ẋ/x_y)·[1 − (r·sgn(ẋz) + 1 − r)·|z|^n], z(0) = 0, by scipy's LSODA (rtol 1e-10);
    r >= 0.5: the loss per step is never negative beyond the travel table's accuracy (1e-5·F_y·x_y), and over the
    second cycle it is the loop area ∮F_y·z dx of the ODE solution (trapezoid)."""
    F_y, x_y, n, r = 150.0, 0.04, 2.5, 0.6
    res, x, _, _ = run_specimen(bouc_wen=((F_y, x_y, n, r),))

    def rhs(t, z):
        xd = A * W * math.cos(W * t)
        return [xd / x_y * (1.0 - (r * np.sign(xd * z[0]) + 1.0 - r) * abs(z[0]) ** n)]

    sol = solve_ivp(rhs, (0.0, res.t[-1]), [0.0], method="LSODA", t_eval=res.t, rtol=1e-10, atol=1e-12,
                    max_step=T / 400)
    extra = res.tension[:, 0] - f_hand(x)
    np.testing.assert_allclose(extra, F_y * sol.y[0], rtol=0, atol=2e-5 * F_y)
    assert np.diff(res.dissipated).min() >= -1e-5 * F_y * x_y
    i1 = int(np.argmin(np.abs(res.t - T)))
    zz, xx = F_y * sol.y[0][i1:], x[i1:]
    loop = float(np.sum(0.5 * (zz[1:] + zz[:-1]) * np.diff(xx)))
    assert loop > 0.5 * F_y * A and res.dissipated[-1] - res.dissipated[i1] == pytest.approx(loop, rel=1e-4)


def test_stribeck_follows_its_law_outside_the_stick_and_does_not_drift():
    """Stribeck F_c = 80 N, dF_s = 60 N, v_s = 0.3 mm/s, dF = 15 N: sliding, the force beyond the spring is
    sgn(ẋ)·[F_c + dF_s·exp(−(ẋ/v_s)²)] + dF at the path's ẋ (exactly, at the output times); after each reversal the
    slider sticks over a travel below (F_s + |dF|)·2·c_lin (the stick spring is the link, 1/c_lin), and there
    the force stays inside the static band [−(F_s − dF), F_s + dF].  The second cycle repeats the first (no drift)."""
    F_c, dF_s, v_s, dF = 80.0, 60.0, 0.3, 15.0
    res, x, xd, e0 = run_specimen(stribeck=((F_c, dF_s, v_s, dF),))
    extra = res.tension[:, 0] - f_hand(x)
    stick = 2 * (F_c + dF_s + abs(dF)) * CL
    rev = np.where(res.t < T / 4, e0, np.where((res.t % T) < 3 * T / 4, e0 + A, e0 - A))
    rev = np.where((res.t >= T) & ((res.t % T) < T / 4), e0 - A, rev)
    sliding = np.abs(x - rev) > 1.5 * stick
    assert sliding.mean() > 0.8
    hand = np.sign(xd) * (F_c + dF_s * np.exp(-(xd / v_s) ** 2)) + dF
    np.testing.assert_allclose(extra[sliding], hand[sliding], rtol=0, atol=1e-9 * F0)
    assert extra.max() <= F_c + dF_s + dF + 1e-9 and extra.min() >= -(F_c + dF_s - dF) - 1e-9
    k = 4000  # samples per cycle: after the first reversal (t > T/4) the loop repeats to round-off
    np.testing.assert_allclose(extra[2 * k // 4 + k:2 * k + 1], extra[2 * k // 4:k + 1], rtol=0, atol=1e-9 * F0)
    assert np.diff(res.dissipated).min() >= 0.0 and res.energy_balance()["relative_error"] < 1e-5


@pytest.mark.parametrize("scheme", ["explicit", "implicit"])
def test_fixture_mass_adds_its_inertia_to_the_drive_force_only(scheme):
    """drive_mass_kg = 5 (effect fixture_mass) on the driven node of a 4-mass line (20 links, 5 kN, sine A = 0.2 mm,
    ω = 2π·40 rad/s): the drive force is (m_0 + 5 kg)·a_0·1e-3 + T_1 with a_0 = −A·ω²·sin(ωt) by hand and m_0 = half
    a 5-link segment (0.5 kg); the tensions are those of the same line without it (the drive is prescribed)."""
    w, Am = 2 * math.pi * 40, 0.2
    kw = dict(n_links=20, n_masses=4, pretension_N=5000.0)
    res = simulate(ChainLine(drive_mass_kg=5.0, **kw), Drive("sine", A=Am, omega=w), 0.1, n_out=50, scheme=scheme)
    ref = simulate(ChainLine(**kw), Drive("sine", A=Am, omega=w), 0.1, n_out=50, scheme=scheme)
    np.testing.assert_array_equal(res.tension, ref.tension)
    a0 = -Am * w * w * np.sin(w * res.t)
    np.testing.assert_allclose(res.drive_force, 1e-3 * (0.5 + 5.0) * a0 + res.tension[:, 0], rtol=1e-12, atol=1e-9)
    assert res.energy_balance()["relative_error"] < 1e-3


def test_static_tangent_adds_the_engaged_dead_band_to_the_shifted_spring():
    """One 16-link segment at F0 = 2 kN with slack s = 0.05 mm and a dead band (k_d = 3e3 N/mm^1.5, g = 0.1 mm,
    p = 1.5) centred at x_c = s + x(F0) − 0.25 mm, engaged at rest: the static elongation e solves
    F_s(e − s) + k_d·(e − x_c − g)^1.5 = F0 (bisection here, F_s the inverse of Eq. 15), and the static tangent is
    the spring's 1/(CL + ⅔·CH·F_s^(−1/3)) at its share F_s plus the band's k_d·p·(e − x_c − g)^(p−1) (by hand).
    Bugs caught: the band's tangent dropped or taken as its force, the spring's argument not shifted by s."""
    s, kd, g, p = 0.05, 3e3, 0.1, 1.5
    xc = s + CL * F0 + CH * F0 ** (2 / 3) - 0.25
    lo, hi = s, s + 2.0
    for _ in range(200):
        e = 0.5 * (lo + hi)
        if f_hand(e - s)[0] + kd * max(e - xc - g, 0.0) ** p < F0:
            lo = e
        else:
            hi = e
    e = 0.5 * (lo + hi)
    Fs = f_hand(e - s)[0]
    assert e - xc - g > 0.05 and Fs < F0 - 100.0  # the band is engaged and carries part of the pretension
    line = ChainLine(n_links=16, n_masses=1, pretension_N=F0, far_end="fixed", slack=s, deadband=(kd, g, p, xc))
    assert line.pretension_elongation()[0] == pytest.approx(e, rel=1e-9)
    want = 1.0 / (CL + (2.0 / 3.0) * CH * Fs ** (-1.0 / 3.0)) + kd * p * (e - xc - g) ** (p - 1.0)
    assert line.static_tangent()[0] == pytest.approx(want, rel=1e-7)


def test_an_element_column_that_is_not_a_play_leaves_the_springs_argument_alone():
    """A line with one Jenkins element (kind 0) and no backlash: the spring's argument is the elongation e − s itself
    (here e = e₀ + 0.01 mm), the spring force F_k(e − s), the element loop starts at column 0 and no element state
    is written; only a play (kind 4) in the first column lags the argument and takes that column."""
    from chainid.dynamics.segments import _elastic
    from chainid.dynamics.simulation import core_arguments
    from chainid.dynamics.springs import spring_force

    line = ChainLine(n_links=16, n_masses=4, pretension_N=1_000.0, hysteresis=((2_000.0, 0.05),))
    args, _ = core_arguments(line, Drive("none"), 1e-5, 10, 10)
    cl, ch, hx, hd, sp = args[3], args[4], args[7], args[8], args[10]
    assert hd[0, 0] == 0
    e = float(line.pretension_elongation()[0]) + 0.01
    ys, y = np.zeros((4, 1)), np.zeros((4, 1))
    f, a, *_, first = _elastic(0, e, 0.01, ys, y, cl, ch, hx, hd, sp, False)
    assert a == pytest.approx(e - sp[0, 1], rel=1e-15) and first == 0 and y[0, 0] == 0.0
    assert f == pytest.approx(spring_force(e - sp[0, 1], cl[0], ch[0], sp[0, 0]), rel=1e-15)


@pytest.mark.parametrize("ev", [2.0, 4.0, 7.0])
def test_a_sliding_stribeck_elements_rate_tangent_is_the_derivative_of_its_force(ev):
    """Sliding (a large step at ė = ev mm/s), the Stribeck element's force is F_c + ΔF_s·exp(−(ė/v_s)²) and its
    tangent dT/dė = −2ė/v_s²·ΔF_s·exp(−(ė/v_s)²) (F_c = 50 N, ΔF_s = 30 N, v_s = 5 mm/s: −4.090 N·s/mm at 2 mm/s),
    equal to a central difference of the force (h = 10⁻⁵ mm/s).  The implicit scheme's Newton step uses it."""
    from chainid.dynamics.segments import _element

    q, tabs = np.array([30.0, 5.0, 0.0]), np.zeros((0, 2, 2))
    _, force, _, _, tangent = _element(2, 0.0, 10.0, 0.1, ev, 50.0, 1000.0, q, tabs)
    w = math.exp(-(ev / 5.0) ** 2)
    assert force == pytest.approx(50.0 + 30.0 * w, rel=1e-12)
    assert tangent == pytest.approx(-2.0 * ev / 25.0 * 30.0 * w, rel=1e-12)
    h = 1e-5
    fd = (_element(2, 0.0, 10.0, 0.1, ev + h, 50.0, 1000.0, q, tabs)[1]
          - _element(2, 0.0, 10.0, 0.1, ev - h, 50.0, 1000.0, q, tabs)[1]) / (2 * h)
    assert tangent == pytest.approx(fd, rel=1e-6)
