"""Mesh convergence of the lumped chain: tension wave speed and peak tension as N grows (units mm, N, s, kg)."""
import math

import numpy as np
import pytest

from chainid.dynamics import ChainLine, Drive, simulate
from chainid.generated.stiffness_paper import stiffness_array

F0 = 20_000.0  # N pretension
V = 50.0       # mm/s drive speed (small: ΔT ≈ 0.5 kN << F0, the waves are nearly linear)
T_RAMP = 0.005  # s


def _wave(N):
    """(front speed c_num, wave speed sqrt(k_e·ℓ_s/ρ_l), peak tension rise, impedance Z) of a 32 m chain."""
    line = ChainLine(n_links=640, n_masses=N, pretension_N=F0, far_end="fixed")
    cl, ch = line.segment_coefficients()
    k = np.array([stiffness_array(np.array([e]), a, b)[0] for e, a, b in zip(line.pretension_elongation(), cl, ch)])
    kl = float(np.mean(k * line.segment_lengths()))  # N: k_e·ℓ_s (the same for every segment up to 1 contact)
    rho = line.chain.mass_per_m  # kg/m = 1e-3 kg/mm
    c = math.sqrt(kl / (rho * 1e-3)) * math.sqrt(1e3)  # mm/s: √(N / (kg/mm)) = √(1e3 mm²/s²)
    Z = math.sqrt(kl * rho * 1e-3 * 1e-3)  # N·s/mm: T = Z·v for a wave front of speed jump v
    L = line.length_mm
    res = simulate(line, Drive("ramp", v=V, t_ramp=T_RAMP), T_RAMP / 2 + 1.9 * L / c, n_out=4000)
    mid = 0.5 * (res.positions[:-1] + res.positions[1:])
    j = int(np.argmin(np.abs(mid - L / 2)))
    dT = res.tension[:, j] - F0
    half = 0.5 * Z * V
    i = int(np.argmax(dT > half))
    t_arr = res.t[i - 1] + (half - dT[i - 1]) * (res.t[i] - res.t[i - 1]) / (dT[i] - dT[i - 1])
    return mid[j] / (t_arr - T_RAMP / 2), c, res.peak_tension - F0, Z


def test_wave_front_speed_and_peak_converge():
    rows = [_wave(N) for N in (20, 40, 80, 160)]
    err = [abs(cn / c - 1) for cn, c, _, _ in rows]
    peaks = [p for _, _, p, _ in rows]
    # front speed (half-rise arrival at mid-length) -> sqrt(k_e l_s / rho_l), monotonically
    assert err[0] > err[1] > err[2] > err[3]
    assert err[3] < 1e-3
    # peak tension converges (differences shrink) to the reflected front 2·Z·v at the fixed end
    d = np.abs(np.diff(peaks))
    assert d[1] < d[0] and d[2] < d[1]
    Z = rows[-1][3]
    assert peaks[-1] == pytest.approx(2 * Z * V, rel=2e-2)
