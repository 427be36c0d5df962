"""A chain's measured force may dip below zero through its damping (the spring force F_k(x) stays positive):
such records are analysed with a warning on stderr and in the JSON, never refused; a record whose mean force is
no tension is refused (no chain), and x < 0 throughout under tension is a warning.

The records are Eq. 1 in closed form: F = F_k(x) + c·ẋ with the paper chain's F_k, x = 0.6 + A sin ωt (A <= 0.3
mm, so F_k(x) >= F_k(0.3 mm) = 980 N > 0 throughout) and c = 1000 N·s/mm, so c·A·ω (up to 9 kN) takes F below
zero; the identified c_e must be that c.
"""
from __future__ import annotations

import json

import numpy as np
import pytest

from chainid.cli import main
from chainid.model.base import ChainModel
from chainid.model.kernels import force
from chainid.records.files import write_records
from chainid.records.record import Record
from chainid.records.simulate import TestSpec, simulate
from chainid.records.validate import RecordWarning, check_data

C = 1000.0
PLAN = [TestSpec(str(i), w, 0.6, A) for i, (w, A) in enumerate(
    [(10, 0.2), (15, 0.3), (20, 0.25), (25, 0.2), (30, 0.3), (12, 0.3), (18, 0.2), (22, 0.3)], 1)]
N_DIP = 7  # all but test 1 (c·A·ω = 2 kN there, less than F_k(0.4 mm)): counted from the closed form


@pytest.fixture(scope="module")
def dip_csv(tmp_path_factory):
    recs = simulate(PLAN, ChainModel(), C, n_cycles=6, samples_per_cycle=128, ramp_rate=None)
    m = ChainModel().mass_kg
    for s, r in zip(PLAN, recs):  # the closed form: spring positive throughout
        assert float(np.min(force(r.x))) > 900.0
        ph = s.omega * r.t
        closed = force(r.x) + C * s.A * s.omega * np.cos(ph) - m * s.omega**2 * s.A * np.sin(ph) * 1e-3
        on = r.t > 0  # (the first sample, t = 0, is the start: at rest)
        assert np.allclose(r.F[on], closed[on], rtol=0, atol=1e-6)
    assert sum(float(r.F.min()) < 0 for r in recs) == N_DIP  # ... and below zero in these
    p = tmp_path_factory.mktemp("dip") / "dip.csv"
    write_records(p, recs)
    return str(p)


def _warned(err: str, command: str) -> list[str]:
    head = f"chainid {command}: warning: "
    return [ln[len(head):] for ln in err.splitlines() if ln.startswith(head)]


def test_identify_warns_and_finds_the_damping(dip_csv, capsys):
    assert main(["identify", dip_csv, "--quiet", "--json", "-"]) == 0
    cap = capsys.readouterr()
    doc = json.loads(cap.out)
    assert [t["c_e"] for t in doc["tests"]] == pytest.approx([C] * len(PLAN), rel=1e-6)
    dips = [w for w in _warned(cap.err, "identify") if "the measured force dips below zero" in w]
    assert len(dips) == N_DIP and all(w in doc["warnings"] for w in dips)
    assert "the chain's spring cannot push, but a measured force can (damping c·ẋ" in dips[0]


def test_diagnose_runs_on_the_spring_force_model_with_the_warning(dip_csv, capsys):
    assert main(["diagnose", "--resamples", "0", dip_csv, "--holdout", "8", "--max-combo", "1", "--json", "-"]) == 0
    cap = capsys.readouterr()
    doc = json.loads(cap.out)
    dips = [w for w in _warned(cap.err, "diagnose") if "dips below zero" in w]
    assert len(dips) == N_DIP and all(w in doc["warnings"] for w in dips)
    assert doc["baseline"]["model"] == "chain[paper]"  # the chain kernel, not a linear stand-in


def test_allow_compression_silences_it(dip_csv, capsys):
    assert main(["identify", dip_csv, "--quiet", "--allow-compression", "--json", "-"]) == 0
    assert "dips below zero" not in capsys.readouterr().err


def test_a_record_without_mean_tension_is_refused():
    t = np.linspace(0.0, 1.0, 101)
    F = 500.0 * np.sin(2 * np.pi * 4 * t)  # swings about zero: mean 0, a part that pushes
    with pytest.raises(ValueError, match=r"force goes compressive .* its mean is no tension .* valid: mean F >= 1 % "
                                         r"of max \|F\| with a chain model\. Is F's sign flipped \(--scale F=-1\)\?"):
        check_data(Record("p", t, np.full(101, 1.0), F))
    check_data(Record("p", t, np.full(101, 1.0), F), allow_compression=True)


def test_x_below_zero_throughout_under_tension_warns():
    t = np.linspace(0.0, 1.0, 101)
    x = -1.0 + 0.2 * np.sin(2 * np.pi * 4 * t)
    F = 13000.0 + 500.0 * np.sin(2 * np.pi * 4 * t)
    with pytest.warns(RecordWarning, match=r"test 'neg': x < 0 throughout \(max x = -0\.8\d* mm\) under a mean "
                                           r"tension of 13000 N: a chain at x <= 0 is slack"):
        check_data(Record("neg", t, x, F))
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_data(Record("pos", t, x + 2.0, F))  # taut: no warning
        check_data(Record("neg", t, x, F), allow_compression=True)  # a linear spring: x_ref is arbitrary


def test_a_simulated_taut_chain_may_dip_but_a_slack_one_is_refused():
    simulate([TestSpec("taut", 20.0, 0.6, 0.3)], ChainModel(), C, n_cycles=3, samples_per_cycle=64)
    with pytest.raises(ValueError, match=r"test 'slack': the force goes compressive where the chain is slack"):
        simulate([TestSpec("slack", 20.0, 0.2, 0.5)], ChainModel(), C, n_cycles=3, samples_per_cycle=64)


def test_a_chain_that_touches_slack_where_its_inertia_pulls_is_simulated_not_refused():
    """x = 0.99·A + A·sin ωt (A = 0.2 mm, ω = 600 rad/s, c = 10.75 N·s/mm, m = 3.2 kg): at the bottom of the stroke
    the chain goes slack (x <= 0 where sin ωt <= −0.99), and there F = c·ẋ + m·ẍ >= m·A·ω²·0.99·1e-3 −
    c·A·ω·√(1 − 0.99²) = 228 − 182 = 46 N > 0 (by hand): nothing compressive where it is slack.  Elsewhere the
    damping takes F below zero while the chain is taut.  Only a compressive force where the chain is slack is the
    model's artefact; this record is simulated."""
    m = ChainModel()
    assert m.mass_kg == pytest.approx(3.2)
    rec = simulate([TestSpec("touch", 600.0, 0.198, 0.2)], m, 10.752, n_cycles=4, samples_per_cycle=256,
                   ramp_rate=None)[0]
    slack = np.asarray(m.force(rec.x)) <= 0
    assert slack.sum() > 10 and float(rec.F[slack].min()) > 46.0
    assert float(rec.F.min()) < -500.0


def _dip_warnings(caught) -> list[str]:
    return [str(w.message) for w in caught if issubclass(w.category, RecordWarning) and "dips below zero" in
            str(w.message)]


def test_each_layer_of_the_analysis_warns_once_per_record():
    """try_analyse checks the data, then analyses it (which validates it): the warning is said once, not per layer."""
    import warnings

    from chainid.records.validate import analyse_record, try_analyse, validate_record

    rec = simulate([PLAN[4]], ChainModel(), C, n_cycles=6, samples_per_cycle=128, ramp_rate=None)[0]
    assert float(rec.F.min()) < 0.0  # c·A·ω = 9 kN against F_k(0.3 mm) = 980 N: it dips (module docstring)
    for call in (lambda: try_analyse(rec), lambda: analyse_record(rec, allow_compression=False),
                 lambda: validate_record(rec), lambda: analyse_record(rec, (30.0, 0.6, 0.3), allow_compression=False)):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            call()
        assert len(_dip_warnings(caught)) == 1


def test_broadband_chain_records_are_checked_as_harmonic_ones_are():
    """A record that is no harmonic test goes to the time route, but its data are a chain's all the same: a dip
    below zero is warned about once, and a force without mean tension is refused (not diagnosed as a chain)."""
    import warnings

    from chainid.gap.diagnose import diagnose

    rng = np.random.default_rng(5)
    t = np.arange(0.0, 8.0, 1.0 / 400.0)
    recs = []
    for i in range(5):  # broadband x about 0.6 mm, |x − 0.6| <= 0.3 mm: F_k(x) >= 980 N; c·ẋ takes F below zero
        u = np.cumsum(rng.normal(size=(t.size, 6)), axis=0)[:, 0]
        u = np.convolve(u - u.mean(), np.ones(40) / 40.0, mode="same")
        x = 0.6 + 0.3 * u / np.max(np.abs(u))
        recs.append(Record(f"b{i}", t, x, force(x) + C * np.gradient(x, t)))
    dipping = {r.test for r in recs if float(r.F.min()) < 0.0}
    assert dipping  # the closed form's damping force exceeds the spring's somewhere
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        diagnose(recs, ["b4"], ChainModel(), uncertainty=False, quiet=True, max_combo=1, effects=["friction"])
    said = _dip_warnings(caught)
    assert sorted(w.split("'")[1] for w in said) == sorted(dipping)  # each dipping record once, and only those
    pushing = Record("push", t, recs[0].x, recs[0].F - float(np.mean(recs[0].F)))  # mean force zero: no tension
    with pytest.raises(ValueError, match=r"test 'push': force goes compressive .* its mean is no tension"):
        diagnose([pushing] + recs[1:], ["b4"], ChainModel(), uncertainty=False, quiet=True, max_combo=1)
