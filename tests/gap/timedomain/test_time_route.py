"""The choice of route (chainid.gap.timedomain.route): harmonic tests keep the phase-bin route by the documented rule."""
from __future__ import annotations

from types import SimpleNamespace


def test_build_problem_routes_harmonic_tests_by_the_documented_rule(monkeypatch):
    """Harmonic tests keep the phase-bin route when at least MIN_TRAIN = 3 of them are for training and no
    --holdout-blocks is given; otherwise they join the time-domain records, with a warning saying why; every
    time-domain record is cut in LOO_BLOCKS = 4 blocks (or the --holdout-blocks K)."""
    from chainid.gap.timedomain import route as dt

    made = {}
    monkeypatch.setattr(dt, "prepare_time", lambda r, nb: SimpleNamespace(test=r.test, nb=nb))
    monkeypatch.setattr(dt, "Problem", lambda data, model, hold, law, require_hold: SimpleNamespace(
        tests=[d.test for d in data], hold=hold, law=law, require_hold=require_hold))

    def anyp(tdata, model, holdout, blocks, hprob):  # noqa: ANN001
        made.update(tdata=[(d.test, d.nb) for d in tdata], hprob=hprob, blocks=blocks)
        return made

    monkeypatch.setattr(dt, "AnyProblem", anyp)
    recs = [SimpleNamespace(test=s) for s in ("h1", "h2", "h3", "h4", "r1")]
    hdata = [SimpleNamespace(test=s) for s in ("h1", "h2", "h3", "h4")]
    warn = []
    dt.build_problem(recs, hdata, [recs[4]], ["h4"], 0, "M", "viscous", warn)
    assert made["tdata"] == [("r1", 4)] and warn == []
    assert (made["hprob"].tests, made["hprob"].hold, made["hprob"].law) == (["h1", "h2", "h3", "h4"], ["h4"], "viscous")
    assert made["hprob"].require_hold is False
    dt.build_problem(recs, hdata, [recs[4]], ["h3", "h4"], 0, "M", "auto", warn)  # 2 harmonic training tests
    assert made["hprob"] is None and made["tdata"] == [("r1", 4), ("h1", 4), ("h2", 4), ("h3", 4), ("h4", 4)]
    assert warn == ["4 harmonic test(s) analysed in the time domain with the other records (fewer than 3 harmonic "
                    "training tests for the phase-bin route)"]
    warn.clear()
    dt.build_problem(recs, hdata, [recs[4]], [], 3, "M", "auto", warn)
    assert made["hprob"] is None and made["blocks"] == 3 and {nb for _, nb in made["tdata"]} == {3}
    assert warn == ["4 harmonic test(s) analysed in the time domain with the other records (--holdout-blocks "
                    "splits every record in time)"]
    warn.clear()
    dt.build_problem(recs[4:], [], [recs[4]], ["r1"], 0, "M", "auto", warn)
    assert made["hprob"] is None and warn == [] and made["tdata"] == [("r1", 4)]
