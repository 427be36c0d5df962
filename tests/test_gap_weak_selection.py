"""Issue 20 §5: behaviours of the gap package (the selection rule on a table of fits, block-mean drift, a step as a
model file and edge cases with a documented answer) that the mutation runs found unpinned (seed 22 and own seeds).

Each test checks a documented behaviour against a hand computation or the documented contract; the expensive
parts (simulation, diagnosis) are replaced by recorders where the test is about what the benchmark hands them.
Units: mm, N, s.
"""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from chainid.model.base import LinearModel


class _Stop(Exception):
    """Raised by a recorder to end a benchmark case once its call was seen."""


# ---------------------------------------------------------------- selection: the step rule on a table of fits

def _world(monkeypatch, table, floor=()):
    """Fits looked up in ``table`` (sorted effect names → (LOTO NRMSE, LOTO SSE per test A, B, C, at_bound,
    n_params)); ``floor``: effect sets whose training residual is at the noise floor."""
    from chainid.gap.core import selection as sel
    from chainid.gap.harmonic.problem import Candidate

    calls = []

    def fit_score(prob, names, start, base_hold):  # noqa: ANN001
        key = tuple(sorted(names))
        calls.append(key)
        loto, sse, bound, k = table[key]
        c = Candidate("+".join(names), {f"{n}.p": 1.0 for n in names}, k, at_bound=list(bound))
        c.nrmse_loto, c.loto_num, c.bic = loto, dict(zip("ABC", sse)), 10.0 * k
        return c

    monkeypatch.setattr(sel, "_fit_score", fit_score)
    monkeypatch.setattr(sel, "train_floor", lambda prob, c: tuple(sorted(c.names)) in floor)
    base = Candidate("baseline", {}, 0)
    base.nrmse_loto, base.loto_num = 1.0, {"A": 100.0, "B": 100.0, "C": 100.0}
    return sel, base, calls


TABLE = {("friction",): (0.5, (25.0, 25.0, 16.0), (), 1),
         ("slack",): (0.95, (90.0, 90.0, 90.0), (), 1),
         ("friction", "slack"): (0.48, (24.0, 24.0, 15.0), (), 2)}


def test_forward_selection_stops_on_an_immaterial_step_by_hand(monkeypatch):
    """Step 1: friction lowers the LOTO NRMSE by 50 % with g_i = ½ln(100/25), ½ln(100/25), ½ln(100/16) (all > 0,
    mean far above 2 SE): kept; slack (5 %) is not material.  Step 2: slack on top lowers it by 4 %: the chain
    stops, and the stop text gives the numbers of the rule."""
    sel, base, calls = _world(monkeypatch, TABLE)
    out = sel.forward_select(None, ["friction", "slack"], base, 1.0)
    assert [c.names for c in out["path"]] == [[], ["friction"]]
    assert sorted(c.name for c in out["singles"]) == ["friction", "slack"]
    g = 0.5 * np.log(np.array([25.0, 25.0, 16.0]) / [24.0, 24.0, 15.0])
    se = float(np.std(g, ddof=1)) / math.sqrt(3)
    assert out["stop"] == (f"no significant improvement: best next effect slack lowers the LOTO NRMSE by 4.0 % (mean "
                           f"log error ratio over tests {g.mean():.3g}, jack-knife SE {se:.2g}; needs > 2 SE and >= "
                           "10 %)")
    st = out["path"][1].step_test
    g1 = 0.5 * np.log(100.0 / np.array([25.0, 25.0, 16.0]))
    assert st["delta_loto"] == pytest.approx(g1.mean(), rel=1e-12)
    assert st["se_jackknife"] == pytest.approx(np.std(g1, ddof=1) / math.sqrt(3), rel=1e-12)
    assert st["relative_gain"] == pytest.approx(0.5, rel=1e-12)
    assert out["confounded"] == [] and out["dropped"] == [] and out["swapped"] == []


def test_forward_selection_stop_reasons(monkeypatch):
    sel, base, _ = _world(monkeypatch, TABLE)
    out = sel.forward_select(None, ["friction", "slack"], base, 1.0, max_effects=1)
    assert out["stop"] == "the chain has the maximum of 1 effects" and len(out["path"]) == 2
    out = sel.forward_select(None, ["friction"], base, 1.0)
    assert out["stop"] == "no library effect left" and len(out["path"]) == 2
    sel, base, _ = _world(monkeypatch, TABLE, floor={("friction",)})
    out = sel.forward_select(None, ["friction", "slack"], base, 1.0)
    assert out["stop"] == "the training residual is at the noise floor" and len(out["path"]) == 2
    pinned = dict(TABLE) | {("friction",): (0.5, (25.0, 25.0, 16.0), ("friction.p",), 1),
                            ("slack",): (0.95, (90.0, 90.0, 90.0), ("slack.p",), 1)}
    sel, base, _ = _world(monkeypatch, pinned)
    out = sel.forward_select(None, ["friction", "slack"], base, 1.0)
    assert out["stop"] == ("the best next effect friction needs parameters at the bounds of their physical range: "
                           "its form does not fit what is left")
    assert len(out["path"]) == 1 and len(out["singles"]) == 2


def test_forward_selection_near_tie_is_confounded_and_look_ahead_takes_the_runner_up(monkeypatch):
    """Hysteresis (2 parameters) within TIE = 5 % of friction (1): friction is chosen, the pair is reported as
    confounded.  The runner-up is within LOOKAHEAD = 30 %; its best extension (hysteresis+slack) must beat the
    choice's best (friction+slack, 0.48) by more than TIE to be taken: 0.47 is not (> 0.95·0.48 = 0.456), 0.40 is."""
    base_table = dict(TABLE) | {("hysteresis",): (0.51, (26.0, 26.0, 17.0), (), 2),
                                ("friction", "hysteresis"): (0.49, (24.5, 24.5, 15.5), (), 3)}
    sel, base, _ = _world(monkeypatch, base_table | {("hysteresis", "slack"): (0.47, (24.0, 24.0, 15.0), (), 3)})
    out = sel.forward_select(None, ["friction", "slack", "hysteresis"], base, 1.0)
    assert out["path"][1].names == ["friction"]
    assert out["confounded"][0] == {"step": 1, "pair": ["friction", "hysteresis"], "loto": [0.5, 0.51]}
    sel, base, _ = _world(monkeypatch, base_table | {("hysteresis", "slack"): (0.40, (10.0, 10.0, 6.0), (), 3)})
    out = sel.forward_select(None, ["friction", "slack", "hysteresis"], base, 1.0, max_effects=2)
    assert [c.names for c in out["path"]][1:] == [["hysteresis"], ["hysteresis", "slack"]]


def test_step_rule_boundaries():
    """Rule 2: mean log ratio > Z = 2 jack-knife SE (strict); rule 3: relative gain >= MIN_GAIN = 10 %."""
    from chainid.gap.harmonic.problem import Candidate
    from chainid.gap.core.selection import loto_jackknife, passes, step_test

    assert passes({"delta_loto": 2.0, "se_jackknife": 1.0, "relative_gain": 0.5}) is False
    assert passes({"delta_loto": 2.001, "se_jackknife": 1.0, "relative_gain": 0.5}) is True
    assert passes({"delta_loto": 3.0, "se_jackknife": 1.0, "relative_gain": 0.1}) is True
    assert passes({"delta_loto": 3.0, "se_jackknife": 1.0, "relative_gain": 0.0999}) is False

    def cand(loto, sse):
        c = Candidate("x", {}, 1)
        c.nrmse_loto, c.loto_num = loto, sse
        return c

    one = loto_jackknife(cand(1.0, {"A": 4.0}), cand(0.5, {"A": 1.0}))
    assert one == (pytest.approx(0.5 * math.log(4.0)), math.inf)  # one test: no spread to judge by
    assert loto_jackknife(cand(1.0, {}), cand(1.0, {})) == (0.0, math.inf)
    st = step_test(cand(0.0, {"A": 1.0, "B": 1.0}), cand(0.0, {"A": 1.0, "B": 1.0}))
    assert st["relative_gain"] == 0.0 and st["z"] == math.inf  # no error before: no gain; se 0: z infinite
    st = step_test(cand(2.0, {"A": 4.0, "B": 9.0}), cand(1.5, {"A": 1.0, "B": 1.0}))
    g = [0.5 * math.log(4.0), 0.5 * math.log(9.0)]
    se = abs(g[1] - g[0]) / math.sqrt(2) / math.sqrt(2)  # sd (ddof 1) of two values = |a − b|/√2
    assert st["z"] == pytest.approx(sum(g) / 2 / se, rel=1e-12) and st["relative_gain"] == pytest.approx(0.25)


def test_no_look_ahead_beyond_the_maximum_chain(monkeypatch):
    """At the last allowed step (two effects chosen, at most three) the look-ahead would fit four effects: it
    is not run (only effect sets of up to ``max_effects`` are ever fitted), and the near-tie is reported."""
    table = dict(TABLE) | {
        ("friction", "slack"): (0.3, (9.0, 9.0, 6.0), (), 2),
        ("hysteresis",): (0.9, (80.0, 80.0, 81.0), (), 2), ("backlash",): (0.92, (85.0, 85.0, 84.0), (), 1),
        ("friction", "hysteresis"): (0.45, (20.0, 20.0, 14.0), (), 3),
        ("backlash", "friction"): (0.46, (21.0, 21.0, 14.0), (), 2),
        ("friction", "hysteresis", "slack"): (0.2, (4.0, 4.0, 3.0), (), 3),
        ("backlash", "friction", "slack"): (0.21, (4.2, 4.2, 3.1), (), 4),
        ("hysteresis", "slack"): (0.6, (30.0, 30.0, 20.0), (), 3)}
    sel, base, calls = _world(monkeypatch, table)
    out = sel.forward_select(None, ["friction", "slack", "hysteresis", "backlash"], base, 1.0, max_effects=3)
    assert [c.names for c in out["path"]][1:] == [["friction"], ["friction", "slack"],
                                                  ["friction", "slack", "hysteresis"]]
    assert max(len(k) for k in calls) == 3
    assert out["stop"] == "the chain has the maximum of 3 effects"
    assert {"step": 3, "pair": ["hysteresis", "backlash"], "loto": [0.2, 0.21]} in out["confounded"]
    assert out["dropped"] == []


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


def test_exchange_swaps_within_a_family_and_backward_pass_drops_a_redundant_effect(monkeypatch):
    """Exchange: after friction then slack, hysteresis (friction's family) refitted with slack is better by more
    than TIE (0.2 < 0.95·0.3): swapped, the chain rebuilt greedily (hysteresis first: 0.9 < 0.95 alone) — unless a
    hysteresis parameter sits at a bound (rule 4).  Backward: slack alone (pinned at step 1, so friction came
    first) is within 3 % of friction+slack: dropping friction is not significantly worse, so it is dropped."""
    table = dict(TABLE) | {("friction", "slack"): (0.3, (9.0, 9.0, 6.0), (), 2),
                           ("hysteresis",): (0.9, (80.0, 80.0, 81.0), (), 2),
                           ("friction", "hysteresis"): (0.45, (20.0, 20.0, 14.0), (), 3),
                           ("hysteresis", "slack"): (0.2, (4.0, 4.0, 3.0), (), 3)}
    sel, base, _ = _world(monkeypatch, table)
    out = sel.forward_select(None, ["friction", "slack", "hysteresis"], base, 1.0, max_effects=2)
    assert out["swapped"] == ["friction -> hysteresis"]
    assert [c.names for c in out["path"]][1:] == [["hysteresis"], ["hysteresis", "slack"]]
    assert out["dropped"] == []
    pinned = table | {("hysteresis", "slack"): (0.2, (4.0, 4.0, 3.0), ("hysteresis.p",), 3)}
    sel, base, _ = _world(monkeypatch, pinned)
    out = sel.forward_select(None, ["friction", "slack", "hysteresis"], base, 1.0, max_effects=2)
    assert out["swapped"] == [] and out["path"][-1].names == ["friction", "slack"]
    redundant = dict(TABLE) | {("slack",): (0.31, (9.5, 9.5, 6.2), ("slack.p",), 1),
                               ("friction", "slack"): (0.3, (9.0, 9.0, 6.0), (), 2)}
    sel, base, _ = _world(monkeypatch, redundant)
    out = sel.forward_select(None, ["friction", "slack"], base, 1.0)
    assert out["dropped"] == ["friction"] and [c.names for c in out["path"]] == [[], ["slack"]]


# ---------------------------------------------------------------- where_time.drift: block-mean trend by hand

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


def test_spectrum_outside_the_band_by_hand():
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


# ---------------------------------------------------------------- modelio: a step as a model file, provenance

def test_model_of_step_carries_effects_delay_law_and_training_ce():
    """Effects other than sensor_delay/damping_law become force terms with their own parameters; the delay is
    sensor_delay.tau; the law's per-test c_e only for training tests; k_e of a linear baseline is its k (a
    chain's: None, from the chain at x0)."""
    from chainid.gap.modelio import model_of_step, step_fields
    from chainid.model.base import ChainModel

    lin = LinearModel(100.0, 0.5)
    prob = SimpleNamespace(train=[SimpleNamespace(test="1"), SimpleNamespace(test="2")], is_chain=False, model=lin,
                           model_for=lambda p: LinearModel(p.get("spring.k", 100.0), p.get("spring.x_ref", 0.5)))
    cand = SimpleNamespace(names=["friction", "sensor_delay"], law="viscous", law_params=[0.25],
                           params={"spring.k": 90.0, "spring.x_ref": 0.4, "friction.F_c": 30.0, "sensor_delay.tau": 0.01},
                           _ev={"c_e": {"1": 0.2, "2": 0.3, "H": 9.0}})
    m = model_of_step(prob, cand, {"note": "x"})
    assert [n for n, _ in m.effects] == ["friction"] and m.effects[0][1]["F_c"] == 30.0
    assert m.delay_s == 0.01 and (m.base.k, m.base.x_ref) == (90.0, 0.4)
    assert (m.damping.law, m.damping.coefficients, m.damping.k_e) == ("viscous", [0.25], 100.0)
    assert m.damping.per_test == {"1": 0.2, "2": 0.3} and m.info == {"note": "x"}
    no_delay = SimpleNamespace(names=["friction"], law="viscous", law_params=[0.25],
                               params={"friction.F_c": 30.0, "sensor_delay.tau": 0.5})
    assert model_of_step(prob, no_delay).delay_s == 0.0  # a stale key of another step is not this step's delay
    chain = SimpleNamespace(train=[], is_chain=True, model=ChainModel(), model_for=lambda p: ChainModel())
    assert model_of_step(chain, no_delay).damping.k_e is None
    f = step_fields(prob, cand)
    assert f["law_params"] == [0.25] and f["delay_s"] == 0.01 and f["mass_kg"] == 0.0


def test_provenance_of_a_model_file(tmp_path):
    import datetime as dt
    import hashlib

    from chainid import __version__
    from chainid.gap.modelio import provenance

    data = tmp_path / "d.csv"
    blob = bytes(range(256)) * 5000  # 1.28 MB: more than one 1 MiB chunk
    data.write_bytes(blob)
    p = provenance(data, "chainid diagnose d.csv")
    assert p["data_sha256"] == hashlib.sha256(blob).hexdigest() and p["data_file"] == str(data)
    assert p["command"] == "chainid diagnose d.csv" and p["chainid_version"] == __version__
    when = dt.datetime.fromisoformat(p["date"])
    assert when.utcoffset() == dt.timedelta(0) and abs(dt.datetime.now(dt.timezone.utc) - when).total_seconds() < 60
    assert provenance(None, "c")["data_file"] is None and provenance(None, "c")["data_sha256"] is None
    assert provenance(tmp_path / "gone.csv", "c")["data_sha256"] is None


# ---------------------------------------------------------------- edge cases with a documented answer

def test_noise_edge_cases():
    """Fewer than 8 spectral lines or a displacement with no variation: the band is the Nyquist frequency and
    the record is not called broadband."""
    from chainid.gap.core import noise

    t = np.arange(12) / 100.0
    assert noise.excitation_band(t, np.sin(t)) == pytest.approx(50.0, rel=1e-9)  # 7 lines
    assert noise.is_broadband(t, np.sin(t)) is False
    t = np.arange(200) / 100.0
    assert noise.excitation_band(t, np.zeros(200)) == pytest.approx(50.0, rel=1e-9)  # no variation at all
    assert noise.force_quantum(np.array([1.0, 1.0, 2.0, 2.0, 3.0, 3.0])) == 1.0
    assert noise.force_quantum(np.array([1.0, 2.0, 3.0, 4.0])) == 0.0  # as many values as samples: not quantised


def test_problem_holdout_errors():
    from chainid.gap.harmonic.problem import Problem

    data = [SimpleNamespace(test=s) for s in ("a", "b", "c", "d")]
    with pytest.raises(ValueError, match=r"--holdout: test id\(s\) \['z'\] not in the usable data; usable ids: a, b, "
                                         "c, d"):
        Problem(data, None, ["a", "z"])
    with pytest.raises(ValueError, match="--holdout: no test held out; give at least one test id"):
        Problem(data, None, [])
    with pytest.raises(ValueError, match=r"--holdout leaves 2 usable training test\(s\); at least 3 are needed"):
        Problem(data, None, ["a", "b"])


def test_every_held_out_test_excluded_is_an_error_with_the_reasons(capsys):
    from chainid.gap import diagnose
    from chainid.gap.benchmark.grid import grid3x3_plan
    from chainid.model.base import ChainModel
    from chainid.records.record import Record
    from chainid.records.simulate import simulate

    recs = simulate(grid3x3_plan(prefix=""), ChainModel(), 50.0, n_cycles=6, samples_per_cycle=64, noise_F=5.0,
                    seed=1)
    t = np.arange(20) / 100.0  # 20 samples: no steady cycle, too short for the time-domain route
    recs[2] = Record("3", t, 2.0 + 0.1 * np.sin(8 * t), 1000.0 + 10 * np.sin(8 * t))
    with pytest.raises(ValueError, match=r"--holdout: every held-out test was excluded \(3\); reasons: "):
        diagnose(recs, ["3"], ChainModel(), quiet=False, uncertainty=False, max_combo=1)
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith("chainid diagnose: test 3 excluded: ")
    with pytest.raises(ValueError, match=r"test '3' cannot be used \(--strict\): "):
        diagnose(recs, ["7"], ChainModel(), quiet=True, uncertainty=False, max_combo=1, strict=True)
