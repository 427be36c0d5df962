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
    assert f"({math.floor(100 * T / res.dt) / 100:.4g} steps per period; valid >= 20)" in msg[0]


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


def test_resolution_thresholds_are_20_steps_and_2_samples_per_period_exactly():
    """resolution_warnings on a sine of ω = 123.456 rad/s (T = 2π/ω = 0.050894 s, by hand): a step of exactly T/20
    and outputs exactly T/2 apart are resolved (no warning); outputs 0.45·T apart (2.2 per period) are too; a step
    5 % above T/20 (20/1.05 = 19.047…, cut to 19.04 steps per period: never rounded up to the threshold) warns once,
    naming ω to 4 digits (123.5) and the largest valid step T/20 = 0.00254 s; outputs 0.55·T apart warn once with
    their interval and 1/0.55 = 1.818…, cut to 1.81 samples per period.  A ramp has no period: never a warning.
    Bugs caught: the bounds made inclusive, the sample bound T/2 → T/3, the 20 steps, the hint's T/20, the digits."""
    from chainid.dynamics.resolution import resolution_warnings

    w = 123.456
    T = 2 * math.pi / w
    d = Drive("sine", A=0.1, omega=w)
    assert resolution_warnings(d, 50.0, T / 20, T / 2) == []
    assert resolution_warnings(d, 50.0, T / 40, 0.45 * T) == []
    (msg,) = resolution_warnings(d, 50.0, 1.05 * T / 20, 1e-9)
    assert msg.startswith("the drive (sine, ω = 123.5 rad/s: period 0.0509 s) is not resolved by the time step dt = "
                          "0.00267 s (19.04 steps per period; valid >= 20)")
    assert f"give dt <= {T / 20:.3g} s (--dt)" in msg and f"{T / 20:.3g}" == "0.00254"
    (msg,) = resolution_warnings(d, 50.0, T / 40, 0.55 * T)
    assert msg.startswith("the drive (sine, ω = 123.5 rad/s: period 0.0509 s) is sampled every 0.028 s by the "
                          "outputs (1.81 per period; valid >= 2)")
    assert resolution_warnings(Drive("ramp", v=1e9, t_ramp=0.0), 50.0, 1.0, 1.0) == []


def test_an_unresolved_polygon_warning_names_the_mean_speed_and_one_pitch():
    """A polygon drive at v̄ = 1234.56 mm/s on a 50 mm pitch has the period p/v̄ = 0.0405 s (by hand); a step of
    0.01 s is 4.05 steps per period: one warning naming the speed to 4 digits (1235 mm/s) and 'one pitch'."""
    from chainid.dynamics.resolution import resolution_warnings

    (msg,) = resolution_warnings(Drive("polygon", v=1234.56, z=8), 50.0, 0.01, 0.01)
    assert msg.startswith("the drive (polygon, v = 1235 mm/s, one pitch: period 0.0405 s) is not resolved by the "
                          "time step dt = 0.01 s (4.05 steps per period; valid >= 20)")


def test_a_count_just_under_the_threshold_is_cut_not_rounded_up_to_it():
    """A step of T/19.998 gives 19.998 steps per period: the warning reads 19.99, never 20 (rounded, it would say
    "20 steps per period; valid >= 20", which reads as no fault)."""
    from chainid.dynamics.resolution import resolution_warnings

    T = 2 * math.pi / 100.0
    (msg,) = resolution_warnings(Drive("sine", A=0.1, omega=100.0), 50.0, T / 19.998, 1e-9)
    assert "(19.99 steps per period; valid >= 20)" in msg
