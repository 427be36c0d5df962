"""The diagnosis refuses bad input before any work (chainid.gap.diagnose): magnitudes, dead channels, hold-out
options, and fits the linear spring on the training records only."""
from __future__ import annotations

import numpy as np
import pytest


def _recs(n=5):
    from chainid.records.record import Record

    t = np.linspace(0, 1, 50)
    return [Record(str(i), t, 2.0 + 0.1 * np.sin(2 * np.pi * t), 100.0 * np.sin(2 * np.pi * t) + i)
            for i in range(1, n + 1)]


def test_check_magnitudes_limits_and_dead_channel():
    """|F| <= 1e12 N and |x| <= 1e9 mm (the documented limits, inclusive); a constant F is refused; a record with
    a non-finite value is left to the later checks."""
    from chainid.gap.diagnose import check_magnitudes
    from chainid.records.record import Record

    t = np.linspace(0, 1, 5)
    ok = Record("a", t, np.array([0, 1e9, 0, -1e9, 0.0]), np.array([1e12, -1e12, 0, 1, 2.0]))
    check_magnitudes([ok])
    with pytest.raises(ValueError, match=r"test 'b': \|F\| = 1\.5e\+12 N is out of range; valid range \|F\| <= "
                                         r"1e\+12 N \(check the column's unit\)"):
        check_magnitudes([ok, Record("b", t, ok.x, np.array([0, 1.5e12, 0, 1, 2.0]))])
    with pytest.raises(ValueError, match=r"test 'c': \|x\| = 2e\+09 mm is out of range; valid range \|x\| <= "
                                         r"1e\+09 mm"):
        check_magnitudes([Record("c", t, np.array([0, -2e9, 0, 1, 2.0]), ok.F)])
    with pytest.raises(ValueError, match=r"test 'd': the force F is constant \(7 N in all 5 samples\): a dead "
                                         "channel"):
        check_magnitudes([Record("d", t, ok.x, np.full(5, 7.0))])
    check_magnitudes([Record("e", t, ok.x, np.array([np.nan, 3e12, 7, 7, 7.0]))])  # NaN: not judged here


def test_diagnose_refuses_bad_holdout_options_before_any_work():
    from chainid.gap.diagnose import diagnose

    recs = _recs()
    with pytest.raises(ValueError, match=r"max_combo = 0 is out of range; valid range 1 to 3"):
        diagnose(recs, ["1"], max_combo=0)
    for k in (1, -1):
        with pytest.raises(ValueError, match=rf"--holdout-blocks = {k} is out of range; valid: 0 \(off\) or >= 2"):
            diagnose(recs, ["1"], holdout_blocks=k)
    with pytest.raises(ValueError, match=r"--holdout: no test held out; give test ids or --holdout-blocks K"):
        diagnose(recs, [" ", ""])
    with pytest.raises(ValueError, match=r"--holdout: all 5 tests are held out; leave at least 3 for training"):
        diagnose(recs, [" 1", "2 ", "3", "4", "5"])  # ids are stripped
    with pytest.raises(ValueError, match=r"--holdout: test id\(s\) \['9'\] not in the data; valid ids: 1, 2, 3, 4, 5"):
        diagnose(recs, ["9"])
    bad = _recs(2)
    bad[1] = type(bad[1])("2", bad[1].t, bad[1].x, np.full(50, 3.0))
    with pytest.raises(ValueError, match="the force F is constant"):  # the --validate set is checked too
        diagnose(recs, ["1"], validate=bad)


def test_fit_linear_model_uses_the_training_records_only():
    from chainid.gap.diagnose import fit_linear_model
    from chainid.records.record import Record

    t = np.linspace(0, 1, 30)
    x = 1.0 + 0.5 * np.sin(2 * np.pi * t)
    recs = [Record("a", t, x, 50.0 * (x - 0.2)), Record("b", t, x + 0.3, 50.0 * (x + 0.1)),
            Record("h", t, x, 999.0 * x)]
    m = fit_linear_model(recs, ["h"])
    assert (m.k, m.x_ref) == (pytest.approx(50.0, rel=1e-9), pytest.approx(0.2, rel=1e-9))
