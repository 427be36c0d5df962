"""``chainid benchmark-gap --summary FILE``: an earlier run's summary computed again from its JSON rows.

References: the summary functions of each generator applied to the same hand-made rows (the text must be theirs,
under a header naming the generator and the case count), and the files a run cannot have written (refused with
the file and what is wrong)."""
from __future__ import annotations

import copy
import json

import pytest

from chainid.cli import main
from chainid.gap.benchmark import odescore as sc
from chainid.gap.benchmark.report import format_summary, summarise
from chainid.gap.benchmark.resummary import load_runs, summary_text


def _sim_row(verdict, truth, true_params, params, ci, excitation="harmonic", family="single"):
    return {"excitation": excitation, "family": family, "truth": truth, "verdict": verdict, "snr": 10.0,
            "shrinkage": 0.9, "confounded": [], "seconds": 1.0, "resamples": 50, "true_params": true_params,
            "params": params, "params_ci90": ci, "open_world": {}, "chain": "14x50", "plan": "grid3x3",
            "noise": 0.01, "levels": [1.0], "seed": 1}


SIM = [_sim_row("friction", ["friction"], {"friction.F_c": 95.0}, {"friction.F_c": 100.0}, {"friction.F_c": [90, 110]}),
       _sim_row("friction", ["friction"], {"friction.F_c": 80.0}, {"friction.F_c": 100.0}, {"friction.F_c": [90, 110]},
                excitation="random"),
       _sim_row("none", [], {}, {}, {}, family="control")]


def _ode_row(family, effects, verdict, shrinkage=None, snr=10.0):
    return {"world": "ode", "family": family, "effects": effects, "verdict": verdict, "shrinkage": shrinkage,
            "snr": snr, "base": "chain14", "excitation": "noise", "seconds": 1.0, "sim_seconds": 0.5,
            "score": {"right": None}}  # a stale score: the summary scores again


ODE = [_ode_row("single", {"friction": 1.0}, "friction", 0.8), _ode_row("single", {"friction": 1.0}, "slack", 0.8),
       _ode_row("single", {"friction": 1.0}, "friction+slack", 0.8), _ode_row("control", {}, "none", None, 0.1)]


def _write(path, data):
    path.write_text(json.dumps(data))
    return path


def test_sim_summary_is_the_runs_own_text(tmp_path):
    f = _write(tmp_path / "sim.json", {"n_cases": 3, "rows": copy.deepcopy(SIM)})
    text = summary_text(f)
    assert text.startswith("== generator sim (3 cases, from sim.json) ==\n")
    assert text.split("\n", 1)[1] == format_summary(summarise(copy.deepcopy(SIM)))
    assert "of which on the time route:" in text  # the route split of the coverage table


def test_ode_rows_are_scored_again(tmp_path):
    f = _write(tmp_path / "ode.json", {"rows": copy.deepcopy(ODE)})
    text = summary_text(f)
    assert text.startswith("== generator ode (4 cases, from ode.json) ==\n")
    rows = copy.deepcopy(ODE)
    for r in rows:
        r["score"] = sc.score_row(r)
    assert text.split("\n", 1)[1] == sc.format_table(sc.summarise(rows))
    assert "67 % (2/3)" in text  # friction, friction+slack right; slack wrong


def test_both_generators_are_printed_apart(tmp_path):
    f = _write(tmp_path / "both.json", {"generator": "both", "sim": {"rows": SIM}, "ode": {"rows": ODE}})
    assert set(load_runs(f)) == {"sim", "ode"}
    text = summary_text(f)
    assert "== generator sim (3 cases" in text and "== generator ode (4 cases" in text


@pytest.mark.parametrize("content, message", [
    (None, r"no such file"),
    ("not json", r"not JSON"),
    ({}, r"no 'rows' \(a non-empty list of cases\) in it: not the JSON of a chainid benchmark-gap run"),
    ({"rows": []}, r"no 'rows'"),
    ({"rows": [1, 2]}, r"'rows' holds an entry that is not a case"),
    ({"generator": "both", "sim": {"rows": SIM}}, r"part 'ode': no 'rows'"),
])
def test_a_file_no_run_wrote_is_refused_naming_it(tmp_path, content, message):
    f = tmp_path / "x.json"
    if content is not None:
        f.write_text(content if isinstance(content, str) else json.dumps(content))
    with pytest.raises(ValueError, match=rf"--summary '.*x\.json'(, part '\w+')?: .*{message}|{message}"):
        load_runs(f)


def test_cli_prints_the_summary_and_refuses_a_bad_file(tmp_path, capsys):
    f = _write(tmp_path / "sim.json", {"rows": SIM})
    assert main(["benchmark-gap", "--summary", str(f)]) == 0
    assert "== generator sim (3 cases, from sim.json) ==" in capsys.readouterr().out
    assert main(["benchmark-gap", "--summary", str(tmp_path / "none.json")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("chainid benchmark-gap: error: --summary") and "no such file" in err


def test_several_runs_are_pooled_as_one_run_of_them_all(tmp_path):
    """A harmonic run and a time-route run given together: the summary is the one of a file holding both runs'
    rows (the coverage table per route and pooled), under one header naming both files."""
    harm = _write(tmp_path / "h.json", {"rows": copy.deepcopy(SIM[:1] + SIM[2:])})
    time_route = _write(tmp_path / "t.json", {"rows": copy.deepcopy(SIM[1:2])})
    text = summary_text([harm, time_route])
    assert text.startswith("== generator sim (3 cases, from h.json + t.json) ==\n")
    rows = copy.deepcopy(SIM[:1] + SIM[2:] + SIM[1:2])
    assert text.split("\n", 1)[1] == format_summary(summarise(rows))
    assert summary_text([harm]) == summary_text(harm)


def test_a_run_named_twice_is_refused(tmp_path, capsys):
    f = _write(tmp_path / "sim.json", {"rows": SIM})
    with pytest.raises(ValueError, match=r"the same file as .*sim\.json'; each run's cases count once"):
        summary_text([f, tmp_path / "." / "sim.json"])
    other = _write(tmp_path / "ode.json", {"rows": ODE})
    assert main(["benchmark-gap", "--summary", str(f), str(other)]) == 0
    out = capsys.readouterr().out
    assert "== generator sim (3 cases, from sim.json) ==" in out  # each generator names the files of its rows
    assert "== generator ode (4 cases, from ode.json) ==" in out
    assert main(["benchmark-gap", "--summary", str(f), str(f)]) == 2
    assert "each run's cases count once" in capsys.readouterr().err


def test_a_case_in_two_files_counts_once_and_a_different_result_is_refused(tmp_path):
    """The same case (family, truth, conditions, seed, true parameters) with the same result in two files is one
    simulation run twice (runs at neighbouring --seed share their controls; a copy shares everything): it counts
    once and the header says how many were repeats.  The same case with another result is runs of two versions:
    refused, naming both files.  Another true parameter (a mismatch case's scale) is another case."""
    f = _write(tmp_path / "sim.json", {"rows": SIM})
    copy_of_f = _write(tmp_path / "copy.json", {"rows": [SIM[1], SIM[0] | {"seed": 2}]})
    text = summary_text([f, copy_of_f])
    assert text.startswith("== generator sim (4 cases, from sim.json + copy.json; 1 repeated case(s) counted "
                           "once) ==\n")
    assert text.split("\n", 1)[1] == format_summary(summarise(copy.deepcopy(SIM + [SIM[0] | {"seed": 2}])))
    other = _write(tmp_path / "other.json", {"rows": [SIM[1] | {"verdict": "slack"}]})
    with pytest.raises(ValueError, match=r"--summary '.*other\.json': its case .* is also in '.*sim\.json' with "
                                         r"another result"):
        summary_text([f, other])
    scaled = _write(tmp_path / "scaled.json", {"rows": [SIM[1] | {"true_params": {"friction.F_c": 70.0}}]})
    assert summary_text([f, scaled]).startswith("== generator sim (4 cases, from sim.json + scaled.json) ==\n")


def test_a_case_that_raised_counts_as_a_miss_as_in_the_run(tmp_path):
    """A case that raised is a row with snr inf (a miss, whatever its strength); JSON has no infinity, so the run's
    file holds null there (as a real run's did).  The summary from the file is the run's own: the error row counts
    as a non-harmonic single case missed (1 of 2 right: 50 %), not a traceback."""
    err = {**_sim_row("error: ValueError: boom", ["deadband"], {}, None, {}, excitation="startup"), "snr": None}
    rows = copy.deepcopy(SIM) + [err]
    f = _write(tmp_path / "sim.json", {"rows": rows})
    text = summary_text(f)
    in_run = copy.deepcopy(rows)
    in_run[-1]["snr"] = float("inf")
    assert text.split("\n", 1)[1] == format_summary(summarise(in_run))
    nh = summarise(copy.deepcopy(in_run))["nonharmonic"]
    assert nh["single_right_rate"] == pytest.approx(0.5) and nh["errors"]
