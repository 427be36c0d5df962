"""Records prepared for the time-domain route (chainid.gap.timedomain.data): input checks, blocks, reversals and
travel, the undamped force of each effect, by hand.  Units s, mm, N."""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from chainid.model.base import LinearModel


def test_time_domain_record_checks_and_split_errors():
    """The time-domain route's input checks name the test and the valid range: >= 64 samples, finite values,
    t strictly increasing, blocks 1 … n // 16; a split needs something held out and >= 3 training units."""
    from chainid.gap.timedomain.data import MIN_SAMPLES, prepare_time
    from chainid.gap.timedomain.problem import TimeProblem
    from chainid.records.record import Record

    n = 160
    t = np.arange(n) / 100.0
    x = 2.0 + 0.1 * np.sin(2 * np.pi * 1.3 * t) + 0.05 * np.sin(2 * np.pi * 3.1 * t)
    F = 1000.0 * x

    def rec(name="r", tt=t, xx=x, FF=F):
        return Record(name, tt, xx, FF)

    with pytest.raises(ValueError, match=rf"test 'r': 63 samples; the time-domain route needs >= {MIN_SAMPLES}"):
        prepare_time(rec(tt=t[:63], xx=x[:63], FF=F[:63]), 1)
    bad = F.copy()
    bad[5] = np.nan
    with pytest.raises(ValueError, match="test 'r': non-finite t, x or F"):
        prepare_time(SimpleNamespace(test="r", t=t, x=x, F=bad), 1)  # (a Record refuses NaN itself)
    tt = t.copy()
    tt[10] = tt[9]
    with pytest.raises(ValueError, match="test 'r': t must be strictly increasing"):
        prepare_time(SimpleNamespace(test="r", t=tt, x=x, F=F), 1)
    for nb in (0, 11):
        with pytest.raises(ValueError, match=rf"blocks per record = {nb} is out of range for test 'r'; valid range "
                                             r"1 to 10"):
            prepare_time(rec(), nb)
    assert prepare_time(rec(), 10).n_blocks == 10
    data = [prepare_time(rec(f"r{i}"), 1) for i in range(3)]
    with pytest.raises(ValueError, match="nothing is held out: give --holdout IDS"):
        TimeProblem(data, None, [], 0)
    # a mixed set runs whole on the time route (harmonic tests are records there): the units are time blocks
    with pytest.raises(ValueError, match=r"the split leaves 2 training unit\(s\) \(time blocks\); at least 3 are "
                                         "needed"):
        TimeProblem(data, None, ["r0"], 0)


def test_reversals_travel_and_blocks_by_hand():
    from chainid.gap.timedomain.data import reversals, split_blocks, travel_since_reversal

    xd = np.array([1.0, 2.0, 0.0, -1.0, -2.0, 0.0, 0.0, 3.0, 1.0])
    assert list(reversals(xd)) == [3, 7]  # the sample after each sign change (zeros skipped)
    assert reversals(np.array([0.0, 1.0, 0.0])).size == 0
    x = np.array([0.0, 1.0, 2.0, 1.5, 1.0, 0.5, 0.5, 1.0, 3.0])
    np.testing.assert_allclose(travel_since_reversal(x, xd), [0, 1, 2, 0, 0.5, 1.0, 1.0, 0, 2.0])
    a = SimpleNamespace(test="a", n_blocks=3)
    b = SimpleNamespace(test="b", n_blocks=2)
    tr, ho = split_blocks([a, b], ["b"], 0)
    assert [(d.test, k) for d, k in tr] == [("a", 0), ("a", 1), ("a", 2)]
    assert [(d.test, k) for d, k in ho] == [("b", 0), ("b", 1)]
    tr, ho = split_blocks([a, b], [], 2)
    assert [(d.test, k) for d, k in tr] == [("a", 0), ("a", 1), ("b", 0)]
    assert [(d.test, k) for d, k in ho] == [("a", 2), ("b", 1)]


def test_undamped_force_of_each_effect_on_a_linear_spring_by_hand():
    """The library's composition (chainid.model.effects.undamped_force, the one place effects make one force) on a
    linear spring: F_n = m·ẍ·1e-3 + k(x − x_ref) plus: friction (F_c + μ|F_k|)·sgn-with-stick; hysteresis the Dahl
    operator; backlash k(play(x, b/2) − x_ref) instead of k(x − x_ref); slack a shifted spring k(x − s − x_ref)
    (a linear spring has no kernel to modify: modify_model refuses it); sensor_delay and damping_law nothing (the
    caller evaluates the inputs at t − τ and the damping)."""
    from chainid.model.effects import dahl_operator, modify_model, play_operator, stick_slip, undamped_force

    t = np.linspace(0.0, 2.0, 401)
    x = 1.0 + 0.3 * np.sin(2 * np.pi * t)
    xd = 0.6 * np.pi * np.cos(2 * np.pi * t)
    xdd = -1.2 * np.pi ** 2 * np.sin(2 * np.pi * t)
    k, xr, m = 100.0, 0.2, 50.0
    spring = LinearModel(k, xr, mass=m)
    Fk = k * (x - xr)
    base = m * xdd * 1e-3 + Fk

    def F(*effects):
        return undamped_force(effects, spring, t, x, xd, xdd, 2 * np.pi, 0.3, 1.0, periodic=False)

    np.testing.assert_allclose(F(), base, rtol=1e-12)
    np.testing.assert_allclose(F(("friction", {"F_c": 5.0, "mu": 0.01})),
                               base + (5.0 + 0.01 * np.abs(Fk)) * stick_slip(x, xd, 0.0, periodic=False), rtol=1e-12)
    np.testing.assert_allclose(F(("hysteresis", {"F_h": 7.0, "x_h": 0.05})),
                               base + dahl_operator(x, 7.0, 0.05, periodic=False), rtol=1e-12)
    np.testing.assert_allclose(F(("backlash", {"b": 0.1})),
                               m * xdd * 1e-3 + k * (play_operator(x, 0.05, periodic=False) - xr), rtol=1e-12)
    np.testing.assert_allclose(F(("slack", {"s": 0.04})), m * xdd * 1e-3 + k * (x - 0.04 - xr), rtol=1e-12)
    with pytest.raises(ValueError, match="effect 'slack' needs a chain model"):  # no kernel to modify
        modify_model("slack", {"s": 0.04}, spring)
    np.testing.assert_allclose(F(("sensor_delay", {"tau": 0.01}), ("damping_law", {"eta": 0.1})), base, rtol=1e-12)


def test_time_route_design_lags_the_motion_and_runs_memory_over_the_view():
    """The time route's design (chainid.gap.timedomain.design.build) on a linear device with a given mass:
    sensor_delay evaluates the motion at t − τ by linear interpolation (columns x(t − τ), ẋ(t − τ), fixed
    m·ẍ(t − τ)·1e-3, each minus its mean: per-record offsets), and the samples whose t − τ is before the record
    carry no residual (their columns 0, the target the fixed force); a view (idx) runs the memory operators over
    its own samples in order (Dahl column = dahl_operator(x[idx], 1, x_h))."""
    from chainid.gap.timedomain.design import Base, build
    from chainid.model.effects import dahl_operator

    t = np.linspace(0.0, 2.0, 401)  # dt = 5 ms
    x = 1.0 + 0.3 * np.sin(2 * np.pi * t)
    xd = 0.6 * np.pi * np.cos(2 * np.pi * t)
    xdd = -1.2 * np.pi ** 2 * np.sin(2 * np.pi * t)
    F = 100.0 * x + 3.0 * xd
    d = SimpleNamespace(test="r", t=t, x=x, xd=xd, xdd=xdd, F=F, omega_c=2 * np.pi, A=0.3, covariates={})
    m, tau = 50.0, 0.0125
    f, Phi, y = build(Base("linear", mass_kg=m), ["sensor_delay"], {"sensor_delay.tau": tau}, d)
    xl, xdl, xddl = (np.interp(t - tau, t, v) for v in (x, xd, xdd))
    f_hand = m * xddl * 1e-3 - np.mean(m * xddl * 1e-3)
    cols = np.column_stack([xl - xl.mean(), xdl - xdl.mean()])  # spring.k, damping.c
    out = t - tau < 0.0
    assert list(np.flatnonzero(out)) == [0, 1, 2]  # 0, 5, 10 ms < 12.5 ms
    cols[out] = 0.0
    np.testing.assert_allclose(f, f_hand, rtol=0, atol=1e-12)
    np.testing.assert_allclose(Phi, cols, rtol=0, atol=1e-12)
    np.testing.assert_allclose(y, np.where(out, f_hand, F - F.mean()), rtol=0, atol=1e-12)
    idx = np.arange(3, 401, 7)
    _, Phi, _ = build(Base("linear", mass_kg=m), ["hysteresis"], {"hysteresis.x_h": 0.05}, d, idx)
    dahl = dahl_operator(x[idx], 1.0, 0.05, periodic=False)
    np.testing.assert_allclose(Phi[:, 2], dahl - dahl.mean(), rtol=0, atol=1e-12)


def test_time_data_blocks_and_properties():
    """Blocks contiguous in time, sample i in block floor(i·K/n); A half the range, x0 the mean, ω the spectral
    peak of x; the fit subset every q-th sample with q = min(fs/(40·band), ceil(n/4000)) (at least 1)."""
    from chainid.gap.timedomain.data import prepare_time
    from chainid.records.record import Record

    n, fs = 1000, 200.0
    t = np.arange(n) / fs
    x = 2.0 + 0.5 * np.sin(2 * np.pi * 2.0 * t)
    d = prepare_time(Record("r", t, x, 100.0 * x), 3)
    assert list(d.block) == [min(i * 3 // n, 2) for i in range(n)]
    assert d.A == pytest.approx(0.5 * np.ptp(d.x)) and d.x0 == pytest.approx(float(np.mean(d.x)))
    assert d.omega == pytest.approx(2 * np.pi * 2.0, rel=0.03)
    q = max(1, min(int(fs / (40 * d.f_band)), int(math.ceil(n / 4000))))
    assert list(d.fit_idx) == list(range(0, n, q))
    assert d.window == f"time domain, {n} samples, band {d.f_band:.3g} Hz, 3 blocks"


def test_low_edge_of_a_motion_without_variance_above_its_floor_is_the_first_bin_without_a_warning():
    # a displacement that never moves: no variance at all, so no share of it lies anywhere; the band's lower edge
    # is the record's lowest resolvable frequency fs/n (a 0/0 share would be a NaN and numpy's warning)
    import warnings

    from chainid.gap.timedomain.data import low_edge

    t = np.arange(1000) / 100.0
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert low_edge(t, np.zeros(t.size)) == pytest.approx(100.0 / 1000, rel=1e-9)


def test_lag_range_is_half_the_longest_useful_period_or_a_quarter_of_the_shortest_record():
    # the delay's scale (the largest lag searched): min(0.5 / lowest band edge, 0.25 · shortest duration).  Random
    # motion over 0.2–4 Hz, 20 s records: the band edge binds (0.5/f_low ≈ 2.5 s < 5 s); records of 4 s: the
    # duration binds (1 s)
    import recovery_cases as rc
    from chainid.gap.timedomain.data import low_edge, prepare_time
    from chainid.gap.timedomain.problem import TimeProblem

    for n, binds in ((4000, "band"), (800, "duration")):
        data = [prepare_time(r, 4) for r in rc.linear_random(n_rec=3, n=n)]
        f_low = min(low_edge(d.t, d.x) for d in data)
        dur = min(float(d.t[-1] - d.t[0]) for d in data)
        want = min(0.5 / f_low, 0.25 * dur)
        assert (want == 0.5 / f_low) == (binds == "band")
        assert TimeProblem(data, None, ["r2"], 0).scales["tau"] == pytest.approx(want, rel=1e-12)


@pytest.mark.parametrize("fraction, edge", [(None, 0.9), (0.5, 1.0), (0.9, 1.1), (0.95, 5.0)])
def test_low_edge_is_where_the_stated_share_of_the_variance_is_reached(fraction, edge):
    """x = 2 + cos(2π·1 Hz·t) + 0.3·cos(2π·5 Hz·t), 10 s at 100 Hz (bins every 0.1 Hz, both lines on the grid).  The
    Hann window spreads each line over its bin and the two neighbours with powers 1/4, 1, 1/4 (window DFT
    0.5, −0.25), and the lines hold 1/1.09 and 0.09/1.09 of the variance: cumulative shares 0.153 (0.9 Hz),
    0.765 (1.0), 0.917 (1.1), 0.931 (4.9), 0.986 (5.0).  So 1 % (the default) is reached at 0.9 Hz, 50 % at 1.0,
    90 % at 1.1, 95 % at 5.0 (within rounding of the bin frequencies)."""
    from chainid.gap.timedomain.data import low_edge

    t = np.arange(1000) / 100.0
    x = 2.0 + np.cos(2 * np.pi * t) + 0.3 * np.cos(2 * np.pi * 5.0 * t)
    got = low_edge(t, x) if fraction is None else low_edge(t, x, fraction)
    assert got == pytest.approx(edge, abs=1e-9)


def test_low_edge_of_a_record_with_fewer_than_eight_bins_is_its_first_bin():
    """A cosine on bin 3 of the record's spectrum.  12 samples at 100 Hz have 7 bins: too few to read, the edge is
    the first bin, 100/12 Hz.  14 samples have 8 bins: read; the Hann window spreads the line over bins 2–4 (powers
    1/4, 1, 1/4), so bin 2 holds about 1/6 of the variance, past 1 %: the edge is 2·100/14 Hz."""
    from chainid.gap.timedomain.data import low_edge

    for n, want in ((12, 100.0 / 12), (14, 200.0 / 14)):
        t = np.arange(n) / 100.0
        assert low_edge(t, np.cos(2 * np.pi * (3 * 100.0 / n) * t)) == pytest.approx(want, rel=1e-9), n


@pytest.mark.parametrize("n, edge, want", [(200, 50, (50, 150)), (100, 50, (18, 82)), (64, 50, (0, 64)),
                                           (60, 5, (0, 60))])
def test_the_compared_interior_leaves_the_edges_but_keeps_the_fewest_samples(n, edge, want):
    """All but the kinematics' edge samples at each end, but at most (n − 64)//2 of them: n = 200, edge 50:
    50 … 149; n = 100: only 18 each side (64 kept); n = 64 or fewer: nothing left out."""
    from chainid.gap.timedomain.data import MIN_SAMPLES, interior

    assert MIN_SAMPLES == 64
    kin = SimpleNamespace(edge_samples=lambda fs: edge)
    assert interior(kin, 100.0, n) == want


def test_a_force_without_noise_gets_the_floor_of_a_millionth_of_its_spread():
    """F a straight line in time: its second difference is 0 (force noise 0) and its detrended spectrum is 0
    (spectral floor 0), so σ is the floor 1e-6·std(F) + 1e-9 N of the whole record's F; a constant force: 1e-9 N."""
    from chainid.gap.timedomain.data import prepare_time
    from chainid.records.record import Record

    t = np.arange(400) / 100.0
    x = 0.5 * np.sin(2 * np.pi * 1.5 * t)
    F = 20.0 + 1000.0 * t
    assert prepare_time(Record("r", t, x, F), 1).sigma == pytest.approx(1e-6 * float(np.std(F)) + 1e-9, rel=1e-9)
    assert prepare_time(Record("r", t, x, np.full(t.size, 3.0)), 1).sigma == pytest.approx(1e-9, rel=1e-9)


def test_fit_windows_take_one_band_centre_period_of_lead_in_before_each_window_but_the_first():
    """4000 samples at 100 Hz, all training, half of them kept (2000): windows of min(4 periods of f_low = 0.5 Hz =
    800, 2000 // 4 blocks = 500) = 500 samples, 4 of them, starting at linspace(0, 3500, 4) = 0, 1166, 2333, 3500;
    each but the first after a lead-in of one period of the band centre (2 Hz: 50 samples), weighed 0.  So
    500 + 3 × 550 = 2150 samples, 150 of them lead."""
    from chainid.gap.timedomain.data import windows

    d = SimpleNamespace(fit_idx=np.arange(4000), t=np.arange(4000) / 100.0, f_low=0.5, n_blocks=4,
                        omega_c=2 * math.pi * 2.0)
    idx, lead = windows(d, 0.5, np.ones(4000, bool))
    want = np.concatenate([np.arange(0, 500), np.arange(1116, 1666), np.arange(2283, 2833), np.arange(3450, 4000)])
    np.testing.assert_array_equal(idx, want)
    assert int(lead.sum()) == 150 and not lead[:500].any() and lead[500:550].all() and not lead[550:1050].any()
