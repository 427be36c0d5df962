"""Drive motions (chainid.dynamics.drives): ramp, sine and polygon kinematics in closed form, the largest speed,
field checks.  Units mm, s, rad."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.dynamics import Drive


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


def test_only_a_moving_drive_has_a_speed_and_only_a_sine_with_amplitude_or_a_polygon_a_period():
    """Drive.max_speed of a held end ("none") is 0 whatever its v field; Drive.period is 2π/ω only for a sine of
    amplitude A > 0 (ω = 4 rad/s: 1.5708 s), p/v̄ for the polygon (50 mm at 400 mm/s: 0.125 s; its own pitch 20 mm:
    0.05 s), inf for a ramp or a held end even with A and ω set, and inf for a sine of zero amplitude (no periodic
    excitation, the docstring).
    Bugs caught: the held end's speed constant, ``A > 0`` → ``A >= 0``, the sine test's ``and`` → ``or``."""
    pitch = 50.0
    assert Drive("none", v=250.0).max_speed(pitch) == 0.0
    assert Drive("sine", A=0.5, omega=4.0).period(pitch) == pytest.approx(2 * math.pi / 4.0, rel=1e-15)
    assert Drive("sine", A=0.0, omega=4.0).period(pitch) == math.inf
    assert Drive("ramp", v=100.0, A=2.0, omega=10.0).period(pitch) == math.inf
    assert Drive("none", A=2.0, omega=10.0).period(pitch) == math.inf
    assert Drive("polygon", v=400.0, z=8, A=2.0, omega=10.0).period(pitch) == pytest.approx(0.125, rel=1e-15)
    assert Drive("polygon", v=400.0, z=8, pitch=20.0).period(pitch) == pytest.approx(0.05, rel=1e-15)


@pytest.mark.parametrize("pitch", [0.0, -50.0, math.inf, math.nan])
def test_a_drive_pitch_that_is_not_a_positive_length_is_refused(pitch):
    """A sprocket's pitch is a length: 0, a negative value, inf and NaN are refused by name with the valid range."""
    with pytest.raises(ValueError, match=r"drive pitch = .* is invalid: valid range > 0 mm"):
        Drive("polygon", v=100.0, z=8, pitch=pitch)
    assert Drive("polygon", v=100.0, z=8, pitch=50.0).pitch == 50.0
