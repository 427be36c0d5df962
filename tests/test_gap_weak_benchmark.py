"""Issue 20 §5: behaviours of the gap package (the benchmark's cases, effects, rows, report texts and grid) that the
mutation runs found unpinned (seed 22 and own seeds).

Each test checks a documented behaviour against a hand computation or the documented contract; the expensive
parts (simulation, diagnosis) are replaced by recorders where the test is about what the benchmark hands them.
Units: mm, N, s.
"""
from __future__ import annotations

import math
import sys
from types import SimpleNamespace

import numpy as np
import pytest

from chainid.model.base import LinearModel


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


def _harmonic_case(**kw):
    case = {"excitation": "harmonic", "family": "single", "truth": ["friction"], "effects": ["friction"],
            "levels": [2.0], "noise": 0.02, "chain": "14x50", "plan": "grid3x3", "seed": 5}
    return case | kw


def test_harmonic_case_noise_damping_and_holdout_by_hand(monkeypatch):
    """``run_case`` (harmonic): noise σ = noise × S with S the plan's median dynamic force k(x0)·A, the viscous
    loss ~2 % of k at the top frequency (Eq. 21's α5 = 0.02·k/ω_max), the friction level 0.1·level·S
    (``effect_spec``), three held-out tests (the 3rd, the middle one and the last)."""
    from chainid.chain.spec import default_chain
    from chainid.gap.benchmark.grid import run_case
    from chainid.model.base import ChainModel
    from chainid.records import simulate as simulate_module

    nominal = ChainModel(default_chain())
    # grid3x3: ω ∈ {1, 2, 4} × A ∈ {0.1, 0.2, 0.3} at x0 = 2, plus (3, 2.2, 0.15) and (1.5, 1.8, 0.25)
    kx = {x0: float(nominal.stiffness(np.array([x0]))[0]) for x0 in (1.8, 2.0, 2.2)}
    dyn = sorted([kx[2.0] * A for A in (0.1, 0.2, 0.3) for _ in range(3)] + [kx[2.2] * 0.15, kx[1.8] * 0.25])
    S = dyn[5]  # the median of 11
    k = kx[2.0]  # median stiffness: 9 of the 11 tests are at x0 = 2
    seen = {}

    def sim(plan, model, law, **kw):  # noqa: ANN001
        seen.update(kw, law=law, plan=[p.test for p in plan])
        x = np.linspace(1.9, 2.1, 5)
        seen["added"] = kw["force_fn"](x, x, np.ones(5), 0 * x, np.zeros(5))  # sliding forward: + F_c
        raise _Stop

    monkeypatch.setattr(simulate_module, "simulate", sim)
    with pytest.raises(_Stop):
        run_case(_harmonic_case())
    assert seen["noise_F"] == pytest.approx(0.02 * S, rel=1e-12)
    assert seen["seed"] == 5 and seen["n_cycles"] == 8 and seen["samples_per_cycle"] == 256
    assert list(seen["law"].params) == pytest.approx([0, 0, 0, 0, 0.02 * k / 4.0], rel=1e-12)
    assert seen["added"] == pytest.approx(np.full(5, 0.1 * 2.0 * S), rel=1e-5)  # F_c = 0.1·level·S (6 digits)

    held = {}

    def sim2(plan, model, law, **kw):  # noqa: ANN001
        return [SimpleNamespace(test=p.test) for p in plan]

    def diag(records, holdout, model, **kw):  # noqa: ANN001
        held["ids"] = list(holdout)
        raise ValueError("boom")

    monkeypatch.setattr(simulate_module, "simulate", sim2)
    monkeypatch.setattr(sys.modules["chainid.gap.diagnose"], "diagnose", diag)
    row = run_case(_harmonic_case())
    assert held["ids"] == ["a3", "a6", "a11"]
    assert row["verdict"] == "error: ValueError: boom" and row["snr"] == math.inf and row["steps"] == []


# ---------------------------------------------------------------- benchmark report: transfer and non-harmonic texts

def _trow(direction, verdict, sh, shr, ok, truth=("friction",)):
    return {"excitation": "transfer", "family": "transfer", "direction": direction, "truth": list(truth),
            "verdict": verdict, "transfer_shrinkage": sh, "transfer_shrinkage_refit": shr, "transfers": ok,
            "transfer_chain": verdict, "seed": 1, "snr": 9.0, "shrinkage": 0.9, "seconds": 1.0}


def test_transfer_rates_by_hand():
    from chainid.gap.benchmark.report import transfer_rates

    rows = [_trow("harmonic>random", "friction", 0.8, 0.6, True), _trow("harmonic>random", "hysteresis", 0.2, None, False),
            _trow("random>harmonic", "friction", None, None, False),
            _trow("random>harmonic", "machine_compliance", 0.9, 0.7, True, truth=("stiffness_level",))]
    t = transfer_rates(rows)
    assert t["n"] == 4
    assert t["median_shrinkage"] == pytest.approx(0.8)  # of 0.8, 0.2, 0.9 (None left out)
    assert t["median_shrinkage_refit"] == pytest.approx(0.65)  # of 0.6, 0.7
    assert t["transfers_rate"] == 0.5
    assert t["fit_right_rate"] == 0.75  # machine_compliance reads as stiffness_level
    h, r = t["by_direction"]["harmonic>random"], t["by_direction"]["random>harmonic"]
    assert (h["n"], h["median_shrinkage"], h["median_shrinkage_refit"], h["transfers_rate"]) == (2, 0.5, 0.6, 0.5)
    assert (r["n"], r["median_shrinkage"], r["fit_right_rate"]) == (2, 0.9, 1.0)
    assert list(t["by_direction"]) == ["harmonic>random", "random>harmonic"]
    assert t["rows"][2] == {"direction": "random>harmonic", "truth": ["friction"], "verdict": "friction",
                            "transfer_chain": "friction", "transfer_shrinkage": None,
                            "transfer_shrinkage_refit": None, "transfers": False, "seed": 1}
    empty = transfer_rates([])
    assert empty["n"] == 0 and empty["median_shrinkage"] is None and empty["transfers_rate"] is None


def _row(exc, family, truth, verdict, snr=9.0, **kw):
    return {"excitation": exc, "family": family, "truth": truth, "verdict": verdict, "snr": snr, "shrinkage": 0.8,
            "seconds": 2.0, "chain": "c", "plan": exc, "noise": 0.01, "levels": [1.0], "seed": 7} | kw


def test_summarise_splits_excitations_and_formats_the_non_harmonic_lines():
    """Harmonic rows at the top level; each non-harmonic excitation apart and pooled; transfer apart; the
    terminal lines say each rate with its n, PASS/MISS against issue 18's targets and the misses."""
    from chainid.gap.benchmark.report import format_summary, summarise

    rows = [_row("harmonic", "single", ["friction"], "friction"),
            _row("random", "single", ["friction"], "friction"), _row("random", "single", ["slack"], "backlash"),
            _row("sweep", "single", ["friction"], "friction"), _row("sweep", "control", [], "none", snr=0.5),
            _row("sweep", "outside", ["chatter"], "friction", truth_named=["friction"], chatter=True),
            _trow("harmonic>random", "friction", 0.8, 0.6, True)]
    s = summarise(rows)
    assert (s["n_cases"], s["harmonic_n"]) == (7, 1)
    assert s["single_right_rate"] == 1.0 and s["single_n"] == 1  # the harmonic one only
    assert sorted(s["by_excitation"]) == ["random", "sweep"]
    assert s["by_excitation"]["random"]["single_right_rate"] == 0.5
    nh = s["nonharmonic"]
    assert (nh["single_right_rate"], nh["single_n"], nh["control_none_rate"]) == (2 / 3, 3, 1.0)
    assert s["transfer"]["n"] == 1 and s["rows"] is rows
    txt = format_summary(s | {"wall_seconds": 12.4})
    lines = txt.splitlines()
    assert "non-harmonic excitations (residual >= 3x noise; n in brackets):" in lines
    i = lines.index("non-harmonic excitations (residual >= 3x noise; n in brackets):")
    assert lines[i + 2] == (f"{'random':<12}{'50.0 % (2)':>14}{'n/a (0)':>14}{'n/a (0)':>14}{'n/a (0)':>14}"
                            f"{'n/a (0)':>14}{'n/a':>10}")
    assert lines[i + 3].startswith("sweep") and lines[i + 3].endswith(f"{'100.0 %':>10}")
    assert lines[i + 4].startswith(f"{'pooled':<12}{'66.7 % (3)':>14}")
    assert ("  MISS: non-harmonic single_right_rate = 66.7 % (target >= 90 %)") in lines
    assert ("  PASS: non-harmonic control_none_rate = 100.0 % (target >= 95 %)") in lines
    assert "  MISS: non-harmonic compound_both_named_rate = n/a (target >= 80 %)" in lines
    assert "  1 non-harmonic miss(es), e.g.:" in lines
    assert "    random single: truth slack -> backlash (snr 9.0, seed 7)" in lines
    assert ("transfer (1 cases): median pooled shrinkage on the other set 80.0 % (target >= 70 %: PASS); after a "
            "per-record refit of offset, spring and dashpot 60.0 %; verdict 'transfers' 100.0 %; true effect named "
            "on the fitting set 100.0 %") in lines
    assert "  harmonic>random: 1 cases, median shrinkage 80.0 %, after refit 60.0 %, transfers 100.0 %" in lines
    assert "median diagnosis time 2.00 s over 7 cases; wall 12 s" in lines
    assert "  PASS: single_right_rate = 100.0 % (target >= 92 %)" in lines
    assert "  MISS: compound_both_named_rate = n/a (target >= 85 %)" in lines


def test_format_summary_without_harmonic_rows_and_with_errors():
    from chainid.gap.benchmark.report import format_summary, summarise

    rows = [_row("quake", "single", ["friction"], "error: ValueError: boom"),
            _row("quake", "single", ["friction"], "friction")]
    txt = format_summary(summarise(rows) | {"wall_seconds": 3.0})
    lines = txt.splitlines()
    assert lines[0] == "2 cases; wall 3 s"
    assert "harmonic families:" not in txt
    assert lines[-1] == "1 case(s) raised an error (counted as misses), e.g. error: ValueError: boom"
    assert format_summary(summarise(rows)).splitlines()[0] == "2 cases"


def test_format_summary_confusion_matrix_and_misses():
    from chainid.gap.benchmark.report import format_summary, summarise

    rows = [_row("harmonic", "single", ["friction"], "friction"),
            _row("harmonic", "single", ["machine_compliance"], "hysteresis+slack"),
            _row("harmonic", "control", [], "none", snr=0.1),
            _row("harmonic", "single", ["backlash"], "error: RuntimeError: x")]
    lines = format_summary(summarise(rows)).splitlines()
    i = lines.index("confusion (rows: truth of single / mismatch / control cases; columns: verdict)")
    cols = ["(combination)", "error: RuntimeError: x", "friction", "none"]
    w = len("error: RuntimeError: x") + 1  # the widest column label + 1 (>= 8)
    assert lines[i + 1] == " " * 22 + "".join(f"{c[:w - 1]:>{w}}" for c in cols)
    assert lines[i + 2] == f"{'backlash':<22}" + "".join(f"{n:>{w}}" for n in (0, 1, 0, 0))
    assert lines[i + 4] == f"{'machine_compliance':<22}" + "".join(f"{n:>{w}}" for n in (1, 0, 0, 0))
    assert "1 case(s) raised an error (counted as misses), e.g. error: RuntimeError: x" in "\n".join(lines)
    assert "2 miss(es), e.g.:" in lines
    assert "  single: truth machine_compliance -> hysteresis+slack (snr 9.0, c, harmonic, noise 0.01)" in lines


# ---------------------------------------------------------------- the benchmark grid against its documentation

def test_benchmark_grid_is_the_documented_one():
    """README (Sim-to-real gap; the gap on any excitation): 524 cases, 344 harmonic, 168 non-harmonic, 12 transfer;
    every first-release effect alone at 3 strengths × 2 noise levels × 2 chains × 2 plans, the second release's four
    (stribeck, bouc_wen, deadband, fixture_mass) at 2 strengths × 2 chains, appended; 24 controls; mismatch
    EA × 0.7–1.4, Hertz compliance × 0.5–2; non-harmonic strengths log-uniform 0.5–3×, noise 0.5–3 %; transfer
    both directions, six effects; case seeds seed + 100000 + 1000·k + i (module docstring of time_grid)."""
    from chainid.gap.benchmark.grid import ALL_EXCITATIONS, GRID_EFFECTS, NEW_GRID_EFFECTS, grid
    from chainid.gap.benchmark.nonharmonic import EXCITATIONS

    g = grid(seed=3)
    ex = [c["excitation"] for c in g]
    assert (len(g), ex.count("harmonic"), ex.count("transfer")) == (524, 344, 12)
    harm = [c for c in g if c["excitation"] == "harmonic"]
    singles = [c for c in harm if c["family"] == "single"]
    for e in GRID_EFFECTS:
        mine = [c for c in singles if c["effects"] == [e]]
        assert len(mine) == 3 * 2 * 2 * 2
        assert len({(c["levels"][0], c["noise"], c["chain"], c["plan"]) for c in mine}) == 24
    for e in NEW_GRID_EFFECTS:
        mine = [c for c in singles if c["effects"] == [e]]
        assert sorted((c["levels"][0], c["chain"]) for c in mine) == sorted(
            (lv, ch) for lv in (1.0, 3.0) for ch in {c["chain"] for c in harm})
        assert harm.index(mine[0]) >= 328  # appended: every earlier case keeps its seed
    assert sum(c["family"] == "control" for c in harm) == 24
    mism = [c for c in harm if c["family"] == "mismatch"]
    ea = sorted({c["ea_scale"] for c in mism if "ea_scale" in c})
    hz = sorted({c["hertz_scale"] for c in mism if "hertz_scale" in c})
    assert (ea[0], ea[-1], hz[0], hz[-1]) == (0.7, 1.4, 0.5, 2.0)
    assert [c["seed"] for c in harm] == list(range(4, 4 + 344))  # seed + 1, + 2, …: one per case
    order = EXCITATIONS + ("transfer",)
    for e in order:
        mine = [c for c in g if c["excitation"] == e]
        assert [c["seed"] for c in mine] == [3 + 100000 + 1000 * order.index(e) + i for i in range(len(mine))]
    timed = [c for c in g if c["excitation"] in EXCITATIONS]
    assert all(0.5 <= lv <= 3.0 for c in timed for lv in c["levels"])
    assert all(0.005 <= c["noise"] <= 0.03 for c in timed)
    assert all(c["hold"] in ("r1", "r2", "r3", "r4") for c in timed)
    tr = [c for c in g if c["excitation"] == "transfer"]
    assert sorted((c["effects"][0], c["direction"]) for c in tr) == sorted(
        (e, d) for e in ("friction", "hysteresis", "backlash", "stiffness_level", "slack", "sensor_delay")
        for d in ("harmonic>random", "random>harmonic"))
    # a case is the same whichever excitations run
    assert grid(seed=3, excitations=("sweep",)) == [c for c in g if c["excitation"] == "sweep"]
    assert grid(seed=3, excitations=("harmonic",)) == harm
    assert tuple(ALL_EXCITATIONS) == ("harmonic",) + order
    with pytest.raises(ValueError, match=r"--excitations 'harmonic,wind': unknown \['wind'\]; valid: "
                                         "harmonic,random,sweep,startup,quake,transfer"):
        grid(excitations=("harmonic", "wind"))
    with pytest.raises(ValueError, match=r"--excitations '': unknown empty"):
        grid(excitations=())


def test_small_grids_one_case_per_family():
    """The small subset (tests): harmonic — friction and stiffness_level alone, a control, a mismatch, a mismatch
    plus friction and one pair; non-harmonic — one single-effect case per family, one control, one transfer."""
    from chainid.gap.benchmark.grid import grid

    g = grid(small=True)
    fam = [(c["excitation"], c["family"], tuple(c["effects"])) for c in g]
    assert fam[:6] == [("harmonic", "single", ("friction",)), ("harmonic", "single", ("stiffness_level",)),
                       ("harmonic", "control", ()), ("harmonic", "mismatch", ()),
                       ("harmonic", "mismatch+", ("friction",)),
                       ("harmonic", "pair", ("friction", "sensor_delay"))]
    assert fam[6:] == [("random", "single", ("friction",)), ("sweep", "single", ("hysteresis",)),
                       ("startup", "single", ("backlash",)), ("quake", "single", ("stiffness_level",)),
                       ("random", "control", ()), ("transfer", "transfer", ("hysteresis",))]


# ---------------------------------------------------------------- benchmark rows from a hand-made diagnosis

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


def test_run_case_dispatches_by_excitation(monkeypatch):
    from chainid.gap.benchmark import nonharmonic as bt
    from chainid.gap.benchmark.grid import run_case

    monkeypatch.setattr(bt, "run_case_time", lambda c: ("time", c["excitation"]))
    monkeypatch.setattr(bt, "run_case_transfer", lambda c: ("transfer", c["excitation"]))
    assert run_case({"excitation": "quake"}) == ("time", "quake")
    assert run_case({"excitation": "transfer"}) == ("transfer", "transfer")


def test_outside_library_hooks_by_hand(monkeypatch):
    """Harmonic cases: a drift adds 0.05·level·S·t/t_end; a relaxation takes off 0.1·level·S·(1 − exp(−3 t/t_end)).
    Non-harmonic records: the same from the record's first sample, (t − t0)/(t_end − t0)."""
    from chainid.gap.benchmark.grid import run_case
    from chainid.gap.benchmark.nonharmonic import _outside
    from chainid.records import simulate as simulate_module

    t = np.linspace(0.0, 4.0, 9)
    z = np.zeros(9)
    # S of the plan (see test_harmonic_case_noise_damping_and_holdout_by_hand), via the noise σ = noise·S
    seen = {}

    def sim_s(plan, model, law, **kw):  # noqa: ANN001
        seen.update(kw)
        raise _Stop

    monkeypatch.setattr(simulate_module, "simulate", sim_s)
    with pytest.raises(_Stop):
        run_case(_harmonic_case(effects=["drift"], truth=["drift"], levels=[2.0], noise=1.0))
    S = seen["noise_F"]
    np.testing.assert_allclose(seen["force_fn"](t, z, z, z, z), 0.05 * 2.0 * S * t / 4.0, rtol=1e-12)
    with pytest.raises(_Stop):
        run_case(_harmonic_case(effects=["relaxation"], truth=["relaxation"], levels=[0.5], noise=1.0))
    np.testing.assert_allclose(seen["force_fn"](t, z, z, z, 10 + z), 10 - 0.1 * 0.5 * S * (1 - np.exp(-3 * t / 4.0)),
                               rtol=1e-12)
    rng = np.random.default_rng(0)
    t2 = 3.0 + t  # a record that starts at 3 s
    np.testing.assert_allclose(_outside("drift", 2.0, 100.0, 0.0, rng)(t2, z, z, z, z), 0.05 * 2 * 100 * t / 4.0,
                               rtol=1e-12)
    np.testing.assert_allclose(_outside("relaxation", 1.0, 100.0, 0.0, rng)(t2, z, z, z, z),
                               -0.1 * 100 * (1 - np.exp(-3 * t / 4.0)), rtol=1e-12)
