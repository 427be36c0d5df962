"""Issue 20 §5, gap package: behaviours the own-seed mutation runs (mutG, seeds 620–659) found unpinned.

Each test checks a documented behaviour (docstring, README, error text) against a hand computation, a closed form
or the documented contract, never against today's output.  Fast: no diagnosis runs here.
Units: mm, N, s.
"""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from chainid.gap.harmonic.problem import Candidate


# ---------------------------------------------------------------- prepare: the time origin

def test_prepared_time_is_from_the_records_first_sample():
    """``TestData.t`` is the time from the record's first sample and ``t + t_origin`` the record's own time
    (the docstring): a sine stamped from t = 1000 s gives t_origin = 1000 s, t inside [0, T], and
    x = x0 + A sin(ω t + θ) on the relative time."""
    from chainid.gap.harmonic.prepare import prepare_test
    from chainid.records.record import Record

    fs, f, n = 200.0, 2.0, 1600  # 8 s, 16 cycles
    tr = np.arange(n) / fs
    rng = np.random.default_rng(0)
    x = 2.0 + 0.3 * np.sin(2 * np.pi * f * tr + 0.4)
    F = 500.0 * x + 3.0 * 0.3 * 2 * np.pi * f * np.cos(2 * np.pi * f * tr + 0.4) + rng.normal(0, 0.5, n)
    rec = Record("T", tr + 1000.0, x, F)
    d = prepare_test(rec)
    assert d.t_origin == 1000.0
    assert 0.0 <= d.t[0] and d.t[-1] <= tr[-1] + 1e-9
    # every prepared sample is a record sample at its own time
    i = np.searchsorted(rec.t, d.t + d.t_origin)
    np.testing.assert_allclose(rec.t[i], d.t + d.t_origin, atol=1e-9)
    np.testing.assert_array_equal(rec.x[i], d.x_meas)
    np.testing.assert_allclose(d.x_meas, d.x0 + d.A * np.sin(d.omega * d.t + d.theta), atol=1e-3)
    assert d.omega == pytest.approx(2 * np.pi * f, rel=1e-4)


# ---------------------------------------------------------------- noise: the smallest record

def test_force_noise_takes_five_samples_and_refuses_four():
    """``force_noise`` needs >= 5 samples (docstring).  F = (0, 1, 3, 2, 7) N: Δ²F = (1, −3, 6), median 1,
    |Δ²F − 1| = (0, 4, 5), MAD 4, σ = 1.4826·4/√6 (5 distinct values: no quantum)."""
    from chainid.gap.core.noise import force_noise

    assert force_noise(np.array([0.0, 1.0, 3.0, 2.0, 7.0])) == pytest.approx(1.4826 * 4 / math.sqrt(6), rel=1e-12)
    with pytest.raises(ValueError, match=r"force_noise needs >= 5 samples; got 4"):
        force_noise(np.array([0.0, 1.0, 3.0, 2.0]))


# ---------------------------------------------------------------- benchmark_time: the chatter hook

@pytest.mark.parametrize("fs, f_ch", [(100.0, 12.0), (1000.0, 50.0), (40.0, 8.0)])
def test_chatter_hook_is_friction_plus_an_oscillation_while_sliding(fs, f_ch):
    """The out-of-library chatter (``_outside``'s docstring): Coulomb friction F_c·sgn(ẋ) plus an oscillation of
    amplitude 0.3–0.8 F_c at max(12 Hz, fs/20), at most fs/5, only while the contact slides faster than a fraction
    0.1–0.25 of the peak speed.  The oscillation's amplitude is fitted by least squares at the known frequency on
    the samples surely sliding (speed above 0.25 of the peak); it is exactly 0 below 0.1 of the peak."""
    from chainid.gap.benchmark.nonharmonic import _outside
    from chainid.model.effects import stick_slip

    t = np.arange(int(4 * fs)) / fs
    x = 2.0 + 0.5 * np.sin(2 * np.pi * 0.5 * t)
    xd = 0.5 * np.pi * np.cos(2 * np.pi * 0.5 * t)
    z = np.zeros_like(t)
    F_c = 40.0
    amps = []
    for seed in range(25):
        hook = _outside("chatter", 1.0, 1000.0, F_c, np.random.default_rng(seed))
        r = hook(t, x, xd, z, z) - F_c * stick_slip(x, xd, 0.0, periodic=False)
        np.testing.assert_allclose(hook(t, x, xd, z, 7.0 + z) - 7.0, r + F_c * stick_slip(x, xd, 0.0, periodic=False),
                                   atol=1e-12 * F_c)  # added to the force it is given
        slow = np.abs(xd) < 0.1 * np.abs(xd).max()
        assert np.all(r[slow] == 0.0)
        fast = np.abs(xd) > 0.25 * np.abs(xd).max()
        M = np.column_stack([np.sin(2 * np.pi * f_ch * t[fast]), np.cos(2 * np.pi * f_ch * t[fast])])
        coef, *_ = np.linalg.lstsq(M, r[fast], rcond=None)
        np.testing.assert_allclose(M @ coef, r[fast], atol=1e-9 * F_c)  # a pure tone at f_ch
        amps.append(math.hypot(*coef))
    assert 0.3 * F_c <= min(amps) and max(amps) <= 0.8 * F_c
    assert max(amps) - min(amps) > 0.2 * F_c  # drawn, not fixed


# ---------------------------------------------------------------- selection: two-for-one alternatives

def test_two_for_one_reports_identified_pairs_within_the_tie(monkeypatch):
    """``_two_for_one``: a stiffness-side effect of the final chain (contact_law) against every pair of the other
    members of its family that are allowed and not in the chain; a pair is reported when its LOTO NRMSE is within
    ``TIE`` (5 %) of the chain's and none of its parameters is at a bound (rule 4).  The pair is fitted with the
    chain's other effects, warm-started from their parameters (the replaced effect's dropped)."""
    from chainid.gap.core import selection as fw

    full = Candidate("friction+contact_law", {"friction.F_c": 3.0, "contact_law.scale": 1.2,
                                              "contact_law.exponent": 1.4}, 3)
    full.nrmse_loto = 1.0
    # (LOTO, at_bound) per pair: within the tie and free | within but pinned | free but 20 % worse
    table = {("stiffness_level", "slack"): (1.04, []), ("stiffness_level", "machine_compliance"):
             (1.04, ["machine_compliance.c"]), ("slack", "machine_compliance"): (1.2, [])}
    seen = []

    def fake(prob, names, start, base_hold):  # noqa: ANN001
        seen.append((list(names), dict(start)))
        loto, ab = table[tuple(names[1:])]
        c = Candidate("+".join(names), {}, 2)
        c.nrmse_loto, c.at_bound = loto, list(ab)
        return c

    monkeypatch.setattr(fw, "_fit_score", fake)
    allowed = ["friction", "contact_law", "stiffness_level", "slack", "machine_compliance"]
    out = fw._two_for_one(None, full, allowed, 1.0)
    assert [o["report"] for o in out] == [{"step": 2, "pair": ["contact_law", "stiffness_level+slack"],
                                           "loto": [1.0, 1.04]}]
    assert out[0]["cand"].name == "friction+stiffness_level+slack"
    assert [s[0] for s in seen] == [["friction", "stiffness_level", "slack"],
                                    ["friction", "stiffness_level", "machine_compliance"],
                                    ["friction", "slack", "machine_compliance"]]
    assert all(s[1] == {"friction.F_c": 3.0} for s in seen)
    # a member not allowed is not tried; an effect outside the family (friction) has no alternatives
    seen.clear()
    assert fw._two_for_one(None, full, ["friction", "contact_law", "stiffness_level", "slack"], 1.0)[0]["report"][
        "pair"] == ["contact_law", "stiffness_level+slack"]
    assert [s[0] for s in seen] == [["friction", "stiffness_level", "slack"]]
    seen.clear()
    only_friction = Candidate("friction", {"friction.F_c": 3.0}, 1)
    assert fw._two_for_one(None, only_friction, allowed, 1.0) == [] and seen == []


# ---------------------------------------------------------------- fitgrid: the documented start set

def _set(out, cols=slice(None)):
    return sorted(tuple(np.round(np.asarray(u, float)[cols], 12)) for u in out)


def test_start_set_of_one_free_parameter_is_the_documented_one():
    """``starts`` with one free parameter (its docstring): the default first, then GRID1, 0.5 − (0.01, 0.05, 0.2),
    around 0 when the range straddles it, the 40 delay midpoints, and ug × (0.5 … 3) for a scale or delay."""
    from chainid.gap.core.fitgrid import starts

    grid1 = [0.0, 0.003, 0.01, 0.03, 0.1, 0.3, 0.6]
    mid = [0.49, 0.45, 0.3]
    one = lambda key, ug, lo, hi: starts([key], [key.split(".")[0]], np.array([ug]), np.zeros(1, bool),  # noqa: E731
                                         np.array([lo]), np.array([hi]))
    out = one("friction.F_c", 0.02, 0.0, 50.0)  # a range from 0: no start around 0, no scale starts
    assert float(out[0][0]) == 0.02
    assert _set(out) == _set([[v] for v in [0.02] + grid1 + mid])
    z = 0.25  # range (−1, 3): 0 at u = 0.25
    out = one("backlash.b", 0.6, -1.0, 3.0)
    around = [z + s * g for g in (0.002, 0.01, 0.05, 0.15) for s in (-1, 1)]
    assert _set(out) == _set([[v] for v in [0.6] + grid1 + mid + around])
    out = one("stiffness_level.scale", 0.3, 0.5, 1.75)
    scale = [0.3 * f for f in (0.5, 0.7, 0.85, 1.2, 1.5, 2.0, 3.0)]
    assert _set(out) == _set([[v] for v in [0.3] + grid1 + mid + scale])
    out = one("sensor_delay.tau", 0.5, -0.2, 0.2)
    delay = [(i + 0.5) / 40 for i in range(40)]
    around = [0.5 + s * g for g in (0.002, 0.01, 0.05, 0.15) for s in (-1, 1)]
    scale = [min(0.5 * f, 1.0) for f in (0.5, 0.7, 0.85, 1.2, 1.5, 2.0, 3.0)]
    assert _set(out) == _set([[v] for v in [0.5] + grid1 + mid + around + delay + scale])


@pytest.mark.parametrize("effect, params, extra", [
    ("friction", ("F_c", "mu", "x_s"), [(a, 0.0, c) for a in (0.03, 0.2) for c in (0.02, 0.1, 0.4)]),
    ("contact_law", ("scale", "exponent"), [(a, b) for a in (0.05, 0.18, 0.4) for b in (0.2, 0.39, 0.6)]),
    ("hysteresis", ("F_h", "x_h"), [(a, b) for a in (0.01, 0.05, 0.2) for b in (0.005, 0.01, 0.02)]),
    ("backlash", ("b", "k2"), []),
])
def test_start_set_of_a_new_effect_with_several_parameters_is_the_documented_one(effect, params, extra):
    """Two or more free parameters: GRID2 × GRID2 (0, 0.003, 0.03, 0.2) over the first two (the others at the
    default), plus the effect's own documented starts (friction, contact law, hysteresis); the default first."""
    from chainid.gap.core.fitgrid import starts

    k = len(params)
    ug = np.full(k, 0.77)
    out = starts([f"{effect}.{p}" for p in params], [effect], ug, np.zeros(k, bool), np.zeros(k), np.ones(k))
    g2 = (0.0, 0.003, 0.03, 0.2)
    want = [tuple(ug)] + [(a, b) + (0.77,) * (k - 2) for a in g2 for b in g2]
    want += [tuple(e) + (0.77,) * (k - len(e)) for e in extra]
    assert np.array_equal(out[0], ug)
    assert _set(out) == _set(want)


# ---------------------------------------------------------------- benchmark_time: the drawn motion programs

def _draws(kind, n_draws, monkeypatch):
    """Every argument ``motion`` hands the excitation constructors, over ``n_draws`` records (recorders: no
    signal is built)."""
    import inspect

    from chainid.gap.benchmark import nonharmonic as bt
    from chainid.records import excitation as ex

    calls = []
    sigs = getattr(_draws, "sigs", None) or {n: inspect.signature(getattr(ex, n)) for n in
                                              ("band_random", "sweep", "startup_steps", "earthquake", "with_envelope")}
    _draws.sigs = sigs  # the constructors' own signatures (before any recorder is in place)

    def recorder(name):
        sig = sigs[name]

        def rec(*a, **kw):  # noqa: ANN001
            b = sig.bind(*a, **kw)
            b.apply_defaults()
            if name == "with_envelope":
                env = calls[-1].setdefault("taper", []), calls[-1].setdefault("lead", [])
                for lst, key in zip(env, ("taper", "lead")):
                    if b.arguments[key] > 0:
                        lst.append(b.arguments[key])
                return b.arguments["m"]
            calls[-1][name] = dict(b.arguments)
            n, fs = b.arguments["n"], b.arguments["fs"]
            t = np.arange(n) / fs
            return ex.Motion(t, t, t, t, 1.0, 1.0, kind)
        return rec

    for name in ("band_random", "sweep", "startup_steps", "earthquake", "with_envelope"):
        monkeypatch.setattr(ex, name, recorder(name))
    rng = np.random.default_rng(5)
    for _ in range(n_draws):
        calls.append({})
        bt.motion(kind, rng)
    return calls


def _spans(vals, lo, hi, frac=0.1):
    """Inside [lo, hi] and reaching both ends (within ``frac`` of the width): the documented range, not a part."""
    v = np.asarray(vals, float)
    w = hi - lo
    return bool(v.min() >= lo - 1e-12 and v.max() <= hi + 1e-12 and v.min() < lo + frac * w and v.max() > hi - frac * w)


def _share(flags, p, n):
    return abs(np.mean(flags) - p) < 4.5 * math.sqrt(p * (1 - p) / n)  # 4.5 binomial SE


def _rate_ok(fs, f_edge, per):
    ok = [f for f in (100.0, 200.0, 250.0, 500.0, 1000.0, 2000.0) if f >= per * f_edge]
    return fs in ok[:3]


N_DRAWS = 400


def test_random_records_are_drawn_from_the_documented_ranges(monkeypatch):
    """``motion("random")``: the ranges of its docstring (README: band edge 1–4 Hz, some with a wandering mean)."""
    calls = _draws("random", N_DRAWS, monkeypatch)
    a = [c["band_random"] for c in calls]
    assert _spans([x["n"] for x in a], 2000, 4500, 0.02)
    assert _spans([x["f_hi"] for x in a], 1.0, 4.0)
    assert all(_rate_ok(x["fs"], x["f_hi"], 25.0) for x in a)
    lo_rel = [x["f_lo"] / x["f_hi"] for x in a if x["f_lo"] > 2.5 * x["fs"] / x["n"] + 1e-12]
    assert _spans(lo_rel, 0.02, 0.1) and all(x["f_lo"] >= 2.5 * x["fs"] / x["n"] - 1e-12 for x in a)
    assert _spans([x["rms"] for x in a], 0.04, 0.11) and _spans([x["x0"] for x in a], 1.7, 2.3)
    wander = [x["wander"] for x in a]
    assert _share([w > 0 for w in wander], 0.3, N_DRAWS) and _spans([w for w in wander if w > 0], 0.02, 0.08, 0.2)
    Te = np.array([(x["n"] - 1) / x["fs"] for x in a])  # the envelope's T: the last sample's time
    taper = [v / t for c, t in zip(calls, Te) for v in c.get("taper", [])]
    lead = [v / t for c, t in zip(calls, Te) for v in c.get("lead", [])]
    assert _share([bool(c.get("taper")) for c in calls], 0.3, N_DRAWS) and _spans(taper, 0.05, 0.1, 0.2)
    assert _share([bool(c.get("lead")) for c in calls], 0.25, N_DRAWS) and _spans(lead, 0.03, 0.1, 0.2)
    assert max(len(c.get("taper", [])) + len(c.get("lead", [])) for c in calls) == 2  # both on some records


def test_sweep_and_startup_records_are_drawn_from_the_documented_ranges(monkeypatch):
    """``motion("sweep")`` (README: up or down, 0.2–0.5 ↔ 2–4 Hz) and ``motion("startup")`` (docstring ranges)."""
    calls = _draws("sweep", N_DRAWS, monkeypatch)
    a = [c["sweep"] for c in calls]
    lo, hi = [min(x["f0"], x["f1"]) for x in a], [max(x["f0"], x["f1"]) for x in a]
    assert _spans(lo, 0.2, 0.5) and _spans(hi, 2.0, 4.0)
    assert _share([x["f0"] > x["f1"] for x in a], 0.3, N_DRAWS) and _share([x["log"] for x in a], 0.5, N_DRAWS)
    assert all(_rate_ok(x["fs"], h, 25.0) for x, h in zip(a, hi))
    assert all(x["n"] >= max(2000, int(3 * x["fs"] / l)) for x, l in zip(a, lo)) and max(x["n"] for x in a) > 4400
    assert _spans([x["A"] for x in a], 0.06, 0.3) and _spans([x["x0"] for x in a], 1.8, 2.3)
    assert _share([bool(c.get("taper")) for c in calls], 0.3, N_DRAWS)
    assert _share([bool(c.get("lead")) for c in calls], 0.25, N_DRAWS)

    calls = _draws("startup", N_DRAWS, monkeypatch)
    a = [c["startup_steps"] for c in calls]
    T = np.array([x["n"] / x["fs"] for x in a])
    assert _spans([x["f_run"] for x in a], 1.0, 4.0) and all(_rate_ok(x["fs"], x["f_run"], 25.0) for x in a)
    assert _spans([x["n"] for x in a], 2000, 4500, 0.02)
    assert sorted({len(x["levels"]) for x in a}) == [2, 3, 4]
    assert _spans([v for x in a for v in x["levels"]], 1.6, 2.5)
    assert _spans([x["t_ramp"] / t for x, t in zip(a, T)], 0.15, 0.3) and _spans([x["t_step"] for x in a], 0.3, 1.5)
    assert _spans([x["A"] for x in a], 0.04, 0.2) and _spans([x["x_start"] for x in a], 0.6, 1.2)
    # no taper on a start-up record; a lead-in on a quarter
    assert not any(c.get("taper") for c in calls)
    assert _share([bool(c.get("lead")) for c in calls], 0.25, N_DRAWS)


def test_quake_records_are_drawn_from_the_documented_ranges(monkeypatch):
    """``motion("quake")``: the docstring's ranges (README: a near-fault pulse on half, an offset on some)."""
    calls = _draws("quake", N_DRAWS, monkeypatch)
    a = [c["earthquake"] for c in calls]
    T = np.array([x["n"] / x["fs"] for x in a])
    fg = np.array([x["f_g"] for x in a])
    assert _spans(fg, 1.0, 3.0) and _spans([x["n"] for x in a], 3000, 6000, 0.02)
    assert all(_rate_ok(x["fs"], 4 * x["f_g"], 20.0) for x in a)
    assert {x["fs"] for x in a} == {100.0, 200.0, 250.0, 500.0, 1000.0}
    assert _spans([x["peak"] for x in a], 0.15, 0.45) and _spans([x["x0"] for x in a], 1.9, 2.4)
    assert _spans([x["zeta_g"] for x in a], 0.3, 0.7) and _spans([x["f_c"] / x["f_g"] for x in a], 0.05, 0.15)
    np.testing.assert_allclose([x["f_hi"] for x in a], 4 * fg, rtol=1e-12)
    assert _spans([x["t_rise"] / t for x, t in zip(a, T)], 0.08, 0.25)
    assert _spans([x["decay"] * t for x, t in zip(a, T)], 3.0, 8.0)
    pulse = [x["pulse"] for x in a]
    assert _share([p > 0 for p in pulse], 0.5, N_DRAWS) and _spans([p for p in pulse if p > 0], 0.5, 1.5)
    off = [x["offset"] for x in a]
    assert _share([o != 0 for o in off], 0.3, N_DRAWS) and _spans([o for o in off if o != 0], -0.3, 0.3)
    assert not any(c.get("taper") for c in calls)
    assert _share([bool(c.get("lead")) for c in calls], 0.25, N_DRAWS)
    with pytest.raises(ValueError, match=r"excitation = 'harmonic' is unknown; valid: random, sweep, startup, quake"):
        _draws("harmonic", 1, monkeypatch)


# ---------------------------------------------------------------- where_time.ringing: thresholds, choice and texts

def _ring(name, s2, amp=5.0, n=8000, fs=1000.0):
    t = np.arange(n) / fs
    xd = 2 * math.pi * np.cos(2 * math.pi * t)  # x = sin(2π t)
    sliding = np.abs(xd) >= 0.2 * np.quantile(np.abs(xd), 0.99)
    res = amp * np.sin(2 * math.pi * 60.0 * t) * np.where(sliding, 1.0, math.sqrt(s2))
    return SimpleNamespace(test=name, f_band=2.0, fs=fs, xd=xd), res


def test_ringing_ratio_threshold_choice_and_texts():
    """``ringing``: the same 60 Hz tone while sliding and, scaled by √s², elsewhere has a mean-square ratio 1/s² (within
    5 %: the tone's mean square over each set of samples and the high-pass's ends);
    chatter needs >= RING_RATIO = 2 (s² = 1/2.2: chatter; 1/1.8: ringing, reported with score 0).  Over records
    a chatter row beats a louder non-chatter one; a record that never rests (or never slides) is skipped."""
    from chainid.gap.timedomain.where import ringing

    d1, r1 = _ring("A", 1 / 2.2)
    got = ringing([d1], {"A": r1})
    assert got["chatter"] is True and got["ratio"] == pytest.approx(2.2, rel=0.05)
    assert got["finding"] == (f"ringing while sliding after reversals at {got['frequency_Hz']:.3g} Hz in test A (RMS "
                              f"{got['rms_N']:.3g} N, {got['ratio']:.1f}× the mean square elsewhere, narrow spectral "
                              f"peak {got['peak_ratio']:.0f}× its neighbourhood): stick-slip chatter — no library effect "
                              "covers it, so it is reported, not named")
    d2, r2 = _ring("B", 1 / 1.8, amp=20.0)
    got = ringing([d2], {"B": r2})
    assert got["chatter"] is False and got["ratio"] == pytest.approx(1.8, rel=0.05) and got["score"] == 0.0
    assert got["finding"] == (f"no ringing after reversals (sliding high-frequency residual {got['ratio']:.2f}× "
                              f"elsewhere, largest narrow peak {got['peak_ratio']:.1f}× its neighbourhood)")
    both = ringing([d2, d1], {"A": r1, "B": r2})
    assert both["test"] == "A" and both["kind"] == "chatter" and both["score"] == both["rms_N"]
    assert ringing([d2, _ring("C", 1 / 1.9, amp=30.0)[0]], {"B": r2, "C": _ring("C", 1 / 1.9, amp=30.0)[1]})[
        "test"] == "C"  # no chatter anywhere: the loudest record
    still = SimpleNamespace(test="S", f_band=2.0, fs=1000.0, xd=np.full(8000, 3.0))
    assert ringing([still], {"S": r1}) == {}


# ---------------------------------------------------------------- stationarity.trend: the scatter's standard error

def test_trend_standard_error_from_the_scatter_by_textbook_formulas():
    """``trend`` without a covariate is the straight-line fit: slope b = Sxy/Sxx, s² = RSS/(n − 2), SE = √(s²/Sxx)
    (textbook OLS); the floor only counts when larger than the scatter (floor 0.01 here: it does not)."""
    from chainid.gap.core.stationarity import trend

    t = np.arange(10, dtype=float)
    y = 3.0 + 0.1 * t + 2.0 * (-1.0) ** np.arange(10)
    sxx = float(np.sum((t - t.mean()) ** 2))
    b = float(np.sum((t - t.mean()) * (y - y.mean()))) / sxx
    rss = float(np.sum((y - y.mean() - b * (t - t.mean())) ** 2))
    sl, se, chg = trend(t, y, sd_floor=0.01)
    assert sl == pytest.approx(b, rel=1e-12) and se == pytest.approx(math.sqrt(rss / 8 / sxx), rel=1e-12)
    assert chg == pytest.approx(abs(b) * 9, rel=1e-12)
    assert trend(t, y, sd_floor=10.0)[1] == pytest.approx(10.0 / math.sqrt(sxx), rel=1e-12)  # the floor wins


def test_train_floor_is_five_chi2_standard_deviations_by_hand():
    """``train_floor``: at the noise floor when r²/f² < 1 + 5·sqrt(2/n) (the χ² mean 1 with standard deviation
    sqrt(2/n) over n noise cells).  n = 200 cells (the problem's n_cells):
    threshold 1 + 5·0.1 = 1.5 by hand; 1.45 is at the floor, 1.55 not, f² = 0 never.  Bug caught:
    ``5 * sqrt`` → ``5 % sqrt`` (threshold 1.0: nothing above the noise itself counts)."""
    from chainid.gap.core.selection import train_floor

    def prob(r2, f2):
        return SimpleNamespace(noise_db=lambda ev, which: (r2, f2, None), n_cells=lambda which: 200)

    cand = SimpleNamespace(_ev={})
    assert train_floor(prob(1.45, 1.0), cand) is True
    assert train_floor(prob(1.55, 1.0), cand) is False
    assert train_floor(prob(2.9, 2.0), cand) is True  # 1.45
    assert not train_floor(prob(0.0, 0.0), cand)
