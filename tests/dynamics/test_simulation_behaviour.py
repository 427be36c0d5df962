"""simulate's contract (chainid.dynamics.simulation) pinned by hand: the default limits, the refusal of non-finite or
non-positive inputs, the ends of the option ranges, the explicit fallback threshold of the implicit scheme, the
refinement after a failed run, strict refusals and the energy-balance message against a numpy balance.
Units mm, N, s, kg; energies N·mm."""
from __future__ import annotations

import math
import re
import warnings

import numpy as np
import pytest

from chainid.dynamics import ChainLine, Drive, SimulationError, simulate, stable_step


def _small(**kw):
    return ChainLine(n_links=40, n_masses=4, pretension_N=1_000.0, **kw)


def _quiet(*args, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return simulate(*args, **kw)


def test_the_default_work_limit_is_2e10_node_steps_and_the_memory_limit_2_gib():
    """Without max_work a run estimated above 2e10 node-steps (1e8 s of a 5-node line at 0.25 ms: 2e12) is refused
    quoting the limit, 2e+10; without max_memory one storing 1e9 samples (1.8e11 bytes) is refused quoting 2 GiB
    (2·1024³ bytes).
    Bugs caught: either default constant changed."""
    with pytest.raises(ValueError) as exc:
        simulate(_small(), Drive("none"), 1e8)
    assert "over max_work = 2e+10 node-steps: valid range <= the limit" in str(exc.value)
    with pytest.raises(ValueError) as exc:
        simulate(_small(), Drive("none"), 0.01, n_out=10 ** 9, max_work=None)
    assert "over max_memory = 2 GiB: valid range <= the limit" in str(exc.value)


@pytest.mark.parametrize("value", [0.0, -5.0, math.nan, math.inf, True])
def test_a_peak_force_that_is_not_a_positive_finite_number_is_refused(value):
    """peak_force sets the tangent of the stable step: 0, a negative value, nan, inf and a bool are refused by
    stable_step and by simulate, naming the field, the value and the range "> 0 N".
    Bugs caught: ``v <= 0`` made ``v < 0`` (0 N accepted: a zero Hertz tangent), the finiteness test dropped."""
    msg = f"peak_force = {value!r} is invalid: valid range > 0 N"
    with pytest.raises(ValueError) as exc:
        stable_step(_small(), value)
    assert str(exc.value) == msg
    with pytest.raises(ValueError) as exc:
        simulate(_small(), Drive("none"), 0.01, peak_force=value)
    assert str(exc.value) == msg


@pytest.mark.parametrize("kw, message", [
    (dict(t_end=math.inf), "t_end = inf is invalid: valid range > 0 s (a finite number)"),
    (dict(t_end=0.01, dt=math.nan), "dt = nan is invalid: valid range > 0 s (a finite number)"),
    (dict(t_end=0.01, dt=math.inf, scheme="implicit"), "dt = inf is invalid: valid range > 0 s (a finite number)"),
    (dict(t_end=0.01, max_work=math.inf), "max_work = inf is invalid: valid range > 0 (or None)"),
    (dict(t_end=0.01, safety=0.0), "safety = 0.0 is invalid: valid range 0 < safety <= 1"),
    (dict(t_end=0.01, n_out=10.0), "n_out = 10.0 is invalid: valid range an int >= 2"),
])
def test_non_finite_or_non_positive_numbers_are_refused_by_name(kw, message):
    """Times, steps and limits are finite positive numbers and the safety factor is above 0: each refused with its
    name, value and range before any work.  Bugs caught: the finiteness test joined by ``and`` (inf passes ``> 0``),
    the positivity test made ``< 0``."""
    with pytest.raises(ValueError) as exc:
        simulate(_small(), Drive("ramp", v=100.0), **kw)
    assert str(exc.value) == message


def test_a_safety_of_one_takes_the_stable_step_and_twenty_levels_are_allowed():
    """safety = 1 (the top of 0 < safety <= 1) runs at the stable step itself: dt = t_end/ceil(t_end/dt_stable)
    (here 0.01 s over the step, by hand); substep_levels = 20 (the top of 0 .. 20) is accepted.
    Bugs caught: ``safety > 1`` made ``>= 1``, ``substep_levels <= 20`` made ``< 20``."""
    line = _small()
    dts = stable_step(line)
    res = simulate(line, Drive("ramp", v=100.0, t_ramp=0.005), 0.01, safety=1.0, n_out=2)
    assert res.dt == pytest.approx(0.01 / math.ceil(0.01 / dts - 1e-9), rel=1e-12) and res.dt <= dts
    res = simulate(line, Drive("ramp", v=100.0, t_ramp=0.005), 0.01, scheme="implicit", substep_levels=20, n_out=10)
    assert res.t[-1] == pytest.approx(0.01, rel=1e-12)


def _bouc_wen_line():
    return ChainLine(n_links=40, n_masses=4, pretension_N=50.0, bouc_wen=[[500.0, 0.001, 2.0, 0.5]])


def test_an_implicit_newton_failure_carries_no_peak_force_hint():
    """The hint "peak_force = ... sets the stable step" belongs to the explicit scheme only: a stiff Bouc–Wen
    element failing Newton at dt/2 = 0.5 ms in an implicit run gives the bare message even with a peak force.
    Bugs caught: the scheme test inverted, its ``and`` made ``or``."""
    with pytest.raises(SimulationError) as exc:
        simulate(_bouc_wen_line(), Drive("sine", A=5.0, omega=300.0), 0.05, dt=1e-3, scheme="implicit",
                 substep_levels=1, peak_force=5_000.0)
    assert str(exc.value) == ("the implicit step did not converge even at dt/2 = 0.0005 s (dt = 0.001 s); "
                              "use a smaller dt")


def test_a_failed_run_is_repeated_at_half_the_step_each_refinement():
    """With refine = 2 a run that fails (Newton at the shortest sub-step) is repeated at dt/2 and dt/4: the error of
    the last attempt names dt = 1 ms / 4 = 0.00025 s and its sub-step 0.000125 s (one halving allowed).
    Bug caught: the step after a failure not halved (or by another factor)."""
    with pytest.raises(SimulationError) as exc:
        simulate(_bouc_wen_line(), Drive("sine", A=5.0, omega=300.0), 0.05, dt=1e-3, scheme="implicit",
                 substep_levels=1, refine=2)
    assert str(exc.value).startswith("the implicit step did not converge even at dt/2 = 0.000125 s (dt = 0.00025 s)")


def test_a_stuck_newton_step_falls_back_to_verlet_only_below_nine_tenths_of_the_stable_step():
    """The implicit scheme replaces a sub-step whose Newton iteration is stuck (a damper's force jumping as a segment
    goes taut) by a Verlet sub-step only when it is at most 0.9·dt_stable (a margin below the explicit limit); above
    that it is an error naming the sub-step.  A damped slack line shaken by 1 mm at 60 rad/s with no halving
    (substep_levels = 0), at steps of 0.79–0.88 and 0.92–1.1 × dt_stable: below 0.9 every run completes and some take
    fallback sub-steps; above it no run takes any, and some fail with "did not converge".
    Bugs caught: the threshold's 0.9 made 1.9 (Verlet above the stable step) or below 0 (never a fallback)."""
    line = ChainLine(n_links=40, n_masses=4, pretension_N=20.0, far_end="fixed", damping=20.0)
    d = Drive("sine", A=1.0, omega=60.0)
    dts = stable_step(line)
    below = [_quiet(line, d, 0.2, dt=f * dts, scheme="implicit", substep_levels=0, n_out=10).explicit_fallbacks
             for f in (0.79, 0.8, 0.82, 0.85, 0.87, 0.88)]
    assert sum(below) >= 3
    above = []
    for f in (0.92, 0.94, 0.96, 0.98, 1.02, 1.06, 1.1):
        try:
            above.append(_quiet(line, d, 0.2, dt=f * dts, scheme="implicit", substep_levels=0,
                                n_out=10).explicit_fallbacks)
        except SimulationError as exc:
            assert re.match(r"the implicit step did not converge even at dt/1 = ", str(exc))
            above.append(None)
    assert above.count(None) >= 3 and all(n in (None, 0) for n in above)


def test_strict_refuses_a_peak_that_does_not_converge_under_refinement():
    """A slack polygon drive (20 segments, 500 N, z = 6) whose peak changes by more than PEAK_TOL = 2 % between dt and
    dt/2 with refine = 1: a warning without strict, a SimulationError quoting it with strict.
    Bug caught: the strict test of the peak check inverted or dropped."""
    line = ChainLine(n_links=200, n_masses=20, pretension_N=500.0)
    d = Drive("polygon", v=1500.0, t_ramp=0.2, z=6)
    res = _quiet(line, d, 0.5, refine=1)
    assert res.peak_change > 0.02 and any(w.startswith("peak tension not converged") for w in res.warnings)
    with pytest.raises(SimulationError, match=r"^strict: peak tension not converged under step refinement: "):
        _quiet(line, d, 0.5, refine=1, strict=True)


def test_the_energy_balance_warning_quotes_the_worst_error_its_time_the_scheme_and_the_step():
    """A coarse run (dt = 0.3 ms, 36 steps of 10/36 ms) misses the balance; its warning quotes the worst relative
    residual r = W − ΔE_kin − ΔE_el − D over the scale max(|W|, |ΔE_kin|, |ΔE_el|, |D|), computed here with numpy
    from the result's arrays, the time of that worst point, the scheme and the step, with BALANCE_TOL = 0.001.
    Bugs caught: the tolerance constant, the message's fields swapped."""
    line = ChainLine(n_links=40, n_masses=4, pretension_N=1_000.0, resistance_N=200.0)
    res = _quiet(line, Drive("ramp", v=50.0, t_ramp=0.005), 0.01, dt=3e-4, n_out=10, peak_force=3_000.0)
    dk, de = res.kinetic - res.kinetic[0], res.elastic - res.elastic[0]
    r = res.work_in - dk - de - res.dissipated
    scale = max(np.abs(a).max() for a in (res.work_in, dk, de, res.dissipated))
    k = int(np.argmax(np.abs(r)))
    rel = abs(r[k]) / scale
    assert rel > 1e-3
    want = (f"energy balance error {rel:.3g} at t = {res.t[k]:.6g} s exceeds 0.001 (explicit, dt = {0.01 / 36:.3g} s): "
            "the result is not converged; use a smaller dt or more refinements (and compare the peak under step "
            "refinement)")
    assert want in res.warnings
