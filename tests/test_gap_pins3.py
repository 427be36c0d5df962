"""Issue 20 §5, gap package (mutG, own seeds 620–659), part 3: the benchmark's rows and records, the plateau rule.

Each test checks a documented behaviour against a hand computation or the documented contract; the expensive
parts (simulation, diagnosis) are replaced by recorders where the test is about what the code hands them.
Units: mm, N, s.
"""
from __future__ import annotations

import math
import sys
import time
from types import SimpleNamespace

import numpy as np
import pytest


# ---------------------------------------------------------------- benchmark.run_case: the harmonic row

def _case(**kw):
    return {"excitation": "harmonic", "family": "pair", "truth": ["friction", "slack"], "effects": ["friction"],
            "levels": [1.0], "noise": 0.02, "chain": "14x50", "plan": "grid3x3", "seed": 3} | kw


def _result(steps=("baseline", "friction", "friction+slack"), **kw):
    return {"verdict": "friction+slack", "baseline": {"excess_rms_N": 30.0, "noise_sigma_N": 4.0},
            "steps": [{"effect": e, "shrinkage": 0.1 * i, "params": {"p": i}} for i, e in enumerate(steps)],
            "best": {"shrinkage": 0.77}, "confounded": [{"pair": ("slack", "contact_law"), "step": 2}],
            "residual": {"stationary": False}} | kw


def _run(monkeypatch, diag):
    from chainid.gap.benchmark.grid import run_case
    from chainid.records import simulate as sim

    monkeypatch.setattr(sim, "simulate", lambda *a, **k: [])
    monkeypatch.setattr(sys.modules["chainid.gap.diagnose"], "diagnose", diag)
    t0 = time.perf_counter()
    row = run_case(_case())
    return row, time.perf_counter() - t0


def test_harmonic_row_by_hand(monkeypatch):
    """``run_case`` (harmonic) from a hand-made diagnosis: the case's keys, the verdict, snr = excess/noise σ
    (30/4), the last step's shrinkage and parameters when the chain has an effect (else the best's shrinkage),
    the effects after the baseline, the confounded pairs as lists, the residual's stationarity; the seconds of
    the diagnosis (between 0 and the call's own duration)."""
    import chainid.gap.diagnose  # noqa: F401  (the module whose diagnose is replaced)

    def slow(*a, **k):  # noqa: ANN001
        time.sleep(0.05)
        return _result()

    row, wall = _run(monkeypatch, slow)
    assert {k: row[k] for k in _case()} == _case()
    assert row["verdict"] == "friction+slack" and row["snr"] == 7.5
    assert row["shrinkage"] == pytest.approx(0.2) and row["params"] == {"p": 2}
    assert row["steps"] == ["friction", "friction+slack"] and row["confounded"] == [["slack", "contact_law"]]
    assert row["stationary"] is False
    assert 0.05 <= row["seconds"] <= wall
    row, _ = _run(monkeypatch, lambda *a, **k: _result(steps=("baseline",), confounded=[],
                                                       baseline={"excess_rms_N": 2.0, "noise_sigma_N": 0.0}))
    assert row["shrinkage"] == 0.77 and row["steps"] == [] and row["params"] == {"p": 0} and row["confounded"] == []
    assert row["snr"] == 2.0 / 1e-300  # σ = 0 is floored, not a division by zero
    row, _ = _run(monkeypatch, lambda *a, **k: _result(steps=(), best=None))
    assert row["shrinkage"] is None and row["params"] is None and row["steps"] == []


def test_harmonic_error_row_by_hand(monkeypatch):
    """A diagnosis that raises is a miss to report: verdict ``error: <type>: <message>``, snr ∞, no shrinkage,
    steps, parameters, stationarity or confounded pairs; its seconds between 0 and the call's duration."""
    import chainid.gap.diagnose  # noqa: F401

    def boom(*a, **k):  # noqa: ANN001
        time.sleep(0.05)
        raise ValueError("boom")

    row, wall = _run(monkeypatch, boom)
    assert row["verdict"] == "error: ValueError: boom" and row["snr"] == math.inf
    assert (row["shrinkage"], row["steps"], row["params"], row["stationary"], row["confounded"]) == (
        None, [], None, None, [])
    assert 0.05 <= row["seconds"] <= wall and {k: row[k] for k in _case()} == _case()


def test_time_rows_time_the_case(monkeypatch):
    """``run_case_time``: the row's seconds are the case's own duration (simulation and diagnosis), for a
    diagnosed case and for one whose diagnosis raises (the error row: verdict, snr ∞, no transfer numbers)."""
    import chainid.gap.diagnose  # noqa: F401
    from chainid.gap.benchmark import nonharmonic as bt

    monkeypatch.setattr(bt, "records", lambda case: (time.sleep(0.05), ([], {"nominal": None, "motions": [], "true": None, "hooks": [], "c": 0.0,
                                                        "sigmas": []}))[1])

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
    monkeypatch.setattr(bt, "effect_snr", lambda *a: [1.0])
    t0 = time.perf_counter()
    row = bt.run_case_time(case)
    assert 0.05 <= row["seconds"] <= time.perf_counter() - t0 and row["effect_snr"] == [1.0]


# ---------------------------------------------------------------- benchmark_time.records: noise of each record

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


# ---------------------------------------------------------------- prepare.other_plateau

def _win(A, m, kept, plateau_A=1.0):
    return SimpleNamespace(cycle_amplitudes=list(A), cycle_means=list(m), cycles_kept=list(kept), plateau_A=plateau_A)


def test_other_plateau_rule_by_hand():
    """``other_plateau``: a whole cycle *outside* the steady window at the plateau's amplitude (within 25 %) about
    a mean more than half that amplitude from the kept cycles' median mean is a second steady state; ramp cycles
    (smaller amplitude), cycles at the same mean, and the kept cycles themselves do not count."""
    from chainid.gap.harmonic.prepare import other_plateau

    kept = [2, 3, 4, 5]
    A = [0.3, 0.6, 1.0, 1.0, 1.0, 1.0, 1.2]
    m = [5.0, 5.0, 5.0, 5.1, 4.9, 5.0, 5.0]
    assert other_plateau(_win(A, m, kept)) == ""  # a ramp-in, the plateau, one more cycle at its mean
    # cycle 6 at 1.2 A (within 25 %) about x = 5.6 (0.6 A away, > 0.5 A): another plateau
    msg = other_plateau(_win(A, m[:6] + [5.6], kept))
    assert msg == ("not one steady harmonic test: cycle 6 oscillates at the plateau amplitude (1.2 mm) about "
                   "x = 5.6 mm, 0.6 mm from the steady window's mean (a load step or another plateau)")
    assert other_plateau(_win(A, m[:6] + [5.45], kept)) == ""  # 0.45 A away: the same plateau
    assert other_plateau(_win(A[:6] + [1.3], m[:6] + [5.6], kept)) == ""  # 1.3 A: not the plateau's amplitude
    assert other_plateau(_win(A[:6] + [0.74], m[:6] + [4.0], kept)) == ""  # 0.74 A: a ramp cycle
    assert other_plateau(_win(A[:6] + [0.76], m[:6] + [4.0], kept)).startswith("not one steady harmonic test: "
                                                                                "cycle 6 ")
    # the first such cycle is named; a kept cycle far from the others' median is not "outside"
    assert "cycle 0 " in other_plateau(_win([1.0] + A[1:6] + [1.0], [3.0] + m[1:6] + [7.0], kept))
    assert other_plateau(_win(A[:6], m[:5] + [6.0], kept)) == ""
    # nothing to judge: no kept cycle, mismatched lists, no plateau amplitude
    assert other_plateau(_win(A, m[:6] + [5.6], [])) == ""
    assert other_plateau(_win(A, m[:6], kept)) == ""
    assert other_plateau(_win(A, m[:6] + [5.6], kept, plateau_A=0.0)) == ""
    assert other_plateau(_win(A, m[:6] + [5.6], kept + [9])) != ""  # an index beyond the cycles is ignored


# ---------------------------------------------------------------- where_time.state_maps: share, z and the text

def _maps(sigma2, n=1600):
    from chainid.gap.timedomain.where import state_maps

    x = np.linspace(0.0, 8.0, n)  # a monotonic stroke: ẋ constant, travel since reversal = x
    r = np.where(x > 4.0, 1.0, -1.0)  # a residual that is a step in x: ±1 N
    load = np.random.default_rng(1).normal(0.0, 1.0, n)  # unrelated to r
    d = SimpleNamespace(test="R", t=np.arange(n) * 0.01, x=x, xd=np.full(n, 8.0 / (n - 1) / 0.01),
                        sigma=math.sqrt(sigma2))
    return {m["variable"]: m for m in state_maps([d], {"R": r}, {"R": load})}


def test_state_map_share_and_threshold_by_hand():
    """``state_maps``: 16 quantile bins of each variable; a residual ±1 N stepping at the middle of x has bin means
    ±1, between-bin variance 1 = its whole variance (share 100 %).  The noise's between-bin variance is ν = σ²·16/n
    and z = (1 − ν)/(ν·√(2/15)) must reach Z_MAP = 5: ν < 1/(1 + 5·√(2/15)) = 0.35389, i.e. σ² < 35.389 for n =
    1600.  ẋ is constant (two levels at most: skipped); travel since reversal equals x here (the same map); the
    load is unrelated noise (no map)."""
    maps = _maps(35.2)  # z = 5.04
    assert sorted(maps) == ["travel", "x"]
    m = maps["x"]
    assert m["share"] == pytest.approx(1.0, rel=1e-12) and m["score"] == pytest.approx(1.0, rel=1e-12)
    assert m["kind"] == "state" and m["bin_means_N"] == [-1.0] * 8 + [1.0] * 8
    np.testing.assert_allclose(m["bin_centres"], 0.25 + 0.5 * np.arange(16), atol=1e-9)
    assert m["finding"] == ("residual follows the displacement x: bin means from -1 to +1 N carry 100 % of its "
                            "variance (→ stiffness side (level, contact law, offset))")
    assert maps["travel"]["finding"].startswith("residual follows the travel since the last reversal: ")
    assert maps["travel"]["finding"].endswith("(→ memory after reversals (stick, hysteresis, play))")
    assert _maps(35.6) == {}  # z = 4.95


def test_state_map_bins_of_one_sample_by_hand():
    """17 samples of a monotonic stroke x = 0 … 16 mm: the 17 quantile edges are the samples themselves, so bins
    0 … 14 hold one sample each and the last bin two (x = 15 and 16).  A residual r = x − 8 N has bin means
    −8 … 6 N, then 7.5 N -- each a mean over its own samples, computed here by hand.  Bug caught (seed 25): the
    bin count's floor ``max(cnt, 1)`` → ``max(cnt, 2)`` (every one-sample bin's mean halved)."""
    from chainid.gap.timedomain.where import state_maps

    x = np.arange(17.0)
    d = SimpleNamespace(test="S", t=x * 0.1, x=x, xd=np.full(17, 10.0), sigma=0.01)
    m = {k["variable"]: k for k in state_maps([d], {"S": x - 8.0}, {"S": np.zeros(17)})}["x"]
    assert m["bin_means_N"] == [float(v) for v in range(-8, 7)] + [7.5]
    assert m["bin_centres"] == [j + 0.5 for j in range(16)]


# ---------------------------------------------------------------- where_time.spectrum_outside by hand

def _rec(name, fs, f_band, sigma, amp, n=4000, f=200.0):
    t = np.arange(n) / fs
    return SimpleNamespace(test=name, fs=fs, f_band=f_band, sigma=sigma, t=t), amp * np.sin(2 * np.pi * f * t)


def test_spectrum_outside_the_band_by_hand():
    """``spectrum_outside``: a residual tone at 200 Hz, far above the cut 4 × f_band = 20 Hz (a 4th-order low-pass
    run twice takes off (20/200)^8 of it), against white noise of σ over the band above the cut (a fraction
    1 − f_c/(fs/2) of the power): ratio = √(Σ n·a²/2 / Σ σ²·(1 − f_c/(fs/2))·n), pooled over records; above 1.5
    the text names content outside the band; a record whose cut reaches 0.45 fs is skipped."""
    from chainid.gap.timedomain.where import spectrum_outside

    d1, r1 = _rec("A", 1000.0, 5.0, 1.0, 3.0)  # cut 20 Hz: fraction 0.96
    d2, r2 = _rec("B", 800.0, 10.0, 2.0, 1.0, n=3200)  # cut 40 Hz: fraction 0.9
    got = spectrum_outside([d1, d2], {"A": r1, "B": r2})
    want = math.sqrt((4000 * 9 / 2 + 3200 * 1 / 2) / (1.0 * 0.96 * 4000 + 4.0 * 0.9 * 3200))
    assert got["ratio_to_noise"] == pytest.approx(want, rel=2e-3) and got["kind"] == "spectrum"
    assert got["score"] == 0.0
    assert got["finding"] == (f"residual above 4× the excitation band: RMS {want:.2f}× white noise of the records' σ "
                              "over that bandwidth (noise)")  # 1.16 <= 1.5
    got = spectrum_outside([d1], {"A": r1})
    assert got["ratio_to_noise"] == pytest.approx(math.sqrt(4.5 / 0.96), rel=2e-3)
    assert got["finding"].endswith("RMS 2.17× white noise of the records' σ over that bandwidth (content outside the "
                                   "excitation's band: ringing, impacts, chatter or a sensor resonance)")
    d3, r3 = _rec("C", 100.0, 11.25, 1.0, 3.0, f=30.0)  # cut 45 Hz = 0.45 fs: nothing above the band to judge
    assert spectrum_outside([d3], {"C": r3}) == {}
    d4, r4 = _rec("D", 100.0, 11.2, 1.0, 3.0, f=48.0)
    assert spectrum_outside([d4], {"D": r4}) != {}


# ---------------------------------------------------------------- where_time.drift: the quarter rule by hand

def _drift_recs(n_rec, n_drift, n=640, slope=0.5):
    rng = np.random.default_rng(4)
    data, res = [], {}
    for i in range(n_rec):
        t = np.arange(n) * 0.01
        data.append(SimpleNamespace(test=f"r{i}", t=t, x=rng.normal(0.0, 1.0, n), sigma=0.1))
        res[f"r{i}"] = slope * t if i < n_drift else np.zeros(n)
    return data, res


def test_drift_quarter_rule_change_and_text_by_hand():
    """``drift``: per record min(20, n/32) blocks (n = 640: 20 blocks of 32 samples, block-mean times 0.155 …
    6.235 s); a residual 0.5 N/s·t has slope 0.5 and change 0.5 × 6.08 = 3.04 N; non-stationary when the
    significant records are at least a quarter, ceil(0.25·n_rec) (1 of 5 is not, 2 of 5 are); the change is the
    RMS over records counting the others as 0: √(2·3.04²/5)."""
    from chainid.gap.timedomain.where import drift

    data, res = _drift_recs(5, 1)
    got = drift(data, res)
    assert got["stationary"] is True and got["trend_change_N"] == pytest.approx(math.sqrt(3.04**2 / 5), rel=1e-9)
    assert got["finding"] == "the residual is stationary over each record (no significant drift of its block means)"
    rows = {r["test"]: r for r in got["tests"]}
    assert rows["r0"]["slope_N_per_s"] == pytest.approx(0.5, rel=1e-9)
    assert rows["r0"]["change_N"] == pytest.approx(3.04, rel=1e-9) and rows["r0"]["z"] > 100
    assert rows["r1"]["z"] == pytest.approx(0.0, abs=1e-6) and got["z"] == rows["r0"]["z"]
    data, res = _drift_recs(5, 2)
    got = drift(data, res)
    chg = math.sqrt(2 * 3.04**2 / 5)
    assert got["stationary"] is False and got["trend_change_N"] == pytest.approx(chg, rel=1e-9)
    assert got["finding"] == (f"non-stationary: the residual drifts with time in 2 of 5 records (change {chg:.3g} N "
                              f"RMS over records, up to {got['z']:.1f} standard errors) beyond what x explains: drift, "
                              "relaxation, heating or wear, which no static library effect explains")
    assert drift(*_drift_recs(4, 1))["stationary"] is False  # 1 of 4 is a quarter
    # 320 samples: 10 blocks of 32 (first and last block means 0.155 and 3.035 s); 191 samples: < 6 blocks, skipped
    got = drift(*_drift_recs(1, 1, n=320))
    assert got["tests"][0]["change_N"] == pytest.approx(0.5 * 2.88, rel=1e-9)
    got = drift(*_drift_recs(2, 2, n=191))
    assert got == {"stationary": None, "trend_change_N": 0.0, "z": 0.0, "tests": [],
                   "finding": "stationarity not checked: records too short for the drift test"}


# ---------------------------------------------------------------- where_time.backbone by hand

def _triangle(g, n=2000, fs=500.0):
    """x a triangle 0 … 2 mm at 1 mm/s (period 4 s), F = g(travel since the last turn) [N]."""
    t = np.arange(n) / fs
    ph = np.mod(t, 4.0)
    x = np.where(ph < 2.0, ph, 4.0 - ph)
    xd = np.where(ph < 2.0, 1.0, -1.0)
    tr = np.where(ph < 2.0, ph, ph - 2.0)
    return SimpleNamespace(test="R", t=t, x=x, xd=xd, F=g(tr))


def test_backbone_kinds_by_hand():
    """``backbone``: travel uniform on (0, 2] mm, so T25 = 0.5, T75 = 1.5 mm; k_small = |ΔF|(T25)/T25, k_large =
    (|ΔF|(T75) − |ΔF|(T25))/(T75 − T25).  Play of 0.3 mm then 100 N/mm: 20/0.5 = 40 against 100 N/mm, ratio 0.4 <=
    1/2: a dead band; 100 N/mm up to 0.5 mm then 20 N/mm: ratio 5 >= 2: stiff then soft; a linear backbone
    (ratio 1): no finding; fewer than 200 samples with travel: not judged (seed-25 survivor: ``< 200`` → ``< 199``)."""
    from chainid.gap.timedomain.where import backbone

    (f,) = backbone([_triangle(lambda tr: 100.0 * np.maximum(tr - 0.3, 0.0))])
    assert f["kind"] == "backbone" and f["test"] == "R" and f["score"] == 0.0
    assert f["travel_T25_mm"] == pytest.approx(0.5, abs=0.01) and f["travel_T75_mm"] == pytest.approx(1.5, abs=0.01)
    assert f["k_small_N_per_mm"] == pytest.approx(40.0, rel=0.02) and f["k_large_N_per_mm"] == pytest.approx(100.0,
                                                                                                            rel=0.02)
    assert f["ratio"] == pytest.approx(0.4, rel=0.03)
    assert f["finding"] == (f"test R: the measured force after reversals shows a dead band then stiffening: "
                            f"{f['k_small_N_per_mm']:.3g} N/mm over the first {f['travel_T25_mm']:.3g} mm of travel "
                            f"after a reversal, {f['k_large_N_per_mm']:.3g} N/mm beyond (play closing onto a contact)")
    (f,) = backbone([_triangle(lambda tr: np.where(tr < 0.5, 100.0 * tr, 50.0 + 20.0 * (tr - 0.5)))])
    assert f["k_small_N_per_mm"] == pytest.approx(100.0, rel=0.02) and f["k_large_N_per_mm"] == pytest.approx(20.0,
                                                                                                             rel=0.03)
    assert f["finding"] == (f"test R: the measured force after reversals shows stiff at small travel then softer: "
                            f"{f['k_small_N_per_mm']:.3g} N/mm up to {f['travel_T25_mm']:.3g} mm after a reversal, "
                            f"{f['k_large_N_per_mm']:.3g} N/mm beyond (stick / pre-sliding, then sliding)")
    assert backbone([_triangle(lambda tr: 70.0 * tr)]) == []
    # ratio just inside each threshold: 0.55 (play 0.225 mm: 27.5/0.5 = 55 against 100) and 1.9 are no finding
    assert backbone([_triangle(lambda tr: 100.0 * np.maximum(tr - 0.225, 0.0))]) == []
    assert backbone([_triangle(lambda tr: np.where(tr < 0.5, 100.0 * tr, 50.0 + 52.6 * (tr - 0.5)))]) == []
    assert backbone([_triangle(lambda tr: 100.0 * np.maximum(tr - 0.3, 0.0), n=199)]) == []
    # the count at its edge: the first sample has no travel, so n = 200 leaves 199 samples with travel (not judged)
    # and n = 201 leaves 200 (judged: the play closing at 0.3 mm within the first 0.4 mm of the stroke)
    assert backbone([_triangle(lambda tr: 100.0 * np.maximum(tr - 0.3, 0.0), n=200)]) == []
    assert len(backbone([_triangle(lambda tr: 100.0 * np.maximum(tr - 0.3, 0.0), n=201)])) == 1


# ---------------------------------------------------------------- where.delay_signature: the fundamental's line

def test_delay_signature_fundamental_phase_line_and_its_r2_by_hand():
    """The fundamental's phase of F against x, φ₁ = atan2(b, a) of F = a sin ψ + b cos ψ + …: a lag τ = 2 ms and a
    damping part q cos ψ give a = 500 cos ωτ, b = q − 500 sin ωτ.  The straight line through (ω, φ₁) and its
    R² = 1 − SS_res/SS_tot are a least-squares fit by hand (phases small, SS_tot < 1 rad²)."""
    from chainid.gap.harmonic.where import delay_signature

    B, tau = 64, 0.002
    psi = (np.arange(B) + 0.5) * 2 * math.pi / B
    ws, qs = (10.0, 20.0, 30.0, 40.0), (5.0, 0.0, 8.0, 2.0)
    data, model = [], {}
    for i, (w, q) in enumerate(zip(ws, qs)):
        F = 500 * np.sin(psi - w * tau) + 100 * np.sin(2 * (psi - w * tau)) + q * np.cos(psi)
        data.append(SimpleNamespace(test=f"T{i}", omega=w, sigma=0.1, counts=np.full(B, 10.0), Fbar=F))
        model[f"T{i}"] = 500 * np.sin(psi) + 100 * np.sin(2 * psi)
    w = np.array(ws)
    p1 = np.arctan2(np.array(qs) - 500 * np.sin(w * tau), 500 * np.cos(w * tau))
    X = np.column_stack([w, np.ones(4)])
    (s, c0), *_ = np.linalg.lstsq(X, p1, rcond=None)
    ss = float(np.sum((p1 - p1.mean()) ** 2))
    r2 = 1 - float(np.sum((p1 - X @ [s, c0]) ** 2)) / ss
    assert ss < 1 and 0.5 < r2 < 0.99
    sig = delay_signature(data, model)
    assert sig["phase1_slope_s"] == pytest.approx(s, rel=1e-9)
    assert sig["phase1_intercept_rad"] == pytest.approx(c0, rel=1e-9, abs=1e-12)
    assert sig["phase1_r2"] == pytest.approx(r2, rel=1e-9)
    assert sig["n_points"] == 4 and sig["tau_harmonics_s"] == pytest.approx(tau, rel=1e-9)  # harmonic 2 only
    # two distinct frequencies: no line (nan), no harmonic reading either below two frequencies
    two = delay_signature(data[:2] + [SimpleNamespace(**(vars(data[1]) | {"test": "T9"}))], model | {"T9": model["T1"]})
    assert math.isnan(two["phase1_slope_s"]) and math.isnan(two["phase1_r2"])


# ---------------------------------------------------------------- transfer: the noise floor of harmonic records

def test_transfer_of_the_true_model_leaves_harmonic_records_at_their_noise_floor():
    """``transfer`` on steady harmonic records: a bin mean of n samples carries noise σ²/n, so the model that
    simulated the records (the paper's plan, viscous c_e) leaves them at 0 dB over their noise (within ± 1 dB over
    9 × 64 bins) and at the noise floor; with no effect named the text says so."""
    from chainid.gap.harmonic.prepare import prepare_test
    from chainid.gap.harmonic.problem import Problem
    from chainid.gap.core.selection import baseline_candidate
    from chainid.gap.transfer import transfer
    from chainid.model.base import ChainModel
    from chainid.model.laws import ViscousLaw
    from chainid.records.simulate import paper_plan, simulate

    model = ChainModel()
    kw = dict(n_cycles=6, samples_per_cycle=128, noise_F=30.0)
    fit = simulate(paper_plan(), model, ViscousLaw([2834.4]), seed=1, **kw)
    other = simulate(paper_plan(), model, ViscousLaw([2834.4]), seed=2, **kw)
    prob = Problem([prepare_test(r) for r in fit], model, ["5"])
    base = baseline_candidate(prob)
    tr = transfer({"_problem": prob, "_path": [base]}, other)
    assert abs(tr["pooled"]["model_db_over_noise"]) < 1.0 and tr["pooled"]["model_at_noise_floor"] is True
    assert tr["transfers"] is False and tr["chain"] == "baseline"
    assert tr["verdict_text"].startswith("no effect was named on the fitting set; on the other set the baseline "
                                         "leaves NRMSE ")


# ---------------------------------------------------------------- benchmark_time: the transfer case's harmonic set

def test_transfer_case_harmonic_set_is_the_documented_one(monkeypatch):
    """``run_case_transfer``'s docstring: 11 harmonic tests h1 … h11 over the random records' band and amplitudes
    (ω ∈ (¼, ½, 1)·ω_lo × A ∈ (½, 1, 1.5)·Ā at x̄0, then two off-grid tests), 8 cycles of 256 samples, noise σ =
    noise·S, seed + 1; the same device (true model, viscous c, effect hook) as the random records."""
    from chainid.gap.benchmark import nonharmonic as bt
    from chainid.records import simulate as sim

    case = next(c for c in bt.time_grid(small=True) if c["excitation"] == "transfer")
    _, dev = bt.records(case | {"excitation": "random"})
    seen = {}

    class Stop(Exception):
        pass

    def recorder(plan, model, c, **kw):  # noqa: ANN001
        seen.update(plan=plan, model=model, c=c, **kw)
        raise Stop

    monkeypatch.setattr(sim, "simulate", recorder)
    assert bt.run_case_transfer(case)["verdict"].startswith("error: ")
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
