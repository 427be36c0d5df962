"""The benchmark's non-harmonic and transfer cases (chainid.gap.benchmark.nonharmonic): records drawn from the
documented ranges, effect levels and texts, out-of-library hooks, noise and quantisation, the rows by hand."""
from __future__ import annotations

import math
import sys
import time
from types import SimpleNamespace

import numpy as np
import pytest

from chainid.gap.benchmark.nonharmonic import effect_spec
from chainid.model.base import LinearModel


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


def _result(steps=("baseline", "friction", "friction+slack"), **kw):
    return {"verdict": "friction+slack", "baseline": {"excess_rms_N": 30.0, "noise_sigma_N": 4.0},
            "steps": [{"effect": e, "shrinkage": 0.1 * i, "params": {"p": i}} for i, e in enumerate(steps)],
            "best": {"shrinkage": 0.77}, "confounded": [{"pair": ("slack", "contact_law"), "step": 2}],
            "residual": {"stationary": False}} | kw


def test_time_rows_time_the_case(monkeypatch):
    """``run_case_time``: the row's seconds are the case's own duration (simulation and diagnosis), for a
    diagnosed case and for one whose diagnosis raises (the error row: verdict, snr ∞, no transfer numbers); a
    diagnosed case's effect SNRs are computed with the records' own viscous c (``c_records``)."""
    import chainid.gap.diagnose  # noqa: F401
    from chainid.gap.benchmark import nonharmonic as bt

    monkeypatch.setattr(bt, "records", lambda case: (time.sleep(0.05), ([], {"nominal": None, "motions": [], "true": None, "hooks": [], "c": 0.0,
                                                        "c_records": [3.0, 4.0], "sigmas": [],
                                                        "true_params": {}}))[1])

    def boom(*a, **k):  # noqa: ANN001
        raise RuntimeError("bad")

    monkeypatch.setattr(sys.modules["chainid.gap.diagnose"], "diagnose", boom)
    case = {"excitation": "random", "hold": "r2", "seed": 1}
    t0 = time.perf_counter()
    row = bt.run_case_time(case)
    wall = time.perf_counter() - t0
    assert row["verdict"] == "error: RuntimeError: bad" and 0.05 <= row["seconds"] <= wall
    assert row["snr"] == math.inf and row["chatter"] is False and row["confounded"] == []
    assert (row["transfer_shrinkage"], row["transfer_shrinkage_refit"], row["shrinkage"], row["params"],
            row["stationary"], row["steps"]) == (None, None, None, None, None, [])
    monkeypatch.setattr(sys.modules["chainid.gap.diagnose"], "diagnose", lambda *a, **k: _result(
        ranking=[], where=[], residual={"stationary": True, "where": []}))
    # each effect's SNR is taken with the damping of each record (the device's c varies over the records)
    monkeypatch.setattr(bt, "effect_snr", lambda motions, true, hooks, c, sigmas: [1.0] + list(c))
    t0 = time.perf_counter()
    row = bt.run_case_time(case)
    assert 0.05 <= row["seconds"] <= time.perf_counter() - t0 and row["effect_snr"] == [1.0, 3.0, 4.0]


@pytest.mark.slow
def test_records_noise_and_quantisation_by_hand(monkeypatch):
    """``records``: per record a force noise σ = noise·S × 0.8–1.25, a force quantum of 0.5–2 σ on about 30 % of the
    records (README), displacement noise up to 0.003 A; the reported σ of a record is that of its noise plus its
    quantisation error, √(σ² + q²/12) (a uniform error over one step has variance q²/12)."""
    from chainid.gap.benchmark import nonharmonic as bt
    from chainid.records import excitation as ex

    seen = []

    def rec(test, m, model, c, **kw):  # noqa: ANN001
        seen.append((test, m, kw))
        return test

    monkeypatch.setattr(ex, "simulate_motion", rec)
    q_share, n_rec = [], 0
    for seed in range(40):
        case = {"excitation": "random", "chain": "14x50", "effects": [], "levels": [], "c_rel": 0.02,
                "noise": 0.01, "seed": 1000 + seed}
        seen.clear()
        recs, dev = bt.records(case)
        assert recs == ["r1", "r2", "r3", "r4"] and len(dev["sigmas"]) == 4
        for (test, m, kw), sg in zip(seen, dev["sigmas"]):
            s, q = kw["noise_F"], kw["quantum_F"]
            assert 0.8 * 0.01 * dev["S"] <= s <= 1.25 * 0.01 * dev["S"]
            assert q == 0.0 or 0.5 * s <= q <= 2.0 * s
            assert sg == pytest.approx(math.sqrt(s * s + q * q / 12), rel=1e-12)
            assert 0.0 <= kw["noise_x"] <= 0.003 * m.A
            assert kw["force_fn"] is None  # no effect: no hook
            q_share.append(q > 0)
            n_rec += 1
    assert abs(np.mean(q_share) - 0.3) < 4.5 * math.sqrt(0.21 / n_rec)


def test_transfer_case_harmonic_set_is_the_documented_one(monkeypatch):
    """``run_case_transfer``'s docstring: 11 harmonic tests h1 … h11 over the random records' band and amplitudes
    (ω ∈ (¼, ½, 1)·ω_lo × A ∈ (½, 1, 1.5)·Ā at x̄0, then two off-grid tests), 8 cycles of 256 samples, noise σ =
    noise·S, seed + 1; the same device (true model, viscous c, effect hook) as the random records, whose c is the
    same on every record (one device: no c_e(ω, A) spread over the random records that the harmonic set lacks)."""
    from chainid.gap.benchmark import nonharmonic as bt
    from chainid.records import simulate as sim

    case = next(c for c in bt.time_grid(small=True) if c["excitation"] == "transfer")
    _, dev = bt.records(case | {"excitation": "random", "damping_varies": False})
    assert dev["c_records"] == [dev["c"]] * len(dev["motions"])
    seen = {}
    made = []
    real_records = bt.records
    monkeypatch.setattr(bt, "records", lambda c: made.append(c) or real_records(c))

    class Stop(Exception):
        pass

    def recorder(plan, model, c, **kw):  # noqa: ANN001
        seen.update(plan=plan, model=model, c=c, **kw)
        raise Stop

    monkeypatch.setattr(sim, "simulate", recorder)
    assert bt.run_case_transfer(case)["verdict"].startswith("error: ")
    assert made and made[0]["damping_varies"] is False
    wl = 2 * np.pi * min(m.f_max for m in dev["motions"])
    A = float(np.median([m.A for m in dev["motions"]]))
    x0 = float(np.median([np.median(m.x) for m in dev["motions"]]))
    want = [(w * wl, x0, a * A) for w in (0.25, 0.5, 1.0) for a in (0.5, 1.0, 1.5)]
    want += [(0.75 * wl, x0 + 0.1, 0.75 * A), (0.375 * wl, x0 - 0.1, 1.25 * A)]
    assert [p.test for p in seen["plan"]] == [f"h{i}" for i in range(1, 12)]
    np.testing.assert_allclose([(p.omega, p.x0, p.A) for p in seen["plan"]], want, rtol=1e-12)
    assert (seen["n_cycles"], seen["samples_per_cycle"], seen["seed"]) == (8, 256, case["seed"] + 1)
    assert seen["noise_F"] == pytest.approx(case["noise"] * dev["S"], rel=1e-12)
    assert seen["c"] == pytest.approx(dev["c"], rel=1e-12)
    assert (seen["model"].ea_scale, seen["model"].hertz_scale) == (dev["true"].ea_scale, dev["true"].hertz_scale)
    t = np.linspace(0, 1, 50)
    x = 2.0 + 0.2 * np.sin(2 * np.pi * t)
    xd = 0.4 * np.pi * np.cos(2 * np.pi * t)
    np.testing.assert_allclose(seen["force_fn"](t, x, xd, 0 * t, 0 * t), dev["hook"](t, x, xd, 0 * t, 0 * t))


def test_the_benchmark_seed_changes_the_effect_levels_of_every_excitation() -> None:
    """``benchmark-gap --seed`` is the seed of the benchmark's random effects: two seeds draw different effect
    levels in every non-harmonic excitation (the levels come from a generator seeded by the seed and the
    excitation), and one seed draws the same levels again."""
    from chainid.gap.benchmark.nonharmonic import EXCITATIONS, time_grid

    def levels(seed: int) -> dict[str, list[float]]:
        out: dict[str, list[float]] = {}
        for c in time_grid(seed, False, EXCITATIONS):
            out.setdefault(c["excitation"], []).extend(c["levels"])
        return out

    a, b = levels(0), levels(1)
    assert set(a) == set(EXCITATIONS)
    for e in EXCITATIONS:
        assert len(a[e]) == len(b[e]) > 10
        assert not np.allclose(a[e], b[e]), e
    assert levels(0) == a


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


@pytest.mark.parametrize("kind", ["random", "sweep", "startup", "quake"])
def test_benchmark_motion_is_of_its_family(kind):
    """Each excitation family of the non-harmonic benchmark draws its own kind of program."""
    from chainid.gap.benchmark.nonharmonic import motion

    m = motion(kind, np.random.default_rng(3))
    assert m.kind == kind and m.t.size >= 2000 and np.all(np.diff(m.t) > 0)


class _Stop(Exception):
    """Raised by a recorder to end a benchmark case once its call was seen."""


def _motion(n: int, fs: float, f: float) -> SimpleNamespace:
    t = np.arange(n) / fs
    w = 2 * np.pi * f
    return SimpleNamespace(t=t, x=2.0 + 0.1 * np.sin(w * t), xd=0.1 * w * np.cos(w * t),
                           xdd=-0.1 * w * w * np.sin(w * t))


def test_effect_snr_is_the_rms_added_force_over_the_pooled_noise_by_hand():
    from chainid.gap.benchmark.nonharmonic import effect_snr

    # two records of whole periods (Σ ẋ = 0): a constant force C has no part along ẋ, so it counts in full;
    # a force proportional to ẋ is all along ẋ (the fitted viscous c absorbs it): 0
    m1, m2 = _motion(400, 100.0, 1.0), _motion(600, 200.0, 2.0)
    C, s1, s2 = 3.0, 2.0, 5.0

    def offset(t, x, xd, xdd, F):  # noqa: ANN001
        return F + C

    def viscous(t, x, xd, xdd, F):  # noqa: ANN001
        return F + 7.0 * xd

    snr = effect_snr([m1, m2], LinearModel(k=100.0, x_ref=0.0), [offset, viscous], 0.5, [s1, s2])
    want = math.sqrt((400 * C ** 2 + 600 * C ** 2) / (400 * s1 ** 2 + 600 * s2 ** 2))
    assert snr[0] == pytest.approx(want, rel=1e-9)
    assert snr[1] == pytest.approx(0.0, abs=1e-9)
    # no noise at all: 0, not a division by zero
    assert effect_snr([m1], LinearModel(k=100.0, x_ref=0.0), [offset], 0.5, [0.0]) == [0.0]


@pytest.mark.parametrize("direction", ["harmonic>random", "random>harmonic"])
def test_transfer_case_fits_on_one_set_and_scores_the_other(monkeypatch, direction):
    """The module docstring: ``harmonic>random`` fits on the 11 harmonic tests (3 held out) and scores on the
    random records; ``random>harmonic`` fits on the random records (one held out) and scores the harmonic set."""
    from chainid.gap.benchmark.nonharmonic import run_case_transfer, time_grid

    seen = {}

    def recorder(records, holdout, model, **kw):  # noqa: ANN001
        seen.update(train=[r.test for r in records], holdout=list(holdout), validate=[r.test for r in kw["validate"]])
        raise _Stop

    monkeypatch.setattr(sys.modules["chainid.gap.diagnose"], "diagnose", recorder)
    case = next(c for c in time_grid(small=True) if c["excitation"] == "transfer") | {"direction": direction}
    row = run_case_transfer(case)
    assert row["verdict"].startswith("error: _Stop")
    harm, rand = [f"h{i}" for i in range(1, 12)], ["r1", "r2", "r3", "r4"]
    if direction == "harmonic>random":
        assert seen == {"train": harm, "holdout": ["h3", "h6", "h11"], "validate": rand}
    else:
        assert seen == {"train": rand, "holdout": [case["hold"]], "validate": harm}


def _fake_result(steps=("baseline", "friction", "slack"), **kw):
    res = {"verdict": "friction+slack", "baseline": {"excess_rms_N": 30.0, "noise_sigma_N": 4.0},
           "steps": [{"effect": e, "shrinkage": 0.1 * i, "params": {"p": i}} for i, e in enumerate(steps)],
           "best": {"shrinkage": 0.77}, "confounded": [{"pair": ["slack", "contact_law"]}],
           "residual": {"stationary": True, "where": [{"kind": "chatter"}]}, "where": [{"kind": "level"}],
           "ranking": [{"effect": "hysteresis"}, {"effect": "friction"}],
           "transfer": {"pooled": {"shrinkage": 0.8, "shrinkage_refit": 0.6}, "transfers": True, "chain": "friction"}}
    return res | kw


def test_time_and_transfer_rows_by_hand(monkeypatch):
    """The row of a non-harmonic case: snr = excess/noise (30/4), the last step's shrinkage when the chain has an
    effect (else the best's), the steps after the baseline, the first of the ranking, chatter found in `where`
    or in the residual's `where`; a transfer case adds the pooled shrinkages and the transfer verdict."""
    from chainid.gap.benchmark.nonharmonic import run_case_time, run_case_transfer, time_grid

    monkeypatch.setattr(sys.modules["chainid.gap.diagnose"], "diagnose", lambda *a, **k: _fake_result())
    cases = time_grid(small=True)
    row = run_case_time(cases[0])
    assert row["snr"] == 7.5 and row["verdict"] == "friction+slack"
    assert row["shrinkage"] == pytest.approx(0.2) and row["steps"] == ["friction", "slack"] and row["params"] == {"p": 2}
    assert row["confounded"] == [["slack", "contact_law"]] and row["stationary"] is True
    assert row["ranked_first"] == "hysteresis" and row["chatter"] is True
    assert len(row["effect_snr"]) == 1 and row["effect_snr"][0] > 0 and row["seconds"] >= 0
    assert {k: row[k] for k in cases[0]} == cases[0]
    monkeypatch.setattr(sys.modules["chainid.gap.diagnose"], "diagnose", lambda *a, **k: _fake_result(
        steps=("baseline",), residual={"stationary": False}, where=[], ranking=[]))
    row = run_case_time(cases[0])
    assert row["shrinkage"] == 0.77 and row["steps"] == [] and row["params"] == {"p": 0}
    assert row["chatter"] is False and row["ranked_first"] is None and row["stationary"] is False
    monkeypatch.setattr(sys.modules["chainid.gap.diagnose"], "diagnose", lambda *a, **k: _fake_result())
    tr = run_case_transfer(cases[-1])
    assert (tr["transfer_shrinkage"], tr["transfer_shrinkage_refit"], tr["transfers"], tr["transfer_chain"]) == \
        (0.8, 0.6, True, "friction")

    def boom(*a, **k):  # noqa: ANN001
        raise RuntimeError("no")

    monkeypatch.setattr(sys.modules["chainid.gap.diagnose"], "diagnose", boom)
    err = run_case_time(cases[0])
    assert err["verdict"] == "error: RuntimeError: no" and err["snr"] == math.inf and err["chatter"] is False
    assert err["transfer_shrinkage"] is None and err["confounded"] == [] and err["stationary"] is None


def test_quake_records_half_with_a_near_fault_pulse(monkeypatch):
    """README (non-harmonic families): quake records are Kanai–Tajimi noise under an envelope, half of them with
    a near-fault pulse (0.5–1.5), some with a permanent offset (|offset| <= 0.3 mm)."""
    from chainid.gap.benchmark.nonharmonic import motion
    from chainid.records import excitation as ex

    seen = []

    def quake(n, fs, A, x0, rng, **kw):  # noqa: ANN001
        seen.append(kw)
        raise _Stop

    monkeypatch.setattr(ex, "earthquake", quake)
    rng = np.random.default_rng(11)
    for _ in range(400):
        with pytest.raises(_Stop):
            motion("quake", rng)
    pulses = np.array([k["pulse"] for k in seen])
    # binomial(400, 1/2): 200 ± 10 (1σ); ± 50 is 5σ
    assert 150 <= np.count_nonzero(pulses) <= 250
    assert pulses[pulses > 0].min() >= 0.5 and pulses.max() <= 1.5
    offs = np.array([k["offset"] for k in seen])
    assert 0 < np.count_nonzero(offs) < 400 and np.abs(offs).max() <= 0.3


def test_chatter_case_slides_with_coulomb_friction_a_tenth_of_the_force_scale_and_a_tone_on_it():
    """The non-harmonic chatter case (outside the library): while the contact slides fast, the hook adds
    F_c·sgn(ẋ) with F_c = 0.1·S, plus a tone of 0.3–0.8 F_c at max(12 Hz, fs/20) (nonharmonic._outside).  Over
    whole periods of the tone the added force averages F_c; its extremes lie within F_c·(1 ± 0.8)."""
    from chainid.gap.benchmark.nonharmonic import records, time_grid

    case = next(c for c in time_grid(0, False, ("random",)) if c["effects"] == ["chatter"])
    _, dev = records(case)
    F_c = 0.1 * dev["S"]
    t = np.arange(2000) / 1000.0  # 2 s at 1 kHz: the tone at 50 Hz, 100 whole periods
    fast = np.full(t.size, 100.0)  # mm/s, sliding everywhere
    z = np.zeros(t.size)
    up = dev["hooks"][0](t, z, fast, z, z)
    down = dev["hooks"][0](t, z, -fast, z, z)
    assert float(up.mean()) == pytest.approx(F_c, rel=1e-9)
    assert float(down.mean()) == pytest.approx(-F_c, rel=1e-9)
    swing = 0.5 * float(up.max() - up.min())
    assert 0.3 * F_c * 0.99 <= swing <= 0.8 * F_c
