"""The shape search's fit subsets are bounded: a record held out whole keeps a token view (nothing changes
numerically), and past ``FIT_TOTAL`` samples each training record keeps evenly spaced contiguous windows over its
training samples, at least four and one per block, each after a lead-in that is weighed 0; the thinned search finds
the shapes the full one finds."""
from __future__ import annotations

import numpy as np
import pytest

import recovery_cases as rc
from chainid.gap.timedomain import data as D
from chainid.gap.timedomain import problem as P
from chainid.gap.timedomain.route import build_problem


def _tdata(n_rec: int = 4, n: int = 4000, band: tuple[float, float] = rc.BAND_LIN, blocks: int = 4) -> list:
    return [D.prepare_time(r, blocks) for r in rc.linear_random(n_rec=n_rec, n=n, band=band)]


def _train(data: list, held_block: bool = False, held: tuple[str, ...] = ()) -> dict:
    return {d.test: np.zeros(d.t.size, bool) if d.test in held
            else (d.block < d.n_blocks - 1 if held_block else np.ones(d.t.size, bool)) for d in data}


def test_under_the_bound_every_training_subset_is_kept_and_a_whole_held_out_record_keeps_64_samples():
    data = _tdata()
    sub = D.fit_subsets(data, _train(data, held=("r3",)), total=10**9)
    for d in data[:3]:
        assert np.array_equal(sub[d.test][0], d.fit_idx) and sub[d.test][1] is None
    assert np.array_equal(sub["r3"][0], np.arange(64)) and sub["r3"][1] is None


@pytest.mark.parametrize("band", [rc.BAND_LIN, (2.0, 8.0)], ids=["0.2-4 Hz", "2-8 Hz"])
def test_over_the_bound_windows_cover_every_training_block_and_the_lead_ins_are_not_fitted(band):
    """Four records of 16 000 samples, 5 blocks each, the last held out; an eighth of the samples kept.  On a
    0.2–4 Hz band four low-edge periods (20 s) are longer than a record's share: the windows are then shorter,
    never one stretch at the record's start."""
    data = _tdata(n=16000, band=band, blocks=5)
    train = _train(data, held_block=True)
    n_train = sum(int(np.count_nonzero(train[d.test][d.fit_idx])) for d in data)
    total = n_train // 8
    sub = D.fit_subsets(data, train, total=total)
    fitted = sum(int(np.count_nonzero(~lead)) for _, lead in sub.values())
    assert total - 4 * 64 <= fitted <= total
    for d in data:
        idx, lead = sub[d.test]
        assert np.all(np.diff(idx) > 0) and np.all(train[d.test][idx])  # in order, training samples only
        blocks_fitted = set(d.block[idx[~lead]].tolist())
        assert blocks_fitted == {0, 1, 2, 3}  # every training block, none of the held-out one
        # windows: runs of fitted samples, contiguous in the record's fit subset, each after its lead-in
        pos = np.searchsorted(d.fit_idx, idx)
        starts = np.flatnonzero(np.diff(np.r_[True, lead].astype(int)) == -1)  # first fitted sample of each window
        assert starts.size >= 5  # at least four windows, and one per block (five blocks)
        for s in starts[1:]:
            assert lead[s - 1] or pos[s] == pos[s - 1] + 1  # a gap before a window is bridged by a lead-in


def test_a_record_held_out_whole_weighs_nothing_in_the_search_so_its_token_view_changes_no_fit():
    """The same fit with the held-out record's whole subset (the former rule) and with its 64-sample token."""
    recs = rc.linear_random(n_rec=4, extra=lambda mo, t: 0.4 * np.sign(mo(t)[1]))
    prob = build_problem(recs, ["r3"], 0, None)
    assert prob._fit["r3"][0].size == 64
    got = prob.fit(["friction"]).params
    prob._fit["r3"] = (prob.tdata[3].fit_idx, None)
    prob._cache.store.clear()
    ref = prob.fit(["friction"]).params
    for k, v in ref.items():
        assert got[k] == pytest.approx(v, rel=1e-9, abs=1e-12), k


def test_the_thinned_search_finds_the_dahl_travel_the_full_search_finds(monkeypatch):
    """Dahl hysteresis F_h = 2 N, x_h = 0.3 mm on the linear device (6 records of 6 000 samples, σ_F = 0.1 N):
    x_h fitted on every sample and on a sixth of them (windows), each within 5 % of the truth and of each other
    within 5 %."""
    from chainid.model.effects.forms import dahl_operator

    recs = rc.linear_random(lambda mo, t: 2.0 * dahl_operator(mo(t)[0], 1.0, 0.3, False), n_rec=6, n=6000, seed=2)
    full = build_problem(recs, ["r5"], 0, None).fit(["hysteresis"]).params["hysteresis.x_h"]
    monkeypatch.setattr(D, "FIT_TOTAL", 5000)
    monkeypatch.setattr(P, "fit_subsets", lambda data, train: D.fit_subsets(data, train, total=5000))
    prob = build_problem(recs, ["r5"], 0, None)
    assert sum(int(np.count_nonzero(~lead)) for _, lead in prob._fit.values() if lead is not None) <= 5000
    thin = prob.fit(["hysteresis"]).params["hysteresis.x_h"]
    assert full == pytest.approx(0.3, rel=0.05)
    assert thin == pytest.approx(0.3, rel=0.05)
    assert thin == pytest.approx(full, rel=0.05)
