"""Results must not depend on the time origin of the records.

A logger writes Unix time stamps (t ~ 1.7e9 s); the same series shifted there, to one day (86 400 s) or to
1e4 s must keep the same tests and give the same c_e as from t = 0.  At 1.7e9 s a float64 time stamp has a
resolution of 2.4e-7 s, so the shifted samples carry that jitter (as a real logger's file does): the
reference is the t = 0 result, with a tolerance of 1e-6 relative on c_e (the jitter moves x by < 1e-6 mm)."""
from __future__ import annotations

import numpy as np
import pytest

from chainid.damping.identify import identify_records
from chainid.model.base import ChainModel
from chainid.model.laws import ViscousLaw
from chainid.records.files import Record, read_records, write_records
from chainid.records.simulate import paper_plan, simulate

C_TRUE = 2834.4  # N.s/mm (the paper's plan and viscous c_e, as `chainid simulate` writes them)
ORIGINS = (1e4, 86_400.0, 1.7e9)  # s


@pytest.fixture(scope="module")
def series(tmp_path_factory):
    """The paper's 9 tests as `chainid simulate` writes them (its ramp; CSV, 9 significant digits), read back."""
    model = ChainModel()
    p = write_records(tmp_path_factory.mktemp("origin") / "d.csv",
                      simulate(paper_plan(), model, ViscousLaw([C_TRUE]), seed=0, ramp_rate=0.08973))
    return read_records(p, validate=False), model


def _shift(recs, t0):
    # t + t0 rounded to float64, as a CSV of a logger is read (its time stamps have that resolution)
    return [Record(r.test, r.t + t0, r.x, r.F) for r in recs]


@pytest.mark.slow
@pytest.mark.parametrize("t0", ORIGINS)
def test_identify_same_tests_and_ce_at_any_origin(series, t0):
    recs, model = series
    ref = identify_records(recs, model)
    got = identify_records(_shift(recs, t0), model)
    assert [r.test for r in ref] == [str(i) for i in range(1, 10)]  # all 9 identified from t = 0
    assert [r.test for r in got] == [r.test for r in ref], got.excluded
    assert not got.excluded
    for a, b in zip(ref, got):
        assert b.c_e == pytest.approx(a.c_e, rel=1e-6)
        assert b.c_e == pytest.approx(C_TRUE, rel=1e-5)  # and both are the simulated value
        assert b.n_cycles == a.n_cycles
        assert b.t_start - t0 == pytest.approx(a.t_start, abs=1e-5)


@pytest.mark.slow
@pytest.mark.parametrize("t0", (86_400.0, 1.7e9))
def test_diagnose_same_tests_at_any_origin(series, t0):
    from chainid.gap.diagnose import diagnose

    recs, model = series
    ref = diagnose(recs, ["3", "7"], model, max_combo=1)
    got = diagnose(_shift(recs, t0), ["3", "7"], model, max_combo=1)
    assert ref["excluded"] == [] and got["excluded"] == []
    assert [t["test"] for t in got["tests"]] == [t["test"] for t in ref["tests"]]
    # noise-free data: the baseline fits to round-off (t = 0) or to the time stamps' resolution (1.7e9 s)
    assert ref["baseline"]["nrmse_train"] < 1e-6
    assert got["baseline"]["nrmse_train"] < 1e-6
    assert got["verdict"] == ref["verdict"]


@pytest.mark.slow
def test_diagnose_time_route_same_at_unix_time(series):
    """A guard (this route was already origin-independent): every record in the time domain (--holdout-blocks)."""
    from chainid.gap.diagnose import diagnose

    recs, model = series
    ref = diagnose(recs, [], model, max_combo=1, holdout_blocks=3)
    got = diagnose(_shift(recs, 1.7e9), [], model, max_combo=1, holdout_blocks=3)
    assert got["baseline"]["nrmse_train"] == pytest.approx(ref["baseline"]["nrmse_train"], rel=1e-3)
    assert got["verdict"] == ref["verdict"]


def test_json_theta_is_in_the_records_own_time(series):
    """The JSON contract is unchanged: theta of x = x0 + A sin(omega t + theta) with t as written in the file."""
    recs, model = series
    r = recs[4]  # test 5
    a = identify_records([r], model)[0].to_dict()
    b = identify_records(_shift([r], 86_400.0), model)[0].to_dict()
    assert "t_origin" not in a and "t_origin" not in b
    # the same sine: shifting t by t0 shifts the phase by -omega t0 (mod 2 pi); omega t0 = 2.7e5 rad here
    d = (b["theta"] - (a["theta"] - a["omega"] * 86_400.0) + np.pi) % (2 * np.pi) - np.pi
    assert abs(d) < 1e-6
