"""Issue 20 §5: behaviours of the gap package (fitgrid's start points, timedomain helpers and localise's findings)
that the mutation runs found unpinned (seed 22 and own seeds).

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


# ---------------------------------------------------------------- fitgrid: the documented start points

def test_fit_start_points_follow_their_documentation():
    """``starts``: the default start first; a delay gets a grid over its whole range (± half the shortest period)
    at 1/40 of a period, i.e. the 40 midpoints (i + ½)/40; a scale or delay also starts around its neutral value
    (below and above it); a parameter whose range straddles 0 starts close to 0 on both sides; the linear spring
    of a --model linear baseline may soften a lot: every start again with k × 0.1 and × 0.01; parameters of
    effects already fitted (fixed) keep their value in every start; everything inside the unit box."""
    from chainid.gap.core.fitgrid import DELAY_GRID, starts

    ug = np.array([0.5])
    out = starts(["sensor_delay.tau"], ["sensor_delay"], ug, np.zeros(1, bool), np.array([-0.1]), np.array([0.1]))
    u = sorted({round(float(v[0]), 12) for v in out})
    assert np.allclose(out[0], ug)
    mids = [(i + 0.5) / DELAY_GRID for i in range(DELAY_GRID)]
    assert DELAY_GRID == 40 and all(any(abs(m - v) < 1e-12 for v in u) for m in mids)
    assert any(0.5 < v < 0.5 + 1e-2 for v in u) and any(0.5 - 1e-2 < v < 0.5 for v in u)  # close to τ = 0, both sides
    sc = starts(["stiffness_level.scale"], ["stiffness_level"], np.array([0.4]), np.zeros(1, bool), np.array([0.5]),
                np.array([1.75]))
    vals = [float(v[0]) for v in sc]
    assert any(0.2 <= v < 0.4 for v in vals) and any(0.4 < v <= 1.0 for v in vals)  # around the neutral 0.4
    assert min(vals) == 0.0 and all(0.0 <= v <= 1.0 for v in vals)
    # a linear spring and one fixed parameter of an earlier effect (slack.s = 0.3 of its range)
    keys = ["spring.k", "spring.x_ref", "slack.s", "friction.F_c", "friction.mu", "friction.x_s"]
    ug = np.array([0.4, 0.5, 0.3, 0.01, 0.0, 0.0])
    fixed = np.array([False, False, True, False, False, False])
    lo, hi = np.zeros(6), np.ones(6)
    out = starts(keys, ["slack", "friction"], ug, fixed, lo, hi)
    assert all(v[2] == 0.3 and v[1] == 0.5 for v in out)
    assert all(np.all((v >= 0) & (v <= 1)) for v in out)
    n = len(out) // 3  # the starts, then each with k × 0.1, then with k × 0.01
    assert len(out) == 3 * n
    for i in range(n):
        base = out[i]
        for j, f in ((1, 0.1), (2, 0.01)):
            np.testing.assert_allclose(out[j * n + i], np.concatenate([[base[0] * f], base[1:]]), rtol=1e-12)
    assert len({tuple(np.round(v[3:], 9)) for v in out}) > 10  # a grid over the new effect's parameters


def test_time_domain_record_checks_and_split_errors():
    """The time-domain route's input checks name the test and the valid range: >= 64 samples, finite values,
    t strictly increasing, blocks 1 … n // 16; a split needs something held out and >= 3 training units."""
    from chainid.gap.timedomain.data import MIN_SAMPLES, prepare_time
    from chainid.gap.timedomain.problem import AnyProblem
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
        AnyProblem(data, LinearModel(1000.0, 0.0), [], 0)
    with pytest.raises(ValueError, match=r"the split leaves 2 training unit\(s\) \(time blocks \+ harmonic tests\); "
                                         "at least 3 are needed"):
        AnyProblem(data, LinearModel(1000.0, 0.0), ["r0"], 0)


def test_library_drops_aliases_and_restricts_to_the_given_effects():
    """machine_compliance is the same physics as stiffness_level for the diagnosis (ALIASES): considered only
    when stiffness_level is not; ``effects`` restricts the library."""
    from chainid.gap.core.selection import library

    prob = SimpleNamespace(applicable=lambda: ["friction", "machine_compliance", "stiffness_level", "slack"])
    assert library(prob, None) == ["friction", "stiffness_level", "slack"]
    assert library(prob, ["machine_compliance", "slack"]) == ["machine_compliance", "slack"]
    assert library(prob, ["backlash"]) == []


def test_baseline_candidate_of_a_chain_and_of_a_linear_spring():
    """The chain model as given (no parameters) or the linear spring re-fitted; scored with shrinkage 0."""
    from chainid.gap.harmonic.problem import Candidate
    from chainid.gap.core.selection import baseline_candidate

    scored = []

    def score(c, names, base_hold):  # noqa: ANN001
        scored.append((c.name, list(names), base_hold))
        c.shrinkage = 0.3
        return c

    chain = SimpleNamespace(is_chain=True, score=score, fit=lambda names: pytest.fail("a chain is not re-fitted"))
    c = baseline_candidate(chain)
    assert (c.name, c.params, c.shrinkage) == ("baseline", {}, 0.0) and scored == [("baseline", [], 1.0)]
    lin = SimpleNamespace(is_chain=False, score=score,
                          fit=lambda names: Candidate("", {"spring.k": 5.0, "spring.x_ref": 0.1}, 2))
    c = baseline_candidate(lin)
    assert (c.name, c.params["spring.k"], c.shrinkage) == ("baseline", 5.0, 0.0)


def test_bin_noise_is_the_pooled_scatter_after_a_per_bin_linear_fit():
    """σ = sqrt(Σ RSS_b / Σ(n_b − 3)) with RSS_b of a least-squares fit of F on (1, ψ, t) within each bin
    (computed here by numpy.linalg.lstsq per bin; the code uses running moments); bins with fewer than 5
    samples do not count; with none left, σ is the plain standard deviation of F."""
    from chainid.gap.harmonic.prepare import _bin_noise

    rng = np.random.default_rng(5)
    B, n = 4, 200
    t = np.sort(rng.uniform(0, 10, n))
    psi = rng.uniform(0, 2 * np.pi, n)
    bins = np.minimum((psi / (2 * np.pi) * B).astype(int), B - 1)
    F = 3.0 * psi - 0.5 * t + rng.normal(0, 2.0, n)
    keep = np.ones(n, bool)
    keep[np.flatnonzero(bins == 3)[4:]] = False  # bin 3 keeps 4 samples: left out of the pool
    t, psi, bins, F = t[keep], psi[keep], bins[keep], F[keep]
    rss = dof = 0.0
    for b in range(B):
        m = bins == b
        if m.sum() < 5:
            continue
        X = np.column_stack([np.ones(m.sum()), psi[m], t[m]])
        r = F[m] - X @ np.linalg.lstsq(X, F[m], rcond=None)[0]
        rss += float(r @ r)
        dof += m.sum() - 3
    assert _bin_noise(t, F, psi, bins, B) == pytest.approx(math.sqrt(rss / dof), rel=1e-9)
    few = np.arange(8) % 4  # 2 samples per bin
    y = np.arange(8.0) ** 2
    assert _bin_noise(np.arange(8.0), y, np.linspace(0, 6, 8), few, 4) == pytest.approx(float(np.std(y)), rel=1e-12)


def test_ce_projection_and_candidate_contract():
    """c_e of a test = the count-weighted projection of F̄ − F_n on v (Eq. 27 on the cycle-mean loop): with
    F̄ − F_n = 2.5·v exactly it is 2.5; Candidate names split on '+', the baseline has none; its JSON turns
    non-finite numbers into null."""
    from chainid.gap.harmonic.problem import Candidate, _ce

    v = np.array([1.0, -2.0, 0.5, 3.0])
    d = SimpleNamespace(counts=np.array([4.0, 1.0, 2.0, 3.0]), Fbar=10.0 + 2.5 * v)
    assert _ce(d, np.full(4, 10.0), v) == pytest.approx(2.5, rel=1e-12)
    w = d.counts
    Fn = np.array([9.0, 11.0, 10.0, 10.5])
    assert _ce(d, Fn, v) == pytest.approx(float(np.sum(w * (d.Fbar - Fn) * v) / np.sum(w * v * v)), rel=1e-12)
    assert Candidate("baseline", {}, 0).names == [] and Candidate("", {}, 0).names == []
    c = Candidate("friction+slack", {"friction.F_c": np.float64(3.0)}, 2, nrmse_holdout=float("nan"),
                  param_sd={"friction.F_c": float("inf")}, at_bound=("slack.s",))
    assert c.names == ["friction", "slack"]
    dct = c.to_dict()
    assert dct["effect"] == "friction+slack" and dct["params"] == {"friction.F_c": 3.0}
    assert dct["params_sd"] == {"friction.F_c": None} and dct["nrmse_holdout"] is None
    assert dct["at_bound"] == ["slack.s"] and dct["n_params"] == 2 and dct["damping_law"] == "polynomial"


def test_laws_for_and_a_given_baseline_law():
    """A candidate is scored with the baseline's law, and viscous too once it has an effect; the damping_law
    effect tries the other forms that n_train − 1 coefficients allow.  A given law is refused when unknown or
    when it has more coefficients than n_train − 1 (the messages name the value and the valid choices)."""
    from chainid.gap.harmonic.law_choice import ALT_LAWS
    from chainid.gap.harmonic.problem import Problem

    p = SimpleNamespace(train=[0] * 4, law="coulomb")
    assert Problem.laws_for(p, []) == ["coulomb"] and Problem.laws_for(p, ["friction"]) == ["coulomb", "viscous"]
    assert Problem.laws_for(SimpleNamespace(train=[0] * 4, law="viscous"), ["friction"]) == ["viscous"]
    assert Problem.laws_for(p, ["damping_law"]) == [k for k in ALT_LAWS if k != "coulomb"]  # <= 3 coefficients
    p2 = SimpleNamespace(train=[0] * 2, law="viscous")
    assert Problem.laws_for(p2, ["damping_law"]) == ["coulomb", "hysteretic"]  # 1 coefficient <= 2 − 1
    assert Problem.laws_for(SimpleNamespace(train=[0], law="viscous"), ["damping_law"]) == ["viscous"]
    fake = SimpleNamespace(train=[0] * 4)
    assert Problem._baseline_law(fake, "viscous+coulomb") == ("viscous+coulomb", "given")
    with pytest.raises(ValueError, match=r"--damping-law = 'cubic' is unknown; valid: auto, polynomial, viscous, "
                                         r"coulomb, viscous\+coulomb, hysteretic"):
        Problem._baseline_law(fake, "cubic")
    with pytest.raises(ValueError, match=r"--damping-law polynomial has 5 coefficients; with 4 training tests at most "
                                         "3 can be scored leave-one-out"):
        Problem._baseline_law(fake, "polynomial")
    assert Problem._baseline_law(SimpleNamespace(train=[0] * 6), "polynomial") == ("polynomial", "given")


def test_run_benchmark_checks_its_output_before_the_work_and_writes_the_summary(tmp_path, monkeypatch, capsys):
    """An existing --json target is refused before any case runs (files are sacred); with overwrite the summary
    is written (strict JSON) and printed; the rows are the run's, one per case of the grid."""
    import json

    import chainid.infra.parallel
    from chainid.gap.benchmark import grid as bm

    ran = []

    def run_cases(fn, cases, **kw):  # noqa: ANN001
        ran.append(len(cases))
        return [c | {"verdict": "none", "snr": 0.0, "shrinkage": None, "seconds": 1.0} for c in cases]

    monkeypatch.setattr(chainid.infra.parallel, "run_cases", run_cases)
    out = tmp_path / "b.json"
    out.write_text("mine")
    with pytest.raises(Exception, match="--json"):
        bm.run_benchmark(small=True, json_path=str(out), excitations=("harmonic",), progress=False)
    assert ran == [] and out.read_text() == "mine"
    s = bm.run_benchmark(small=True, json_path=str(out), overwrite=True, excitations=("harmonic",), progress=False)
    n = len(bm.grid(small=True, excitations=("harmonic",)))
    assert ran == [n] and s["n_cases"] == n and s["control_none_rate"] == 1.0
    doc = json.loads(out.read_text())
    assert doc["n_cases"] == n and len(doc["rows"]) == n and doc["wall_seconds"] >= 0
    assert "control gives none: 100.0 % of 1 (target >= 95 %)" in capsys.readouterr().out


# ---------------------------------------------------------------- timedomain helpers by hand

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
    """F_n = m·ẍ·1e-3 + k(x − x_ref) plus: friction (F_c + μ|F_k|)·sgn-with-stick; hysteresis the Dahl operator;
    backlash k(play(x, b/2) − x_ref) instead of k(x − x_ref); sensor_delay everything at t − τ (linear
    interpolation); damping_law nothing; slack needs a chain model (a chain-only effect)."""
    from chainid.gap.timedomain.data import undamped
    from chainid.model.effects import dahl_operator, play_operator, stick_slip

    t = np.linspace(0.0, 2.0, 401)
    x = 1.0 + 0.3 * np.sin(2 * np.pi * t)
    xd = 0.6 * np.pi * np.cos(2 * np.pi * t)
    xdd = -1.2 * np.pi ** 2 * np.sin(2 * np.pi * t)
    d = SimpleNamespace(t=t, x=x, xd=xd, xdd=xdd)
    k, xr, m = 100.0, 0.2, 50.0
    spring = LinearModel(k, xr, mass=m)
    Fk = k * (x - xr)
    base = m * xdd * 1e-3 + Fk
    F, v = undamped([], {}, spring, d)
    np.testing.assert_allclose(F, base, rtol=1e-12)
    np.testing.assert_array_equal(v, xd)
    F, _ = undamped(["friction"], {"friction.F_c": 5.0, "friction.mu": 0.01}, spring, d)
    np.testing.assert_allclose(F, base + (5.0 + 0.01 * np.abs(Fk)) * stick_slip(x, xd, 0.0, periodic=False),
                               rtol=1e-12)
    F, _ = undamped(["hysteresis"], {"hysteresis.F_h": 7.0, "hysteresis.x_h": 0.05}, spring, d)
    np.testing.assert_allclose(F, base + dahl_operator(x, 7.0, 0.05, periodic=False), rtol=1e-12)
    F, _ = undamped(["backlash"], {"backlash.b": 0.1}, spring, d)
    np.testing.assert_allclose(F, m * xdd * 1e-3 + k * (play_operator(x, 0.05, periodic=False) - xr), rtol=1e-12)
    with pytest.raises(ValueError, match="effect 'slack' needs a chain model"):  # slack is chain-only
        undamped(["slack"], {"slack.s": 0.04}, spring, d)
    F, v = undamped(["sensor_delay", "damping_law"], {"sensor_delay.tau": 0.01}, spring, d)
    xl, xdl, xddl = (np.interp(t - 0.01, t, y) for y in (x, xd, xdd))
    np.testing.assert_allclose(F, m * xddl * 1e-3 + k * (xl - xr), rtol=1e-12)
    np.testing.assert_allclose(v, xdl, rtol=1e-12)
    idx = np.array([3, 50, 200])
    F, v = undamped(["hysteresis"], {"hysteresis.F_h": 7.0, "hysteresis.x_h": 0.05}, spring, d, idx)
    np.testing.assert_allclose(F, (base + dahl_operator(x, 7.0, 0.05, periodic=False))[idx], rtol=1e-12)


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


# ---------------------------------------------------------------- where.localise: the findings by hand

def _localise(C=30.0, tau=0.0):
    from chainid.gap.harmonic.where import localise

    B = 64
    psi = (np.arange(B) + 0.5) * 2 * math.pi / B
    data = [SimpleNamespace(test=f"T{i}", sigma=1.0, counts=np.full(B, 10.0), omega=w, A=A, x0=2.0,
                            Fbar=1000.0 + 500.0 * np.sin(psi - w * tau) + C * np.cos(psi))
            for i, (w, A) in enumerate([(10.0, 0.2), (20.0, 0.3), (30.0, 0.4)])]
    base = {"res": {d.test: C * np.cos(psi) for d in data}, "per_test": {d.test: 0.1 * (i + 1) for i, d in
                                                                          enumerate(data)},
            "c_e": {d.test: 1.0 for d in data}}
    prob = SimpleNamespace(data=data, hold=data[:1], train=data[1:], sigma_raw=1.0, ke={d.test: 5000.0 for d in data})
    return {f["kind"]: f for f in localise(prob, base)}, localise(prob, base)


def test_localise_level_branch_and_energy_by_hand():
    """Residual C·cos ψ (C = 30 N) in every test: RMS C/√2 = 21.21 N against a cycle-mean floor σ/√10 = 0.316 N
    (36.5 dB); the loading branch (cos ψ > 0) averages +2C/π, the unloading −2C/π: a difference of 4C/π =
    +38.2 N; c_e = 1 everywhere makes W = π·c_e·ω·A², slopes (2, 1): viscous; no delay (the phase of F is the
    same at every ω)."""
    kinds, found = _localise()
    lv = kinds["level"]
    assert lv["rms_N"] == pytest.approx(30 / math.sqrt(2), rel=1e-9)
    assert lv["noise_floor_N"] == pytest.approx(1 / math.sqrt(10), rel=1e-12)
    assert lv["finding"] == ("baseline residual RMS 21.21 N, 36.5 dB over the cycle-averaged noise floor 0.316 N "
                             "(noise σ = 1 N from cycle-to-cycle scatter)")
    br = kinds["branch"]
    assert br["difference_N"] == pytest.approx(4 * 30 / math.pi, rel=1e-3)
    assert br["finding"].startswith("loading vs unloading branch: mean residual differs by +38.2 N")
    en = kinds["energy"]
    assert (en["slope_A"], en["slope_omega"]) == (pytest.approx(2.0, abs=1e-9), pytest.approx(1.0, abs=1e-9))
    assert "(closest form: viscous;" in en["finding"]
    assert "delay" not in kinds
    tests = [f for f in found if f["kind"] == "test"]
    assert [f["test"] for f in tests] == ["T0", "T1", "T2"]  # all equal RMS: the data's order
    assert tests[0]["finding"].startswith("test T0 (held-out; ω=10 rad/s, A=0.2 mm, x0=2 mm): NRMSE 0.1, residual "
                                          "RMS 21.2 N, signed energy error")
    assert tests[1]["finding"].startswith("test T1 (training;")
    # the energy error per cycle ∮ r dx = π·A·C (a viscous excess dissipates)
    assert [f["energy_error_Nmm"] for f in tests] == pytest.approx([math.pi * A * 30 for A in (0.2, 0.3, 0.4)],
                                                                   rel=1e-9)
    assert [f["score"] for f in found] == sorted((f["score"] for f in found), reverse=True)


def test_localise_names_a_force_channel_lag():
    """F(ψ − ωτ) with τ = 5 ms: the fundamental's phase falls as −ωτ over ω = 10 … 30 rad/s (R² = 1, ωτ_max =
    0.15 >= 0.05): a delay finding with slope −5 ms."""
    kinds, _ = _localise(C=0.0, tau=0.005)
    dl = kinds["delay"]
    assert dl["tau_s"] == pytest.approx(0.005, rel=1e-9) and dl["phase1_r2"] == pytest.approx(1.0, abs=1e-6)
    assert dl["finding"].startswith("delay signature: the phase of F against x falls linearly with ω across tests "
                                    "(slope -5 ms, R² 1.000")
    assert "delay" not in _localise(C=0.0, tau=0.0015)[0]  # ωτ_max = 0.045 < 0.05
    assert "delay" in _localise(C=0.0, tau=0.0017)[0]  # 0.051


def test_contract_ranking_best_and_chain_text_by_hand():
    """The JSON contract: ranking = the single effects and the chain's multi-effect steps, by LOTO NRMSE; best
    = the chain's last step (else the best single); left NRMSE = the last step's (else the baseline's);
    chain_text = the step texts joined by arrows and the dB left; private keys carry the objects."""
    from chainid.gap.harmonic.problem import Candidate
    from chainid.gap.core.verdict import contract

    def cand(name, loto, hold, params=None):
        c = Candidate(name, params or {}, len(params or {}), nrmse_loto=loto, nrmse_holdout=hold)
        return c

    base = cand("baseline", 0.9, 0.8)
    f = cand("friction", 0.4, 0.3, {"friction.F_c": 12.0})
    s = cand("slack", 0.5, 0.6, {"slack.s": 0.1})
    fs = cand("friction+slack", 0.2, 0.1, {"friction.F_c": 11.0, "slack.s": 0.05})
    prob = SimpleNamespace(law="viscous", law_reason="given")
    model = SimpleNamespace(name="chain")
    fwd = {"path": [base, f, fs], "singles": [s, f], "stop": "S", "dropped": []}
    out = contract(prob, model, base, {"noise_sigma_N": 2.0}, fwd, "friction+slack", "", {"db_over_noise": 1.26},
                   [], [], [], [], ["h"], [])
    assert [r["effect"] for r in out["ranking"]] == ["friction+slack", "friction", "slack"]
    assert out["best"]["effect"] == "friction+slack" and out["left_nrmse_holdout"] == 0.1
    assert [st["effect"] for st in out["steps"]] == ["baseline", "friction", "slack"]
    # each step names its newest effect with that effect's parameters at the step's fit
    assert out["chain_text"] == ("baseline [held-out NRMSE 0.8] → friction F_c = 12 N [held-out NRMSE 0.3] → "
                                 "slack s = 0.05 mm [held-out NRMSE 0.1] → residual 1.3 dB over noise")
    assert out["baseline"]["model"] == "chain" and out["baseline"]["damping_law"] == "viscous"
    assert out["baseline"]["noise_sigma_N"] == 2.0 and out["mechanism"] == "friction+displacement offset"
    assert out["_best"] is fs and out["_path"] == [base, f, fs] and out["_problem"] is prob
    none = contract(prob, model, base, {}, {"path": [base], "singles": [s, f], "stop": "S", "dropped": []}, "none",
                    "", {"db_over_noise": 0.0}, [], [], [], [], ["h"], [])
    assert none["best"]["effect"] == "friction" and none["left_nrmse_holdout"] == 0.8
    assert none["steps"][0]["effect"] == "baseline" and len(none["steps"]) == 1
    empty = contract(prob, model, base, {}, {"path": [base], "singles": [], "stop": "S", "dropped": []}, "none",
                     "", {"db_over_noise": 0.0}, [], [], [], [], ["h"], [])
    assert empty["best"] is None and empty["_best"] is None
