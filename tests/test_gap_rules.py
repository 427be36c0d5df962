"""Pins of the gap layer's small documented rules (verdict warnings, terminal summary, second-plateau message,
ringing ratio, benchmark effect texts, step 0's baseline) to hand-computed values (issue 20 §5: the survivors of
the seed-21 mutation run, `benchmarks/mutation_survivors_seed21.md`).

Units: N, s, mm, Hz.
"""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from chainid.gap.core import verdict as vd
from chainid.gap.benchmark.nonharmonic import effect_spec
from chainid.gap.harmonic.prepare import other_plateau
from chainid.gap.core.summary import summary
from chainid.gap.timedomain.where import PEAK, RING_RATIO, ringing
from stand_ins import localise_viscous_excess

STAT_OK = {"stationary": True, "trend_change_N": 0.0, "finding": ""}


# ---------------------------------------------------------------- verdict.decide
def _decide(consistent, final, best):
    warn: list[str] = []
    v = vd.decide(consistent, final, dict(STAT_OK), 1.0, [], {"stop": "STOP"}, [], warn, best=best)
    return v, warn


def test_no_effect_warning_only_when_the_verdict_is_unexplained():
    """'no effect passed the step rule' is said only for an `unexplained` verdict with no final step and a best
    candidate (documented in decide).  Bug caught: `and` → `or` (the warning on a `none` verdict)."""
    best = SimpleNamespace(names=("friction",), shrinkage=0.9)
    assert _decide(True, None, best) == ("none", [])  # the baseline is at the noise: nothing to warn about
    v, warn = _decide(False, None, best)
    assert v == "unexplained" and warn == ["no effect passed the step rule (STOP)"]
    assert _decide(False, None, None) == ("unexplained", [])  # no candidate at all: no step rule was tried
    final = SimpleNamespace(names=("friction", "slack"), shrinkage=vd.MIN_SHRINK)
    assert _decide(False, final, best) == ("friction+slack", [])
    short = SimpleNamespace(names=("friction",), shrinkage=0.99 * vd.MIN_SHRINK)
    assert _decide(False, short, best) == ("unexplained", [])


# ---------------------------------------------------------------- summary
def _result(**baseline):
    b = {"model": "linear", "damping_law": "viscous", "nrmse_train": 0.1, "nrmse_holdout": 0.2,
         "db_over_noise": 3.0, "excess_rms_N": 5.0, "noise_sigma_N": 2.0} | baseline
    return {"baseline": b, "where": [], "ranking": [], "verdict": "none", "steps": []}


def test_summary_says_the_damping_law_reason_unless_given():
    """The baseline's damping-law reason is printed when the law was chosen (auto), not when the user gave it,
    and a result without a reason has no such line.  Bug caught: `and` → `or` in the condition."""
    assert "  damping law:" not in summary(_result())
    assert "  damping law:" not in summary(_result(damping_law_reason="given"))
    txt = summary(_result(damping_law_reason="4 training tests: a law with <= 3 coefficients"))
    assert "  damping law: 4 training tests: a law with <= 3 coefficients" in txt.splitlines()
    assert "VERDICT: none" in txt


# ---------------------------------------------------------------- prepare.other_plateau
def test_second_plateau_named_with_its_distance_from_the_steady_mean():
    """A whole cycle at the plateau amplitude about a mean more than half that amplitude away is a second steady
    state; the message gives its index, amplitude, mean and distance |8 − 5| = 3 mm (by hand).  Ramp cycles
    (amplitude 40 % off) and cycles within half an amplitude of the mean do not count."""
    win = SimpleNamespace(cycle_amplitudes=[1.2, 2.0, 2.0, 2.0, 2.0, 2.1, 1.9], cycle_means=[9.0, 5.0, 5.1, 4.9, 5.0,
                          5.9, 8.0], cycles_kept=[1, 2, 3, 4], plateau_A=2.0)
    msg = other_plateau(win)
    # cycle 0 is a ramp (1.2/2 − 1 = −40 %), cycle 5 is 0.9 mm < 1 mm (half the amplitude) from the mean 5.0
    assert msg.startswith("not one steady harmonic test: cycle 6 oscillates at the plateau amplitude (1.9 mm)")
    assert "about x = 8 mm, 3 mm from the steady window's mean" in msg
    win.cycle_means = [9.0, 5.0, 5.1, 4.9, 5.0, 5.9, 5.8]
    assert other_plateau(win) == ""


# ---------------------------------------------------------------- where_time.ringing
def _ring_case(burst_everywhere: bool):
    fs, n = 1000.0, 8000
    t = np.arange(n) / fs
    xd = 2 * math.pi * np.cos(2 * math.pi * 1.0 * t)  # x = sin(2π t): 1 Hz motion
    sliding = np.abs(xd) >= 0.2 * np.quantile(np.abs(xd), 0.99)
    hum = 5.0 * np.sin(2 * math.pi * 60.0 * t)  # 60 Hz, far above the cut 4 × 2 Hz
    res = hum if burst_everywhere else np.where(sliding, hum, 0.0) + 0.05 * np.random.default_rng(1).normal(size=n)
    d = SimpleNamespace(test="R", f_band=2.0, fs=fs, xd=xd)
    return ringing([d], {"R": res}), sliding


def test_ringing_needs_the_sliding_residual_above_the_rest():
    """A narrow 60 Hz tone of the same amplitude while sliding and at rest (mains hum, a sensor resonance) is not
    chatter: its sliding/rest mean-square ratio is 1 (by construction), below RING_RATIO, although its spectral
    peak is narrow.  The same tone only while sliding is chatter: ratio (25/2)/0.05² ≫ RING_RATIO.
    Bug caught: the ratio replaced by inf when the rest has power (`rest > 0` → `rest <= 0`)."""
    hum, _ = _ring_case(True)
    assert hum["peak_ratio"] >= PEAK and hum["ratio"] == pytest.approx(1.0, abs=0.1)
    assert hum["chatter"] is False and hum["kind"] == "ringing" and hum["score"] == 0.0  # reported, not ranked
    chat, _ = _ring_case(False)
    assert chat["ratio"] > 100 * RING_RATIO and chat["chatter"] is True and chat["kind"] == "chatter"
    assert chat["score"] == chat["rms_N"]
    assert chat["frequency_Hz"] == pytest.approx(60.0, abs=2.0)
    assert chat["rms_N"] == pytest.approx(5.0 / math.sqrt(2), rel=0.05)  # RMS of the 5 N tone while sliding


# ---------------------------------------------------------------- benchmark_time.effect_spec
@pytest.mark.parametrize("effect, level, want", [
    ("friction", 2.0, "friction:F_c=200"),  # 0.1 · 2 · S
    ("hysteresis", 1.5, "hysteresis:F_h=150,x_h=0.15"),  # 0.1 · 1.5 · S, 0.3 · Amin
    ("backlash", 2.0, "backlash:b=0.1"),  # 0.1 · 2 · Amin
    ("slack", 3.0, "slack:s=0.15"),
    ("machine_compliance", 2.5, "machine_compliance:c=0.001"),  # 0.1 · 2.5 / k
    ("stiffness_level", 2.0, "stiffness_level:scale=0.8"),  # 1 − 0.1 · level below level 3
    ("stiffness_level", 3.0, "stiffness_level:scale=1.3"),  # a stiffer chain from level 3 on
    ("contact_law", 2.0, "contact_law:scale=1.6"),  # 1 + 0.3 · level
    ("sensor_delay", 2.0, "sensor_delay:tau=0.03"),  # 0.15 · 2 / wmax
    ("damping_law", 2.0, "damping_law:eta=0.2"),
])
def test_benchmark_effect_text_by_hand(effect, level, want):
    """S = 1000 N, k = 250 N/mm, Amin = 0.5 mm, wmax = 10 rad/s: the `--effect` texts computed by hand from the
    documented strengths."""
    assert effect_spec(effect, level, 1000.0, 250.0, 0.5, 10.0) == want


# ---------------------------------------------------------------- modelio.step_models
def test_step_models_baseline_is_step_zero_and_step_zero_is_bare():
    """Every step's model is compared with step 0 (the baseline: the base spring and the fitted damping, no effect,
    no delay); step 0's own baseline is that same bare model, so both predict the same force on any record.
    The truth here is a pure 0.05 s force-channel lag: the last step carries it, step 0 does not."""
    from chainid.gap.benchmark.grid import grid3x3_plan
    from chainid.gap.diagnose import diagnose
    from chainid.model.base import ChainModel
    from chainid.model.effects import parse_effect
    from chainid.model.laws import PolynomialLaw
    from chainid.records.simulate import simulate

    model = ChainModel()
    recs = simulate(grid3x3_plan(prefix=""), model, PolynomialLaw([0.5, 1.0, 100.0, 20.0, 50.0]), n_cycles=6,
                    samples_per_cycle=96, noise_F=2.0, seed=1, force_fn=parse_effect("sensor_delay:tau=0.05", model))
    res = diagnose(recs, ["3", "7", "11"], model, max_combo=1, uncertainty=False, quiet=True)
    assert res["verdict"] == "sensor_delay"
    models = res["_models"]
    assert len(models) == len(res["steps"]) == 2
    assert models[0].effects == [] and models[0].delay_s == 0.0
    assert models[1].delay_s == pytest.approx(0.05, rel=0.05) and models[1].baseline is models[0]
    b0 = models[0].baseline
    assert b0.effects == [] and b0.delay_s == 0.0 and b0.base is models[0].base
    r = recs[0]
    t, x = np.asarray(r.t, float), np.asarray(r.x, float)
    np.testing.assert_allclose(b0.force(t, x), models[0].force(t, x), rtol=1e-12, atol=1e-9)


# ---------------------------------------------------------------- plot_steps.waterfall_figure
def test_waterfall_figure_bars_shrinkage_and_noise_floor():
    """Bars of the held-out NRMSE per step (0.4 → 0.1 → 0.05), each later bar annotated with its shrinkage against
    the previous (−75 %, −50 %), and the noise floor 0.05/10^(6/20) = 0.02506 (the last step 6 dB over the noise)
    as a dashed line; log axis from min/3 to max·4 (by hand)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from chainid.gap.core.plot_steps import waterfall_figure

    steps = [{"effect": "baseline", "nrmse_holdout": 0.4, "db_over_noise": 24.0},
             {"effect": "friction", "nrmse_holdout": 0.1, "db_over_noise": 12.0},
             {"effect": "slack", "nrmse_holdout": 0.05, "db_over_noise": 6.0}]
    fig = waterfall_figure({"steps": steps, "verdict": "friction+slack"})
    try:
        ax = fig.axes[0]
        assert [p.get_height() for p in ax.patches] == [0.4, 0.1, 0.05]
        assert [a.xy for a in ax.texts[:3]] == [(0.0, 0.4), (1.0, 0.1), (2.0, 0.05)]  # on top of each bar's centre
        assert [t.get_text() for t in ax.get_xticklabels()] == ["baseline", "+ friction", "+ slack"]
        texts = [t.get_text() for t in ax.texts]
        assert texts[:3] == ["0.4\n24.0 dB", "−75 %\n0.1\n12.0 dB", "−50 %\n0.05\n6.0 dB"]
        floor = 0.05 / 10 ** (6.0 / 20)
        (line,) = ax.lines
        assert line.get_ydata()[0] == pytest.approx(floor, rel=1e-12) and line.get_linestyle() == "--"
        assert texts[3] == "noise floor"
        assert ax.get_yscale() == "log"
        assert ax.get_ylim() == (pytest.approx(floor / 3, rel=1e-12), pytest.approx(1.6, rel=1e-12))
        assert ax.get_title() == "explanation chain: friction+slack" and ax.get_ylabel() == "held-out NRMSE"
        # below the noise (dB < 0) the floor is the last step itself
        steps[-1]["db_over_noise"] = -3.0
        fig2 = waterfall_figure({"steps": steps})
        assert fig2.axes[0].lines[0].get_ydata()[0] == pytest.approx(0.05, rel=1e-12)
        plt.close(fig2)
    finally:
        plt.close(fig)


# ---------------------------------------------------------------- problem.damping_separable
def test_damping_separable_needs_three_by_three_and_six_tests():
    """Eq. 21 has 5 coefficients: separable on >= 6 tests at >= 3 frequencies and >= 3 amplitudes (full rank);
    five such tests, or 9 tests at 2 amplitudes, are not, and the message counts them."""
    from chainid.gap.harmonic.problem import damping_separable

    plan = [(1.0, 0.1), (2.0, 0.2), (4.0, 0.3), (1.0, 0.3), (2.0, 0.1), (4.0, 0.2)]
    data = [SimpleNamespace(omega=w, A=a) for w, a in plan]
    assert damping_separable(data) == (True, "")
    ok, msg = damping_separable(data[:5])  # full rank (cond 84) but no test left over: not separable
    assert not ok and msg.startswith("the training plan has 5 tests at 3 distinct frequencies and 3 distinct "
                                     "amplitudes (cond 84);")
    two = [SimpleNamespace(omega=w, A=a) for w in (1.0, 2.0, 4.0) for a in (0.1, 0.2, 0.2)]
    ok, msg = damping_separable(two)
    assert not ok and "9 tests at 3 distinct frequencies and 2 distinct amplitudes" in msg


# ---------------------------------------------------------------- prepare.fourier_x / phase_grid
def test_fourier_x_reproduces_a_two_harmonic_motion_and_its_derivatives():
    """x = 2 + 0.3 sin ψ + 0.05 cos 3ψ, ψ = 5t + 0.2 (inside the 5-harmonic basis): x, ẋ = 1.5 cos ψ − 0.75 sin 3ψ,
    ẍ = −7.5 sin ψ − 11.25 cos 3ψ, exact to round-off at any t."""
    from chainid.gap.harmonic.prepare import fourier_x

    t = np.linspace(0.0, 3.0, 700)
    ps = 5 * t + 0.2
    f = fourier_x(t, 2 + 0.3 * np.sin(ps) + 0.05 * np.cos(3 * ps), 5.0, 0.2)
    ts = np.array([-1.0, 0.37, 10.0])
    p = 5 * ts + 0.2
    x, xd, xdd = f(ts)
    np.testing.assert_allclose(x, 2 + 0.3 * np.sin(p) + 0.05 * np.cos(3 * p), rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(xd, 1.5 * np.cos(p) - 0.75 * np.sin(3 * p), rtol=1e-9, atol=1e-10)
    np.testing.assert_allclose(xdd, -7.5 * np.sin(p) - 11.25 * np.cos(3 * p), rtol=1e-9, atol=1e-9)


def test_phase_grid_commensurate_sampling_is_one_point_per_phase():
    """64 samples per cycle over 3 cycles, 8 bins: the grid has the 64 distinct phases (weight 3 each, 24 per bin) at
    t = (ψ − θ)/ω in [0, T), and a grid mean of any function of ψ equals the samples' bin mean exactly."""
    from chainid.gap.harmonic.prepare import phase_grid

    w, th, B = 2 * math.pi, math.pi / 64, 8  # phases half a sample off the bin edges
    t = np.arange(3 * 64) / 64.0
    psi = np.mod(w * t + th, 2 * math.pi)
    g = phase_grid(psi, B, th, w, lambda ts: (np.sin(w * ts), np.cos(w * ts), -np.sin(w * ts)))
    np.testing.assert_allclose(g["t"], np.arange(64) / 64.0, atol=1e-12)
    # cells may split one phase by round-off (ψ mod 2π): the weights still count every sample in its own bin
    assert np.bincount(g["bin"], weights=g["w"]).tolist() == [24.0] * 8
    assert np.bincount(g["map"], weights=g["w"]).tolist() == [3.0] * 64
    np.testing.assert_allclose(g["x"], np.sin(w * g["t"]), atol=1e-12)
    bins = np.minimum((psi / (2 * math.pi) * B).astype(int), B - 1)
    counts = np.bincount(bins, minlength=B).astype(float)
    binmean = np.bincount(bins, weights=np.sin(w * t) ** 3, minlength=B) / counts  # x(t) = sin(ωt) sampled
    gridmean = np.bincount(g["bin"], weights=g["w"] * (g["x"] ** 3)[g["map"]], minlength=B) / counts
    np.testing.assert_allclose(gridmean, binmean, atol=1e-12)


def test_ringing_is_not_looked_for_when_the_band_reaches_the_sampling():
    """The ringing check needs room above the band: a record whose cut 4·f_band is at or above 0.2·fs (here
    4·6 = 24 Hz ≥ 20 Hz at fs = 100 Hz) is skipped, so one such record gives no finding at all."""
    fs = 100.0
    t = np.arange(4000) / fs
    xd = np.cos(2 * math.pi * t)
    res = np.where(np.abs(xd) > 0.2, 5.0 * np.sin(2 * math.pi * 40.0 * t), 0.0)
    assert ringing([SimpleNamespace(test="R", f_band=6.0, fs=fs, xd=xd)], {"R": res}) == {}
    assert ringing([SimpleNamespace(test="R", f_band=4.9, fs=fs, xd=xd)], {"R": res}) != {}  # 19.6 Hz < 20 Hz


def test_state_maps_skip_a_variable_with_two_levels_and_go_on():
    """A displacement with two levels has < 3 distinct quantile edges and gets no map; the other variables are
    still mapped: a residual 10·ẋ/max|ẋ| (σ = 0.1 N) is found to follow ẋ."""
    from chainid.gap.timedomain.where import state_maps

    t = np.linspace(0.0, 8.0, 4000)
    xd = np.cos(2 * math.pi * t)
    x = np.where(np.sin(2 * math.pi * t) > 0, 2.0, 1.0)
    d = SimpleNamespace(test="R", t=t, x=x, xd=xd, sigma=0.1)
    r = 10.0 * xd + 0.1 * np.random.default_rng(2).normal(size=t.size)
    maps = state_maps([d], {"R": r}, {"R": 5.0 * t})
    names = [m["variable"] for m in maps]
    assert "x" not in names and "xd" in names
    m = maps[names.index("xd")]
    assert m["share"] > 0.9 and m["finding"].startswith("residual follows the ")


@pytest.mark.parametrize("kind", ["random", "sweep", "startup", "quake"])
def test_benchmark_motion_is_of_its_family(kind):
    """Each excitation family of the non-harmonic benchmark draws its own kind of program."""
    from chainid.gap.benchmark.nonharmonic import motion

    m = motion(kind, np.random.default_rng(3))
    assert m.kind == kind and m.t.size >= 2000 and np.all(np.diff(m.t) > 0)


def test_localise_names_a_residual_harmonic_above_twice_the_noise_floor():
    """Bin-mean noise floor σ/√n = 1/√10 = 0.316 N: a residual r = C·cos ψ of C = 3 N (above 2 × 0.316 N) is named
    as the fundamental in phase with ẋ with RMS over tests 3 N; C = 0.5 N (below) is not."""
    def found(C):
        return [f for f in localise_viscous_excess(C)[1] if f.get("kind") == "harmonic"]

    named = found(3.0)
    assert [f["component"] for f in named] == ["h1_xdot"] and named[0]["amplitude_N"] == pytest.approx(3.0)
    assert named[0]["finding"] == "residual fundamental in phase with ẋ (damping): RMS over tests 3 N"
    assert found(0.5) == []


def test_a_given_damping_law_needs_one_training_test_more_than_its_coefficients():
    """Eq. 21 has 5 coefficients: leave-one-out needs >= 6 training tests.  Seven tests, one held out: the given
    law is taken ("given"); two held out (5 training tests): refused, saying so."""
    from chainid.gap.harmonic.prepare import prepare_test
    from chainid.gap.harmonic.problem import Problem
    from chainid.model.base import ChainModel
    from chainid.records.simulate import TestSpec, simulate

    model = ChainModel()
    plan = [TestSpec(str(i), w, 2.0, a) for i, (w, a) in
            enumerate([(1.0, 0.1), (2.0, 0.2), (4.0, 0.3), (1.0, 0.3), (2.0, 0.1), (4.0, 0.2), (3.0, 0.15)], 1)]
    data = [prepare_test(r) for r in simulate(plan, model, 60.0, n_cycles=5, samples_per_cycle=64, noise_F=5.0,
                                              seed=1)]
    prob = Problem(data, model, ["7"], "polynomial")
    assert (prob.law, prob.law_reason) == ("polynomial", "given")
    with pytest.raises(ValueError, match="has 5 coefficients; with 5 training tests at most 4"):
        Problem(data, model, ["6", "7"], "polynomial")
