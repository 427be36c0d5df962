"""Where the time-domain residual sits (chainid.gap.timedomain.where): drift, state maps, the spectrum outside the
band, ringing while sliding, the backbone, by hand.  Units s, mm, N, Hz."""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from chainid.gap.timedomain.where import PEAK, RING_RATIO, ringing

from transient_forms import chain_set


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


def test_local_peak_over_the_octave_median():
    """A flat power spectrum with one line 50× higher at 40 Hz: the peak is found at 40 Hz with height 50 (the
    median within ± one octave is the flat level).  Bug caught: the octave window's upper edge garbled."""
    from chainid.gap.timedomain.where import OCT, _local_peak

    f = np.arange(1.0, 201.0)
    P = np.ones_like(f)
    P[39] = 50.0
    fk, h = _local_peak(f, P, 5.0)
    assert fk == 40.0 and h == pytest.approx(50.0, rel=1e-12)
    assert OCT == 2.0
    P2 = np.ones_like(f)
    P2[f >= 75] = 100.0  # a broad raised band: 66 of the 106 bins of 70 Hz's octave 35..140 Hz
    P2[69] = 60.0  # a line at 70 Hz below the band's level: no narrow peak (ratio 0.6)
    fk2, h2 = _local_peak(f, P2, 5.0)
    assert h2 == pytest.approx(1.0, rel=1e-12)  # the flat parts' ratio 1 is the best anywhere


def _ring_record(name, xd, f_band=2.0, fs=1000.0, sigma=0.05):
    """What ``ringing`` reads of a record: id, band [Hz], sampling rate [Hz], velocity [mm/s], force noise σ [N]."""
    return SimpleNamespace(test=name, f_band=f_band, fs=fs, xd=xd, sigma=sigma)


def _ring(name, s2, amp=5.0, n=8000, fs=1000.0):
    t = np.arange(n) / fs
    xd = 2 * math.pi * np.cos(2 * math.pi * t)  # x = sin(2π t)
    sliding = np.abs(xd) >= 0.2 * np.quantile(np.abs(xd), 0.99)
    res = amp * np.sin(2 * math.pi * 60.0 * t) * np.where(sliding, 1.0, math.sqrt(s2))
    return _ring_record(name, xd, fs=fs), res


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
                              f"peak {got['peak_ratio']:.0f}× its neighbourhood and the force noise): stick-slip "
                              "chatter — no library effect covers it, so it is reported, not named")
    d2, r2 = _ring("B", 1 / 1.8, amp=20.0)
    got = ringing([d2], {"B": r2})
    assert got["chatter"] is False and got["ratio"] == pytest.approx(1.8, rel=0.05) and got["score"] == 0.0
    assert got["finding"] == (f"no ringing after reversals (sliding high-frequency residual {got['ratio']:.2f}× "
                              f"elsewhere, largest narrow peak {got['peak_ratio']:.1f}× its neighbourhood and the "
                              "force noise)")
    both = ringing([d2, d1], {"A": r1, "B": r2})
    assert both["test"] == "A" and both["kind"] == "chatter" and both["score"] == both["rms_N"]
    assert ringing([d2, _ring("C", 1 / 1.9, amp=30.0)[0]], {"B": r2, "C": _ring("C", 1 / 1.9, amp=30.0)[1]})[
        "test"] == "C"  # no chatter anywhere: the loudest record
    still = _ring_record("S", np.full(8000, 3.0))
    assert ringing([still], {"S": r1}) == {}


# ---------------------------------------------------------------- where_time.ringing
def _ring_case(burst_everywhere: bool, sigma: float = 0.05):
    fs, n = 1000.0, 8000
    t = np.arange(n) / fs
    xd = 2 * math.pi * np.cos(2 * math.pi * 1.0 * t)  # x = sin(2π t): 1 Hz motion
    sliding = np.abs(xd) >= 0.2 * np.quantile(np.abs(xd), 0.99)
    hum = 5.0 * np.sin(2 * math.pi * 60.0 * t)  # 60 Hz, far above the cut 4 × 2 Hz
    res = hum if burst_everywhere else np.where(sliding, hum, 0.0) + 0.05 * np.random.default_rng(1).normal(size=n)
    d = _ring_record("R", xd, fs=fs, sigma=sigma)
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


def test_a_ring_below_the_records_own_force_noise_is_not_chatter():
    """The residual is of the band-limited force: a ring tied to sliding but far below the noise the raw record
    carries is not measurable as chatter.  The 5 N tone while sliding (mean square 12.5 N² in about one Hann-window
    bin of fs/2048 = 0.49 Hz, ENBW 1.5 bins: ≈ 17 N²/Hz) against a white force noise of density 2σ²/fs: with σ = 2 N
    (0.008 N²/Hz) the peak is 2000× it, chatter; with σ = 100 N (20 N²/Hz, 17 over the sliding share) it is about
    equal to it, ringing only.  (Seed 1 of the time grid: 11 quake and start-up cases gave 0.04–2.3 N "chatter"
    under 5–23 N of noise, an artefact of the band-limited residual.)"""
    loud, _ = _ring_case(False, sigma=2.0)
    assert loud["chatter"] is True and loud["peak_ratio"] >= PEAK
    buried, _ = _ring_case(False, sigma=100.0)
    assert buried["chatter"] is False and buried["kind"] == "ringing" and buried["peak_ratio"] < 1.5
    assert buried["ratio"] == pytest.approx(loud["ratio"])  # the sliding/rest contrast itself is unchanged


def test_ringing_is_not_looked_for_when_the_band_reaches_the_sampling():
    """The ringing check needs room above the band: a record whose cut 4·f_band is at or above 0.2·fs (here
    4·6 = 24 Hz ≥ 20 Hz at fs = 100 Hz) is skipped, so one such record gives no finding at all."""
    fs = 100.0
    t = np.arange(4000) / fs
    xd = np.cos(2 * math.pi * t)
    res = np.where(np.abs(xd) > 0.2, 5.0 * np.sin(2 * math.pi * 40.0 * t), 0.0)
    assert ringing([_ring_record("R", xd, f_band=6.0, fs=fs)], {"R": res}) == {}
    assert ringing([_ring_record("R", xd, f_band=4.9, fs=fs)], {"R": res}) != {}  # 19.6 Hz < 20 Hz


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


def test_backbone_dead_band_of_play():
    # play b = 0.06 mm: after each reversal the force changes little over the first travel, then at full stiffness
    from chainid.gap.timedomain.data import prepare_time
    from chainid.gap.timedomain.where import backbone

    _, recs = chain_set("backlash", {"b": 0.06}, n_rec=1, seed=90)
    f = backbone([prepare_time(r, 1) for r in recs])
    assert f and "dead band" in f[0]["finding"]
    assert f[0]["ratio"] <= 0.5
    _, lin = chain_set("none", {}, n_rec=1, seed=91)  # the chain alone: no backbone finding
    assert backbone([prepare_time(r, 1) for r in lin]) == []


def _trec(name, slope, n=640, sigma=32.0 ** 0.5):
    t = np.arange(n) / 64.0
    return SimpleNamespace(test=name, t=t, x=np.full(n, 2.0), sigma=sigma), slope * t


def test_time_drift_rule_by_hand():
    """640 samples (10 s) in N_DRIFT = 20 blocks of 32: block mid-times 0.5 s apart, Σ(t − t̄)² = 0.25·665; the
    floor σ/sqrt(32) = 1 N (σ = sqrt 32); a noise-free residual slope of 2 N/s: z = 2·sqrt(166.25), change
    2·9.5 = 19 N.  Non-stationary when at least a quarter of the records drift (1 of 4, not 1 of 5)."""
    from chainid.gap.timedomain.where import drift

    def run(slopes):
        recs = [_trec(f"r{i}", s) for i, s in enumerate(slopes)]
        return drift([d for d, _ in recs], {d.test: r for d, r in recs})

    out = run([2.0, 0.0, 0.0, 0.0])
    z = 2.0 * math.sqrt(166.25)
    assert out["stationary"] is False and out["z"] == pytest.approx(z, rel=1e-9)
    assert out["tests"][0]["change_N"] == pytest.approx(19.0, rel=1e-9)
    assert out["trend_change_N"] == pytest.approx(math.sqrt(19.0 ** 2 / 4), rel=1e-9)
    assert out["finding"].startswith(f"non-stationary: the residual drifts with time in 1 of 4 records (change 9.5 N "
                                      f"RMS over records, up to {z:.1f} standard errors)")
    five = run([2.0, 0.0, 0.0, 0.0, 0.0])
    assert five["stationary"] is True and five["finding"].startswith("the residual is stationary over each record")
    # the z threshold (Z_TREND = 4): slope 3.9/sqrt(166.25) is not a drift, 4.1/… is
    assert run([3.9 / math.sqrt(166.25)])["stationary"] is True
    assert run([4.1 / math.sqrt(166.25)])["stationary"] is False
    # fewer than 6 blocks of 32 samples: not checked
    short = [_trec("s", 1.0, n=191)]
    res = drift([short[0][0]], {"s": short[0][1]})
    assert res == {"stationary": None, "trend_change_N": 0.0, "z": 0.0, "tests": [],
                   "finding": "stationarity not checked: records too short for the drift test"}
    ok = _trec("s", 1.0, n=192)
    assert len(drift([ok[0]], {"s": ok[1]})["tests"]) == 1  # 6 blocks of 32


def test_state_map_threshold_by_hand():
    """A residual ±a split at the median of x: 16 quantile bins of x with means ±a, between-bin variance a²;
    pure noise of σ would give σ²·16/N; z = (a² − σ²·16/N)/(σ²·16/N · sqrt(2/15)); reported from z = 5 on, with
    the bin means' range and the share of the residual's variance (100 %)."""
    from chainid.gap.timedomain.where import state_maps

    n, sig = 1600, 1.0
    x = np.linspace(1.0, 3.0, n)
    noise = sig ** 2 * 16 / n

    def maps(z):
        a = math.sqrt(noise * (1 + z * math.sqrt(2 / 15)))
        d = SimpleNamespace(test="r", t=np.arange(n) / 100.0, x=x, xd=np.zeros(n), sigma=sig)
        out = state_maps([d], {"r": np.where(x < 2.0, a, -a)}, {"r": np.zeros(n)})
        return a, {f["variable"]: f for f in out}

    a, got = maps(5.1)
    f = got["x"]
    assert f["share"] == pytest.approx(1.0, rel=1e-9) and len(f["bin_means_N"]) == 16
    assert f["finding"] == (f"residual follows the displacement x: bin means from {-a:+.3g} to {a:+.3g} N carry "
                            "100 % of its variance (→ stiffness side (level, contact law, offset))")
    assert f["score"] == pytest.approx(a, rel=1e-9)
    assert "load" not in got  # a constant model force has no bins
    assert "x" not in maps(4.9)[1]


def test_spectrum_outside_the_band_of_a_40_hz_sine_by_hand():
    """A 40 Hz sine of amplitude a in the residual, band 2 Hz (cut 4× = 8 Hz), fs = 100 Hz, σ = 1 N: the high
    pass keeps the sine, RMS² a²/2 against white noise over 8 … 50 Hz, σ²·(1 − 8/50): ratio sqrt(a²/2/0.84);
    above 1.5 it is called content outside the band, else noise.  A band whose cut reaches 0.45·fs is skipped."""
    from chainid.gap.timedomain.where import spectrum_outside

    n, fs = 4000, 100.0
    t = np.arange(n) / fs
    d = SimpleNamespace(test="r", t=t, fs=fs, f_band=2.0, sigma=1.0)
    for a, tail in ((1.0, " (noise)"), (3.0, " (content outside the excitation's band: ringing, impacts, chatter or "
                                           "a sensor resonance)")):
        out = spectrum_outside([d], {"r": a * np.sin(2 * np.pi * 40.0 * t)})
        want = math.sqrt(a * a / 2 / 0.84)
        assert out["ratio_to_noise"] == pytest.approx(want, rel=2e-3)
        assert out["finding"] == (f"residual above 4× the excitation band: RMS {out['ratio_to_noise']:.2f}× white "
                                  "noise of the records' σ over that bandwidth" + tail)
    wide = SimpleNamespace(test="r", t=t, fs=fs, f_band=11.25, sigma=1.0)  # 4 · 11.25 = 45 Hz = 0.45 fs
    assert spectrum_outside([wide], {"r": np.sin(2 * np.pi * 40.0 * t)}) == {}


def test_sliding_median_equals_one_median_per_window():
    """The sliding sorted window gives every window's ``np.median`` exactly, for windows that grow, shrink, jump
    past each other and hold ties, and the peak search over it equals a brute-force loop of one median per bin."""
    from chainid.gap.timedomain.where import OCT, _local_peak, sliding_median

    rng = np.random.default_rng(5)
    vals = np.round(rng.exponential(1.0, 600), 1)  # ties on purpose
    lo = np.sort(rng.integers(0, 550, 300))
    hi = np.minimum(np.maximum.accumulate(lo + rng.integers(1, 60, lo.size)), vals.size)
    ref = np.array([np.median(vals[a:b]) for a, b in zip(lo, hi)])
    assert np.array_equal(sliding_median(vals, lo, hi), ref)
    nan = vals.copy()
    nan[10] = np.nan
    assert np.array_equal(sliding_median(nan, lo, hi), np.array([np.median(nan[a:b]) for a, b in zip(lo, hi)]),
                          equal_nan=True)
    f = np.fft.rfftfreq(4096, 1 / 2000.0)
    P = rng.chisquare(2, f.size) * (1 + 1e3 / (1 + f))
    P[1234] *= 40.0
    best = (float("nan"), 0.0)
    for k in np.flatnonzero(f >= 30.0):
        m = (f >= f[k] / OCT) & (f <= f[k] * OCT)
        if m.sum() >= 5 and P[k] / np.median(P[m]) > best[1]:
            best = (float(f[k]), float(P[k] / np.median(P[m])))
    assert _local_peak(f, P, 30.0) == best
    assert best[0] == f[1234]


def test_sliding_median_clips_windows_and_gives_nan_for_an_empty_one_as_numpy_does():
    """Windows past the array's end are clipped (``np.median`` of the slice); an empty window is NaN; a NaN power
    bin makes no peak of the bins whose octave holds it (their median is NaN, as in the loop of one median per bin),
    and a line whose octave is clean is still found."""
    from chainid.gap.timedomain.where import _local_peak, sliding_median

    v = np.arange(10.0)
    out = sliding_median(v, np.array([0, 5, 8, 10]), np.array([4, 12, 12, 10]))
    np.testing.assert_array_equal(out[:3], [np.median(v[0:4]), np.median(v[5:]), np.median(v[8:])])
    assert math.isnan(out[3])
    f = np.arange(1.0, 201.0)
    P = np.ones_like(f)
    P[99] = 30.0  # a line at 100 Hz
    P[9] = np.nan  # 10 Hz: in the octaves of 5–20 Hz only
    assert _local_peak(f, P, 5.0) == (100.0, 30.0)


def test_level_finding_pools_the_records_noise_variances_by_their_samples():
    """The first finding of ``localise_time`` is the residual's level: its RMS over the pooled noise σ, the root of
    the sample-weighted mean of the records' σ² (records of 1000 and 1500 samples, σ ≈ 0.1 N and 0.3 N)."""
    import recovery_cases as rc
    from chainid.gap.timedomain.data import prepare_time
    from chainid.gap.timedomain.where import localise_time

    recs = rc.linear_random(n_rec=1, n=1000) + rc.linear_random(n_rec=1, n=1500, sigma_F=0.3, seed=1)
    data = [prepare_time(r, 4) for r in recs]
    data[1].test = "s"  # both simulated as "r0"
    rng = np.random.default_rng(2)
    res = {d.test: rng.normal(0.0, 0.5, d.t.size) for d in data}
    lev = [f for f in localise_time(data, res, {d.test: d.F for d in data}) if f["kind"] == "level"][0]
    n1, n2 = data[0].t.size, data[1].t.size
    s2 = (n1 * data[0].sigma ** 2 + n2 * data[1].sigma ** 2) / (n1 + n2)
    assert 0.05 < data[0].sigma < 0.2 and 0.2 < data[1].sigma < 0.45  # the two records' own noise, as drawn
    assert lev["noise_floor_N"] == pytest.approx(math.sqrt(s2), rel=1e-12)
    rms = math.sqrt(float(np.mean(np.concatenate([res["r0"], res["s"]]) ** 2)))
    assert lev["rms_N"] == pytest.approx(rms, rel=1e-12)
    assert f"{20 * math.log10(rms / math.sqrt(s2)):.1f} dB over the noise" in lev["finding"]
