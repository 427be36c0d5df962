"""A periodic drive that the time step does not resolve (fewer than 20 steps per period) is a warning naming the
period and the step, and one that the stored outputs sample fewer than twice per period is a warning too (the
series alias it); a resolved drive runs without either.  Periods by hand: 2π/ω for a sine, pitch/v̄ for the
polygon effect (14×50 chain: 50 mm)."""
from __future__ import annotations

import math
import warnings

import pytest

from chainid.dynamics import ChainLine, Drive, simulate

LINE = ChainLine(n_links=100, n_masses=10, pretension_N=5000.0)


def _run(drive, t_end, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return simulate(LINE, drive, t_end, **kw)


def test_an_unresolved_sine_drive_warns():
    w = 1e7
    res = _run(Drive("sine", A=0.1, omega=w), 0.01)
    T = 2 * math.pi / w
    msg = [m for m in res.warnings if "is not resolved by the time step" in m]
    assert len(msg) == 1
    assert f"period {T:.3g} s" in msg[0] and f"dt = {res.dt:.3g} s" in msg[0]
    assert f"({T / res.dt:.3g} steps per period; valid >= 20)" in msg[0]


def test_an_unresolved_polygon_drive_warns():
    v = 5e6  # mm/s: one 50 mm pitch every 1e-5 s
    res = _run(Drive("polygon", v=v, t_ramp=0.0, z=8), 0.002, max_work=None)
    msg = [m for m in res.warnings if "is not resolved" in m]
    assert len(msg) == 1 and f"period {50.0 / v:.3g} s" in msg[0]


def test_outputs_that_alias_a_resolved_drive_warn():
    w = 2 * math.pi * 100.0  # period 0.01 s: resolved by the step, but 500 outputs over 10 s are 0.02 s apart
    res = _run(Drive("sine", A=0.01, omega=w), 10.0)
    assert res.dt < 0.01 / 20
    msg = [m for m in res.warnings if "by the outputs" in m]
    assert len(msg) == 1 and "(0.5 per period; valid >= 2)" in msg[0]


@pytest.mark.parametrize("drive", [Drive("sine", A=0.1, omega=2 * math.pi * 5), Drive("ramp", v=1000.0, t_ramp=0.2),
                                   Drive("polygon", v=1000.0, t_ramp=0.2, z=8)])
def test_a_resolved_drive_gives_no_resolution_warning(drive):
    res = _run(drive, 0.5)
    assert not [m for m in res.warnings if "resolved" in m or "by the outputs" in m]
