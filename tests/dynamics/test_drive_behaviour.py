"""Drive laws (chainid.dynamics.drives) pinned by hand: the polygon's position within a tooth, its kinematics during
the start-up ramp, the pitch it uses, the shapes drive_motion returns and the refusal of infinite fields.
Units mm, s, rad."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.dynamics import Drive
from chainid.dynamics.drives import drive_motion


@pytest.mark.parametrize("travel, k, phi", [(12.5, 0, math.pi / 12), (37.5, 1, -math.pi / 12),
                                            (110.0, 2, math.pi / 15), (24.0, 0, 0.48 * math.pi / 3)])
def test_polygon_position_is_whole_pitches_plus_the_chord_offset(travel, k, phi):
    """z = 6, p = 50 mm: R = p/(2 sin(π/6)) = 50 mm, θ = 2π·travel/(z·p) for the mean travel v·t (v = 400 mm/s, no
    ramp); the tooth k = round(θ·z/2π) and φ = θ − 2πk/z: a quarter pitch (12.5 mm) is tooth 0 at φ = π/12, three
    quarters (37.5 mm) tooth 1 at −π/12, 2.2 pitches tooth 2 at π/15, 0.48 pitch still tooth 0.  u = k·p + R sin φ,
    u̇ = R cos φ·θ̇ with θ̇ = 2π·400/300 rad/s, ü = −R sin φ·θ̇² (rel 1e-12).
    Bugs caught: the rounding's + 0.5 (tooth k off by one), k·p garbled, the sign of the chordal acceleration."""
    p, z, v = 50.0, 6, 400.0
    R, thd = 50.0, 2 * math.pi * v / (z * p)
    u, ud, udd = drive_motion(Drive("polygon", v=v, z=z), np.array([travel / v]), p)
    assert u[0] == pytest.approx(k * p + R * math.sin(phi), rel=1e-12)
    assert ud[0] == pytest.approx(R * math.cos(phi) * thd, rel=1e-12)
    assert udd[0] == pytest.approx(-R * math.sin(phi) * thd ** 2, rel=1e-9)


def test_polygon_speed_and_acceleration_during_the_ramp_are_the_derivatives():
    """During a cosine start-up (t_r = 0.2 s to 400 mm/s, z = 6, p = 50 mm) the sprocket accelerates: θ̈ = 2π·ü_r/(z·p)
    and ü = R cos φ·θ̈ − R sin φ·θ̇².  Checked against numpy's central differences of the drive's own position and
    speed on a 1 µs grid over 0.02–0.18 s, away from the tooth changes (where ü jumps); the ramp term is not small
    here (its share of ü up to about 3 m/s²).  Bugs caught: θ̈ taken from the speed or dropped, the ramp's
    acceleration sign."""
    p, z, v, tr = 50.0, 6, 400.0, 0.2
    t = np.arange(0.02, 0.18, 1e-6)
    u, ud, udd = drive_motion(Drive("polygon", v=v, t_ramp=tr, z=z), t, p)
    du, dud = np.gradient(u, t), np.gradient(ud, t)
    smooth = np.abs(np.diff(udd, prepend=udd[0])) < 1.0  # mm/s² per µs: not at a tooth change
    smooth &= np.roll(smooth, 1) & np.roll(smooth, -1)
    smooth[:2] = smooth[-2:] = False
    assert smooth.mean() > 0.99
    np.testing.assert_allclose(ud[smooth], du[smooth], rtol=0, atol=1e-6 * np.abs(ud).max())
    np.testing.assert_allclose(udd[smooth], dud[smooth], rtol=0, atol=1e-5 * np.abs(udd).max())
    ramp_term = 50.0 * 2 * math.pi / (z * p) * 0.5 * v * (math.pi / tr)  # R·θ̈ at its largest [mm/s²]
    assert ramp_term > 0.5 * np.abs(udd).max()


def test_a_polygon_uses_the_drives_own_pitch_else_the_chains():
    """Drive pitch 20 mm on a chain of pitch 50 mm: at a quarter tooth (5 mm of mean travel at 400 mm/s, z = 6) the
    strand is at R sin(π/12) with R = 20/(2 sin(π/6)) = 20 mm; without a pitch of its own the drive takes the pitch
    it is given (50 mm: 12.5 mm of travel is the quarter tooth).
    Bug caught: the pitch fallback inverted (``is not None`` → ``is None``)."""
    own = drive_motion(Drive("polygon", v=400.0, z=6, pitch=20.0), np.array([5.0 / 400.0]), 50.0)[0]
    assert own[0] == pytest.approx(20.0 * math.sin(math.pi / 12), rel=1e-12)
    chain = drive_motion(Drive("polygon", v=400.0, z=6), np.array([12.5 / 400.0]), 50.0)[0]
    assert chain[0] == pytest.approx(50.0 * math.sin(math.pi / 12), rel=1e-12)


@pytest.mark.parametrize("field, value, valid", [("v", math.inf, ">= 0 mm/s"), ("t_ramp", math.inf, ">= 0 s"),
                                                 ("A", math.inf, ">= 0 mm"), ("omega", math.inf, "> 0 rad/s")])
def test_an_infinite_drive_field_is_refused_by_name(field, value, valid):
    """inf satisfies ``>= 0`` but is no speed, time, amplitude or frequency: refused with the field, value and range.
    Bug caught: the finiteness test joined to the range test by ``or``."""
    with pytest.raises(ValueError) as exc:
        Drive("sine", **{field: value})
    assert str(exc.value) == f"drive {field} = inf is invalid: valid range {valid}"


def test_drive_motion_keeps_the_shape_of_its_times():
    """drive_motion returns arrays of the shape of t: a (2, 3) grid of times gives (2, 3) arrays matching the sine law
    A sin ωt, Aω cos ωt, −Aω² sin ωt element by element; a 0-d time gives 0-d arrays."""
    A, w = 1.5, 20.0
    t = np.array([[0.0, 0.01, 0.02], [0.05, 0.1, 0.3]])
    u, ud, udd = drive_motion(Drive("sine", A=A, omega=w), t, 50.0)
    assert u.shape == ud.shape == udd.shape == (2, 3)
    np.testing.assert_allclose(u, A * np.sin(w * t), rtol=0, atol=1e-13)
    np.testing.assert_allclose(ud, A * w * np.cos(w * t), rtol=0, atol=1e-12)
    np.testing.assert_allclose(udd, -A * w * w * np.sin(w * t), rtol=0, atol=1e-10)
    u0, _, _ = drive_motion(Drive("sine", A=A, omega=w), np.float64(0.05), 50.0)
    assert u0.shape == () and float(u0) == pytest.approx(A * math.sin(w * 0.05), rel=1e-13)
