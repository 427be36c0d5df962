"""The independent device simulations the recovery tests take as truth (:mod:`sim_devices`), checked against closed
forms: exact motion derivatives against finite differences, the Bouc–Wen/Dahl state on monotone paths (Dahl:
z = 1 − e^(−x/x_h); n = 2: z = tanh(x/x_y); r = 1/2, n = 2 unloading: dz/dx = 1/x_y), a Maxwell branch on a ramp
(F = k_m·v·τ_m·(1 − e^(−t/τ_m))), and the resonator against its steady-state transfer function.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import sim_devices as sd


@pytest.mark.parametrize("motion", [
    sd.multisine(8.0, 0.5, 10.0, 1.0, 0.3, seed=1),
    sd.onset(sd.multisine(8.0, 0.5, 10.0, 1.0, seed=3), 2.0, 0.5),
    sd.between_rests(sd.multisine(20.0, 0.2, 4.0, 1.0, seed=1), 1.0, 19.0, 1.0),
    sd.chirp(0.5, 8.0, 1.5, 6.5, 1.0, 0.3),
], ids=["multisine", "onset", "between_rests", "chirp"])
def test_motion_derivatives_are_exact(motion):
    t = np.linspace(0.0, 8.0, 160001)
    x, xd, xdd = motion(t)
    h = t[1] - t[0]
    # central differences: error (h²/6)·x''' — below 1e-4 of the signal here
    assert np.max(np.abs(np.gradient(x, h)[1:-1] - xd[1:-1])) <= 1e-4 * np.max(np.abs(xd))
    assert np.max(np.abs(np.gradient(xd, h)[1:-1] - xdd[1:-1])) <= 1e-4 * np.max(np.abs(xdd))


def test_periodic_multisine_is_whole_periods():
    mo = sd.multisine(8.0, 0.5, 10.0, 1.0, seed=2, periodic=True)
    a, b = mo(np.array([0.0, 8.0]))[0], mo(np.array([1e-3, 8.0 + 1e-3]))[0]
    assert a[0] == pytest.approx(a[1], abs=1e-9) and b[0] == pytest.approx(b[1], abs=1e-9)
    x = mo(np.arange(4000) / 500.0)[0]
    assert np.std(x) == pytest.approx(1.0, rel=1e-6)  # RMS as asked (lines on the grid are orthogonal)


def test_dahl_and_bouc_wen_states_on_monotone_paths():
    x = np.linspace(0.0, 0.5, 2001)
    assert np.max(np.abs(sd.bouc_wen_z(x, 0.1, 1.0, 1.0) - (1 - np.exp(-x / 0.1)))) <= 1e-9
    assert np.max(np.abs(sd.bouc_wen_z(x, 0.1, 2.0, 0.6) - np.tanh(x / 0.1))) <= 1e-9
    # load to z = tanh(3), then unload by 0.05 mm with r = 1/2, n = 2: dz/dx = 1/x_y exactly
    path = np.concatenate([np.linspace(0.0, 0.3, 1201), np.linspace(0.3, 0.25, 201)[1:]])
    z = sd.bouc_wen_z(path, 0.1, 2.0, 0.5)
    assert z[1200] == pytest.approx(math.tanh(3.0), abs=1e-9)
    assert z[-1] == pytest.approx(math.tanh(3.0) - 0.05 / 0.1, abs=1e-9)


def test_maxwell_branch_on_a_ramp():
    t = np.linspace(0.0, 2.0, 4001)
    F = sd.maxwell_force(t, 3.0 * t, 5.0, 0.3)
    assert np.max(np.abs(F - 5.0 * 3.0 * 0.3 * (1 - np.exp(-t / 0.3)))) <= 1e-9


def test_resonator_reaches_its_steady_state_response():
    m, c, k, f = 2.0, 0.4, 20.0, 12.0
    t = np.arange(0, 6000) / 1000.0
    x, xd, xdd = sd.resonant_response(lambda tt: 5.0 * np.sin(2 * np.pi * f * tt), t, m, c, k)
    w = 2 * np.pi * f
    H = 1.0 / (k - m * 1e-3 * w**2 + 1j * c * w)  # mm/N
    late = t > 4.0  # the free response decays as exp(-c/(2m·1e-3)·t) = exp(-100 t)
    ref = 5.0 * np.imag(H * np.exp(1j * w * t[late]))
    assert np.max(np.abs(x[late] - ref)) <= 1e-6 * np.max(np.abs(ref))
    assert np.max(np.abs(xd[late] - 5.0 * np.imag(1j * w * H * np.exp(1j * w * t[late])))) <= 1e-6 * w * np.max(np.abs(ref))


@pytest.mark.parametrize("c", [0.02, 0.6])  # damping ratio 0.05 and 1.5: complex and real roots
def test_resonator_closed_form_from_rest_matches_an_integrator(c):
    """The closed-form line response (steady state + free response from rest) against solve_ivp on one force."""
    m, k = 2.0, 20.0
    t = 0.3721 + np.arange(0, 3000) / 1000.0  # from rest at t[0] = 0.3721 s, not at 0
    lines = sd.force_sines(3.0, 2.0, 30.0, 5.0, seed=3)
    x, xd, _ = sd.resonant_response(lines, t, m, c, k)
    xi, xdi, _ = sd.resonant_response(lambda tt: lines(tt), t, m, c, k)  # not a LineForce: integrated
    assert abs(x[0]) <= 1e-12 * np.max(np.abs(x)) and abs(xd[0]) <= 1e-12 * np.max(np.abs(xd))
    assert np.max(np.abs(x - xi)) <= 1e-7 * np.max(np.abs(xi))
    assert np.max(np.abs(xd - xdi)) <= 1e-7 * np.max(np.abs(xdi))
