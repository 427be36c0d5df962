"""Plausibility warnings (chainid.records.plausible): sampling, aliasing and main frequency, unit slips against the
chain's breaking elongation and working load, one line per check (not one per test)."""
from __future__ import annotations

import numpy as np
import pytest

from chainid.chain.spec import default_chain
from chainid.records.plausible import grouped, plausibility_warnings
from chainid.records.record import Record


# ---------------------------------------------------------------- survivors of the seed-24 check (records)
def Record_(*a):  # noqa: N802
    from chainid.records.record import Record

    return Record(*a)


def test_a_force_under_a_ten_thousandth_of_the_working_load_is_named():
    """``chain_warnings``: a largest force under 1/10000 of the chain's working load (kN read as N) is named;
    at 1/20000 it warns, at 1/5000 not (the paper's chain; working load from its practice sheet).  Bug caught:
    ``wl * 1e-4`` → ``wl % 1e-4`` (the threshold ~0: never warned)."""
    from chainid.chain.spec import default_chain
    from chainid.model.practice import chain_practice
    from chainid.records.plausible import chain_warnings

    chain = default_chain()
    wl = chain_practice(chain)["working_load_N"]
    t = np.linspace(0.0, 10.0, 500)
    x = 2.2 + 0.25 * np.sin(2.0 * t)
    for frac, warns in ((1 / 20000, True), (1 / 5000, False)):
        F = wl * frac * (0.6 + 0.4 * np.sin(2.0 * t))
        out = [w for w in chain_warnings([Record_("a", t, x, F)], chain) if "working load" in w]
        assert bool(out) is warns, (frac, out)
        if warns:
            assert out[0].startswith(f"test 'a': the largest force {wl * frac:.3g} N is under 1/10000 of the "
                                     f"chain's working load ({wl:.4g} N)")


# --- seed 24 survivors -----------------------------------------------------------------------------------------
def test_a_motion_at_the_nyquist_frequency_is_named_at_half_the_sampling_rate():
    """x alternating every sample (x = 3 + cos(π n)) at 1 kHz is a 500 Hz motion, 2 samples per cycle: the
    aliasing warning names 500 Hz, exactly fs/2 (its spectrum's last bin).  Bug caught: the bin zeroed before
    the peak search moved from DC to the last one (``spec[0]`` → ``spec[-1]``: the peak becomes the bin next to
    Nyquist, 499 Hz)."""
    from chainid.records.plausible import sampling_warnings
    from chainid.records.record import Record

    n = 1000
    t = np.arange(n) / 1000.0
    x = 3.0 + np.cos(np.pi * np.arange(n))
    (w,) = sampling_warnings([Record("a", t, x, 1000.0 + 100.0 * x)])
    assert "1000 Hz sampling gives 2 samples per cycle of the main frequency 500 Hz " in w


def test_white_noise_has_no_main_frequency_and_draws_no_sampling_warning():
    """x white noise at 1 kHz (10 seeds, 2000 samples): no line holds half the power (the peak and its two
    neighbours each side hold about 5 of 1001 equal shares), so there is no main frequency and no sampling
    warning.  Bug caught (seed 25): the power test ``0.5 * power.sum()`` → ``0.5 ** power.sum()`` (≈ 0: the
    largest noise line becomes the main frequency, and 7 of these 10 seeds are called aliased, above fs/4)."""
    from chainid.records.plausible import sampling_warnings
    from chainid.records.record import Record

    t = np.arange(2000) / 1000.0
    for seed in range(10):
        x = 2.2 + 0.1 * np.random.default_rng(seed).standard_normal(t.size)
        assert sampling_warnings([Record("n", t, x, 1000.0 + 10.0 * x)]) == [], seed


def _rec(test: str, scale: float) -> Record:
    t = np.linspace(0.0, 10.0, 2001)
    x = scale * (2.0 + 0.5 * np.sin(2 * np.pi * t))
    return Record(test, t, x, 2.0e4 + 5.0e3 * np.sin(2 * np.pi * t))


def test_one_slip_in_every_test_is_one_line_naming_all_tests():
    recs = [_rec(f"t{i}", 1000.0) for i in range(5)]  # x in um read as mm
    msgs = [m for m in plausibility_warnings(recs, default_chain()) if "x spans" in m]
    assert len(msgs) == 1
    assert msgs[0].startswith("test 't0': x spans")
    assert "[the same check on 4 more test(s): 't1', 't2', 't3', 't4']" in msgs[0]


def test_different_checks_and_unslipped_tests_stay_apart():
    msgs = grouped(["test 'a': x spans 1.2e+03 mm, 3x", "test 'b': F reaches 9e+09 N", "test 'c': x spans 17 mm, 4.1x",
                    "no tag 1", "no tag 2"])
    assert msgs == ["test 'a': x spans 1.2e+03 mm, 3x [the same check on 1 more test(s): 'c']",
                    "test 'b': F reaches 9e+09 N", "no tag 1", "no tag 2"]  # untagged: never merged


def test_x_in_micrometres_is_flagged_against_the_breaking_elongation():
    """x spanning 500 mm on a 14x50 chain: the warning gives the span over the elongation at the breaking load,
    x_bl = x(F_bl) of Eq. 15 (typed in paper_forms), and suggests µm."""
    import paper_forms

    from chainid.chain.spec import default_chain
    from chainid.model.practice import chain_practice
    from chainid.records.plausible import plausibility_warnings

    x_bl = paper_forms.x_of_F(chain_practice(default_chain())["breaking_load_N"])
    t = np.linspace(0, 10, 1000)
    rec = Record("u", t, 2200 + 250 * np.sin(t), 11000 + 1000 * np.sin(t))
    w = [s for s in plausibility_warnings([rec], default_chain()) if "x spans" in s]
    assert w == [f"test 'u': x spans 500 mm, {500 / x_bl:.3g}x the chain's elongation at the breaking load "
                 f"({x_bl:.3g} mm): is x in um read as mm (--units x=um)?"]


# --- own-seed (702) mutation survivors -------------------------------------------------------------------------
def test_aliasing_warning_states_samples_per_cycle():
    """A 10 Hz sine sampled at 30 Hz (12 s): 3 samples per cycle, under the 4 that the check asks; the warning
    names 30 Hz, 3 samples per cycle and the 10 Hz main frequency.  Bug caught: ``fs / f`` → ``fs | f``."""
    from chainid.records.plausible import sampling_warnings
    from chainid.records.record import Record

    t = np.arange(360) / 30.0
    x = 2.0 + np.sin(2 * np.pi * 10.0 * t + 0.3)
    w = sampling_warnings([Record("a", t, x, 100.0 * x)])
    assert len(w) == 1
    assert w[0].startswith("test 'a': 30 Hz sampling gives 3 samples per cycle of the main frequency 10 Hz")


# --- plausibility of the sampling, and the table's row messages (contracts no test stated) ----------------------
def _sine_record(test, f, fs, cycles):
    from chainid.records.record import Record

    t = np.arange(int(round(cycles * fs / f))) / fs
    x = 2.0 + 0.5 * np.sin(2 * np.pi * f * t)
    return Record(test, t, x, 1000.0 * x)


@pytest.mark.parametrize("f,fs,words", [
    (0.005, 1.0, "the main frequency 0.005 Hz (a cycle of 200 s) is implausibly slow"),
    (2000.0, 20000.0, "the main frequency 2000 Hz is implausibly fast for a chain test"),
    (0.02, 1.0, None), (500.0, 20000.0, None), (1.0, 4.0, None),  # inside 0.01–1000 Hz; 4 samples a cycle is enough
])
def test_sampling_warnings_for_implausible_main_frequencies(f, fs, words):
    """The main frequency of a record (a sine on an FFT bin, 10 cycles) is plausible in 0.01–1000 Hz; outside,
    one warning names the test, the frequency (and for a slow one its cycle, 1/f) and the likely unit slip."""
    from chainid.records.plausible import sampling_warnings

    w = sampling_warnings([_sine_record("s", f, fs, 10)])
    if words is None:
        assert w == []
    else:
        assert len(w) == 1 and w[0].startswith(f"test 's': {words}"), w


def test_sampling_above_a_megahertz_is_a_unit_slip():
    """A time step of 1e-7 s (10 MHz, over the 1 MHz limit): one warning naming the step and the rate; a step of
    2 µs (500 kHz) is not warned about."""
    from chainid.records.plausible import sampling_warnings
    from chainid.records.record import Record

    t = np.arange(400) * 1e-7
    x = 2.0 + np.sin(2 * np.pi * 250_000.0 * t)
    w = sampling_warnings([Record("u", t, x, x)])
    assert w == ["test 'u': time step 1e-07 s implies sampling at 1e+07 Hz, above 1e+06 Hz: is t in s while "
                 "declared ms or us (--units t=...)?"]
    t = np.arange(400) * 2e-6
    assert not any("above 1e+06 Hz" in m for m in sampling_warnings([Record("v", t, x, x)]))


@pytest.mark.parametrize("ratio,text", [
    (1000.0, "x in m read as mm"), (1e-3, "F in kN read as N"), (25.4, "x in inches declared mm?"),
    (1 / 25.4, "x declared inches while in mm"), (1 / 4448.2, "F in kip read as N"),
    (1 / 4.448, "F in lbf read as N (--units F=lbf)"), (1 / 4.448 * 2.9, "F in lbf read as N"),
    (0.75, "a unit slip of x or F?"),  # 3.34 x the lbf ratio 0.2248: outside every slip's factor-3 window
    (8.0, "a unit slip of x or F?"),  # 25.4 / 8 = 3.2: outside the inches window too
])
def test_stiffness_ratio_names_the_slip_within_a_factor_three(ratio, text):
    """The stiffness-ratio check names the known slip nearest (in log) to the record's k over the chain's, when
    it is within a factor 3: m/mm or kN/N (1000), inches (25.4), kip (4448.2 N) and lbf (4.448 N) per unit; else
    the generic question.  Bug caught: the lbf factor 4.448 garbled (3.448: 0.75 would be named lbf)."""
    from chainid.records.plausible import _slip

    assert text in _slip(ratio)


def test_the_main_frequency_rule_does_not_depend_on_the_unit_of_x():
    """The rule "the peak and its two neighbours each side hold half the power" is a ratio, so it gives the same
    answer in any unit of x: white noise of 1 µm (x a dead channel's noise, 10 seeds at 1 kHz) has no main
    frequency and draws no sampling warning, like the same noise of 1 mm; a 300 Hz sine of 1 µm at 1 kHz (3.3
    samples per cycle) is named aliased, at 300 Hz, like the same sine of 1 mm.  Bug caught (seed 27): the power
    ``spec ** 2`` → ``spec - 2`` (a unit-dependent rule: every line of a small-valued x below 2 counts as negative
    power, so the largest noise line becomes a main frequency: seed 0 is called aliased at 334 Hz)."""
    from chainid.records.plausible import sampling_warnings
    from chainid.records.record import Record

    t = np.arange(2000) / 1000.0
    for scale in (1e-3, 1.0):
        for seed in range(10):
            x = 2.2 + scale * np.random.default_rng(seed).standard_normal(t.size)
            assert sampling_warnings([Record("n", t, x, 1000.0 + 10.0 * x)]) == [], (scale, seed)
        x = 2.2 + scale * np.sin(2 * np.pi * 300.0 * t)
        (w,) = sampling_warnings([Record("s", t, x, 1000.0 + 10.0 * x)])
        assert "1000 Hz sampling gives 3.3 samples per cycle of the main frequency 300 Hz " in w, scale


# ---------------------------------------------------------------- the chain's inertia at the declared frequency
def _quasi_static_chain_record(f_hz: float) -> Record:
    """A paper-chain harmonic test at *f_hz*: x = 2.2 + 0.25·sin(2πft) mm, F = F_k(x) of Eq. 15 (typed in
    paper_forms) with no inertia in it, 40 samples per cycle over 5 cycles."""
    import paper_forms

    t = np.arange(200) / (40.0 * f_hz)
    x = 2.2 + 0.25 * np.sin(2 * np.pi * f_hz * t)
    return Record("q", t, x, np.array([paper_forms.F_of_x(float(v)) for v in x]))


@pytest.mark.parametrize("f_hz", [0.3, 3.0])
def test_a_quasi_static_chain_test_draws_no_inertia_warning(f_hz):
    """At 0.3 and 3 Hz the paper chain's inertia (3.2 kg) is far under a quarter of the force swing."""
    w = [s for s in plausibility_warnings([_quasi_static_chain_record(f_hz)], default_chain()) if "inertia" in s]
    assert w == []


def test_a_test_in_seconds_declared_ms_is_named_by_the_chain_inertia_it_would_need():
    """The same 0.3 Hz record with t read as ms (300 Hz, 0.47 m/s, 90 g: inside every sampling bound) puts the
    paper chain's inertia m·(2πf)²·A, computed here by hand from m = 3.2 kg (16 links x 50 mm x 4 kg/m), over
    the measured force swing: the warning names the share and suggests --units t=ms."""
    import paper_forms

    rec = _quasi_static_chain_record(300.0)
    assert plausibility_warnings([rec]) == []  # the sampling checks alone pass it
    w = [s for s in plausibility_warnings([rec], default_chain()) if "inertia" in s]
    f_in = 3.2e-3 * (2 * np.pi * 300.0) ** 2 * 0.25
    half_F = 0.5 * (paper_forms.F_of_x(2.45) - paper_forms.F_of_x(1.95))
    assert len(w) == 1 and "--units t=ms" in w[0], w
    share = float(w[0].split(" is ")[1].split("x the measured")[0])
    assert share == pytest.approx(f_in / half_F, rel=0.03)


@pytest.mark.parametrize("share, warns", [(0.2, False), (0.3, True)])
def test_the_inertia_warning_starts_at_a_quarter_of_the_force_swing(share, warns):
    """The frequency at which m·ω²·A is *share* of the half-span of F (both by hand): 0.2 is quiet, 0.3 warns."""
    import paper_forms

    half_F = 0.5 * (paper_forms.F_of_x(2.45) - paper_forms.F_of_x(1.95))
    f_hz = np.sqrt(share * half_F / (3.2e-3 * 0.25)) / (2 * np.pi)
    w = [s for s in plausibility_warnings([_quasi_static_chain_record(f_hz)], default_chain()) if "inertia" in s]
    assert bool(w) is warns, (f_hz, w)


# --- seed 29 survivors -----------------------------------------------------------------------------------------
@pytest.mark.parametrize("flat", ["x", "F"])
def test_a_flat_channel_gets_no_stiffness_span_warning(flat):
    """The record's stiffness span(F)/span(x) is judged only when both channels move: a constant x (a load cell
    beside a locked actuator) or a constant F (a dead load cell) would give span(F)/span(x) = inf or 0, "∞× the
    chain's k_e", a number that says nothing.  Bug caught: ``span_x > 0 and span_F > 0`` → ``or``."""
    from chainid.records.plausible import chain_warnings

    chain = default_chain()
    t = np.linspace(0.0, 10.0, 500)
    x = np.full(t.size, 2.2) if flat == "x" else 2.2 + 0.25 * np.sin(2.0 * t)
    F = np.full(t.size, 11000.0) if flat == "F" else 11000.0 + 1000.0 * np.sin(2.0 * t)
    out = chain_warnings([Record_("a", t, x, F)], chain)
    assert not any("span(F)/span(x)" in w for w in out), out
