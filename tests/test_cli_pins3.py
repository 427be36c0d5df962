"""cli pins from the blind mutation run of seed 23 (issue 20 §5): what the commands hand to the library
(``identify --mass``, ``simulate --model M.toml --max-memory``, ``diagnose --model linear``, ``dynamics``' sine
drive default) and the grade error of ``chains``, each against a hand computation, the library's own default
or the documented message.  Units: mm, N, s, kg; memory GiB = 2^30 bytes.
"""
from __future__ import annotations

import json

import numpy as np
import pytest

from chainid.cli import main


class _Reached(Exception):
    """Raised by a stand-in once the command has handed over its arguments."""


@pytest.fixture(scope="module")
def chain_records(tmp_path_factory):
    from chainid.model.base import ChainModel
    from chainid.model.laws import ViscousLaw
    from chainid.records.files import write_records
    from chainid.records.simulate import paper_plan, simulate

    recs = simulate(paper_plan(), ChainModel(), ViscousLaw([300.0]), n_cycles=4, samples_per_cycle=100,
                    ramp_rate=None)
    return write_records(tmp_path_factory.mktemp("c") / "d.csv", recs)


def test_identify_mass_moves_the_in_phase_amplitude_by_m_omega2_a(chain_records, tmp_path, capsys):
    """``--mass m`` is the mass whose inertia m·ẍ is taken off F in the dissipated force F_c = F − m·ẍ − F_k
    (Eq. 17/20): the in-phase amplitude of F_c (``F_as``) changes by m·ω²·A·1e-3 N between ``--mass 0`` and
    ``--mass 4000`` (ẍ = −ω²(x − x0)), by hand per test, and each test reports the mass used.  Bug caught:
    ``--mass`` dropped when handing it to the identification (the chain's own 3.2 kg used)."""
    out = {}
    for m in (0, 4000):
        j = tmp_path / f"m{m}.json"
        assert main(["identify", str(chain_records), "--mass", str(m), "--law", "viscous", "--quiet",
                     "--json", str(j)]) == 0
        out[m] = {t["test"]: t for t in json.loads(j.read_text())["tests"]}
    capsys.readouterr()
    assert len(out[0]) == 9
    for test, a in out[0].items():
        b = out[4000][test]
        assert b["F_as"] - a["F_as"] == pytest.approx(4000 * a["omega"] ** 2 * a["A"] * 1e-3, rel=1e-3)
        assert (a["mass_kg"], b["mass_kg"]) == (0.0, 4000.0)


def test_simulate_model_file_hands_max_memory_in_bytes(tmp_path, monkeypatch):
    """``simulate --model M.toml --max-memory 0.5``: the limit reaches ``simulate_model`` as 0.5·2^30 bytes
    (GiB, the option's unit).  Bug caught: 1024³ → 1023³ on the model-file path."""
    import chainid.records.simulate as sim
    from chainid.model.augmented import AugmentedModel
    from chainid.model.base import LinearModel
    from chainid.model.modelfile import save_model
    from chainid.model.timedamping import Damping

    mf = tmp_path / "m.toml"
    save_model(AugmentedModel(LinearModel(1e4, 0.0), [], Damping("viscous", {"c": 1.0}), 0.0, 0.0), mf)
    seen = {}

    def stand_in(plan, model, **kw):  # noqa: ANN001
        seen.update(kw)
        raise _Reached

    monkeypatch.setattr(sim, "simulate_model", stand_in)
    with pytest.raises(_Reached):
        main(["simulate", str(tmp_path / "r.csv"), "--model", str(mf), "--max-memory", "0.5"])
    assert seen["max_memory"] == 0.5 * 2**30


def test_diagnose_model_linear_hands_no_chain_model(chain_records, monkeypatch):
    """``diagnose --model linear`` diagnoses against a linear spring fitted to the data: the library is given no
    chain model (None); the default hands it the chain's.  Bug caught: ``== "linear"`` → ``> "linear"`` (the
    chain model used for --model linear)."""
    import importlib

    from chainid.model.base import ChainModel

    seen = []

    def stand_in(recs, holdout, model, **kw):  # noqa: ANN001
        seen.append(model)
        raise _Reached

    monkeypatch.setattr(importlib.import_module("chainid.gap.diagnose"), "diagnose", stand_in)
    for extra in (["--model", "linear"], []):
        with pytest.raises(_Reached):
            main(["diagnose", str(chain_records), "--holdout", "3,7", "--quiet", *extra])
    assert seen[0] is None and isinstance(seen[1], ChainModel)


def test_dynamics_sine_drive_defaults_to_the_librarys_omega(monkeypatch):
    """``dynamics --drive sine --amplitude 5`` without ``--omega`` builds the drive with ω = 1 rad/s, the
    library's default (``Drive("sine").omega``) and the option's help.  Bug caught: the option's default 1 → 2."""
    import chainid.dynamics as dyn
    from chainid.cli.parser import build_parser
    from chainid.dynamics import Drive

    seen = {}

    def stand_in(line, drive, t_end, **kw):  # noqa: ANN001
        seen["drive"] = drive
        raise _Reached

    monkeypatch.setattr(dyn, "simulate", stand_in)
    with pytest.raises(_Reached):
        main(["dynamics", "--links", "100", "--masses", "10", "--pretension", "1000", "--t-end", "0.1", "--quiet",
              "--drive", "sine", "--amplitude", "5"])
    assert seen["drive"].omega == Drive("sine").omega == 1.0
    sub = next(a for a in build_parser()._subparsers._group_actions[0].choices.items() if a[0] == "dynamics")[1]
    assert "(default 1)" in next(a.help for a in sub._actions if "--omega" in a.option_strings)


def test_chains_grade_of_another_kind_names_the_first_family_given(capsys):
    """``chains --grade C --family studless studlink``: C (a DIN 22252 grade) fits neither; the error names the
    first family given and its grades (R3 … R5), in one line.  Bug caught: the last family named instead."""
    assert main(["chains", "--grade", "C", "--family", "studless", "studlink"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["chainid chains: error: --grade 'C' does not apply to studless chain: valid grades are "
                   "['R3', 'R3S', 'R4', 'R4S', 'R5']"]


def test_predict_plots_one_figure_per_chosen_test_with_the_measured_force(tmp_path, capsys, monkeypatch):
    """``predict M D --tests 3,7 --plots DIR`` (a fast stand-in for the slow augmented-model file): one PNG per
    chosen test, ``DIR/predict_<test>.png`` as the docs name it, each announced with "wrote"; the figure's first
    panel draws the record's own force samples over their times (read back from the CSV; the steady cycles
    predicted, over 2 periods at least), and the residual-over-x panel
    is there.  Bug caught (seed 24): the plotting loop emptied (``for p in []``: nothing written, exit 0)."""
    from model_texts import SPECIMEN

    import chainid.infra.fileio as fileio
    from chainid.records.files import read_records

    data, model, figs = tmp_path / "d.csv", tmp_path / "m.toml", tmp_path / "fig"
    assert main(["simulate", str(data), "--cycles", "5", "--samples-per-cycle", "48"]) == 0
    model.write_text(SPECIMEN)
    seen = {}
    real = fileio.save_figure

    def spy(fig, path, **kw):
        seen[path.name] = [(a.get_title(), [ln.get_xydata().copy() for ln in a.get_lines()]) for a in fig.axes]
        return real(fig, path, **kw)

    monkeypatch.setattr(fileio, "save_figure", spy)
    capsys.readouterr()
    assert main(["predict", str(model), str(data), "--tests", "3,7", "--plots", str(figs)]) == 0
    out = capsys.readouterr().out
    assert sorted(p.name for p in figs.iterdir()) == ["predict_3.png", "predict_7.png"]
    for name in ("predict_3.png", "predict_7.png"):
        assert f"wrote {figs / name}" in out
        assert (figs / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    rec = {r.test: r for r in read_records(data)}["3"]
    title, lines = seen["predict_3.png"][0]
    assert title == "test 3: force over time"
    t_plot, F_plot = lines[0][:, 0], lines[0][:, 1]
    i = np.searchsorted(rec.t, t_plot)  # the steady part predicted: a run of the record's own samples
    assert np.array_equal(rec.t[i], t_plot) and np.array_equal(rec.F[i], F_plot) and np.all(np.diff(i) == 1)
    assert t_plot[-1] - t_plot[0] >= 2 * (2 * np.pi / 1.885)  # at least 2 periods of test 3 (1.885 rad/s)
    assert [a[0] for a in seen["predict_3.png"]] == ["test 3: force over time", "force over x",
                                                      "residual over time", "residual over x"]


@pytest.fixture(scope="module")
def six_long_ids(tmp_path_factory):
    """Six simulated tests of the paper plan (exactly MIN_TESTS = 6) under ids longer than any table header."""
    from chainid.model.base import ChainModel
    from chainid.model.laws import ViscousLaw
    from chainid.records.files import write_records
    from chainid.records.simulate import paper_plan, simulate

    recs = simulate(paper_plan()[:6], ChainModel(), ViscousLaw([300.0]), n_cycles=4, samples_per_cycle=100,
                    ramp_rate=None)
    for i, r in enumerate(recs):
        r.test = f"shaker_run_2026_11_24_{i:03d}"
    return write_records(tmp_path_factory.mktemp("six") / "d.csv", recs)


def test_identify_plots_of_six_tests_check_the_surface_figure_before_any_work(six_long_ids, tmp_path, capsys):
    """Six tests (MIN_TESTS, the fewest a damping law is fitted to) also draw ``damping_surface.png``: a user's
    file of that name in the ``--plots`` folder is refused without ``--force`` before any test is identified (no
    "identifying test" progress line), and left byte for byte.  Bug caught (seed 25): the surface counted only
    above six tests (``>= MIN_TESTS`` → ``> MIN_TESTS``), so the check came after the work."""
    figs = tmp_path / "figs"
    figs.mkdir()
    (figs / "damping_surface.png").write_bytes(b"mine")
    capsys.readouterr()
    assert main(["identify", str(six_long_ids), "--plots", str(figs)]) == 2
    err = capsys.readouterr().err
    assert "damping_surface.png" in err and "identifying test" not in err
    assert (figs / "damping_surface.png").read_bytes() == b"mine"


def test_identify_table_columns_widen_to_their_longest_cell(six_long_ids, capsys):
    """The per-test table is right-aligned on the longest of header and cells: with 26-character test ids
    (longer than the header "test") every line of the table has the length of the header line, and each id
    ends where the header "test" ends.  Bug caught (seed 25): widths taken from the headers alone (``if cells``
    → ``if not cells``: the rows run past the header)."""
    capsys.readouterr()
    assert main(["identify", str(six_long_ids), "--quiet"]) == 0
    lines = capsys.readouterr().out.splitlines()
    i = next(k for k, ln in enumerate(lines) if ln.lstrip().startswith("test ") and "omega rad/s" in ln)
    head = lines[i]
    rows = lines[i + 2:i + 8]  # the six rows under the dashes
    assert head.index("test") + 4 == len("shaker_run_2026_11_24_000")
    for ln in [lines[i + 1]] + rows:
        assert len(ln) == len(head), ln
    assert all(ln.startswith("shaker_run_2026_11_24_") for ln in rows)


def test_step_files_are_outputs_only_with_save_steps(tmp_path):
    """``check_io``: the step files ``M.step0.toml`` … are outputs of the run only with ``--save-steps``; an input
    named like one is refused then (naming ``--save-steps``), and accepted without it.  Bug caught (seed 25):
    ``save_steps and save_model`` → ``or`` (the step files counted as outputs of every ``--save-model`` run)."""
    from argparse import Namespace

    from chainid.cli.common import check_io

    data = tmp_path / "m.step0.toml"
    data.write_text("x")
    check_io(Namespace(data=str(data), save_model=str(tmp_path / "m.toml"), save_steps=False))
    with pytest.raises(ValueError, match="--save-steps"):
        check_io(Namespace(data=str(data), save_model=str(tmp_path / "m.toml"), save_steps=True))
