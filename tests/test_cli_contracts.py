"""CLI contracts pinned through the public functions and the command line (issue 20 §5, mutation survivors of
cli): identify's non-elliptic-loop note (a Coulomb loop's fundamental carries 8/π² of F_c's power), the model
file that ``--save-model`` writes (the last step of the explanation chain), the step files checked before the
diagnosis runs (``--max-combo`` + 1 of them), ``predict --plots`` panels (measured minus model over t and x), and
the parser module run as a script."""
from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from chainid.cli import main
from repo_paths import REPO as ROOT
from chainid.cli.model import plot_predictions, save_models, step_paths
from chainid.model.augmented import AugmentedModel
from chainid.model.base import LinearModel
from chainid.model.effects import parse_effect
from chainid.model.modelfile import load_model
from chainid.records.files import write_records
from chainid.records.simulate import TestSpec, simulate

SPRING = LinearModel(k=200.0, x_ref=0.0, mass=0.0)
PTS = [(2.0, 1.0, 0.5), (3.0, 1.0, 0.4), (1.5, 1.0, 0.3)]  # (ω rad/s, x0 mm, A mm)


def _mixed(tmp_path):
    """Tests v1-v3: viscous (c_e = 20 N·s/mm, an ellipse); f1-f3: Coulomb friction 300 N on a tiny c_e (six tests:
    enough for the damping law, so that the command succeeds)."""
    visc = simulate([TestSpec(f"v{i}", *p) for i, p in enumerate(PTS, 1)], SPRING, 20.0, n_cycles=6,
                    samples_per_cycle=256, noise_F=0.1, seed=1)
    fric = simulate([TestSpec(f"f{i}", *p) for i, p in enumerate(PTS, 1)], SPRING, 0.01, n_cycles=6,
                    samples_per_cycle=256, noise_F=0.1, seed=2, force_fn=parse_effect("friction:F_c=300", SPRING))
    p = tmp_path / "mixed.csv"
    write_records(p, visc + fric)
    return p


def test_identify_notes_only_the_non_elliptic_loops(tmp_path, capsys):
    """R²(F_c) < 0.97 marks a loop that is not an ellipse. A Coulomb force is a square wave in phase with ẋ, whose
    fundamental carries 8/π² = 0.81 of its power; a viscous loop's F_c is one harmonic (R² = 1)."""
    data = _mixed(tmp_path)
    out = tmp_path / "r.json"
    assert main(["identify", str(data), "--model", "linear", "--k", "200", "--x-ref", "0", "--mass", "0",
                 "--json", str(out), "--quiet"]) == 0
    stdout = capsys.readouterr().out
    r2 = {t["test"]: t["r2_c"] for t in json.loads(out.read_text())["tests"]}
    assert min(r2[f"v{i}"] for i in (1, 2, 3)) > 0.999
    assert [r2[f"f{i}"] for i in (1, 2, 3)] == pytest.approx([8 / math.pi**2] * 3, abs=0.03)
    notes = [ln for ln in stdout.splitlines() if ln.startswith("note: F_c of test(s)")]
    assert len(notes) == 1 and notes[0].startswith("note: F_c of test(s) f1, f2, f3 is far from one harmonic")
    # viscous records only: no note at all
    visc = tmp_path / "visc.csv"
    write_records(visc, simulate([TestSpec(f"v{i}", *p) for i, p in enumerate(PTS * 2, 1)], SPRING, 20.0,
                                 n_cycles=6, samples_per_cycle=256, noise_F=0.1, seed=1))
    assert main(["identify", str(visc), "--model", "linear", "--k", "200", "--x-ref", "0", "--mass", "0",
                 "--quiet"]) == 0
    assert "note: F_c" not in capsys.readouterr().out


def test_save_models_writes_the_last_step_and_every_step(tmp_path):
    """``--save-model M.toml`` is the chosen chain's model (the last step); ``--save-steps`` writes step i to
    ``M.stepi.toml``; every file carries the command line as provenance."""
    step0 = AugmentedModel(base=SPRING)
    step1 = AugmentedModel(base=SPRING, effects=[("friction", {"F_c": 150.0, "mu": 0.0})])
    step2 = AugmentedModel(base=SPRING, effects=[("friction", {"F_c": 150.0, "mu": 0.0}),
                                                 ("backlash", {"b": 0.02})])
    res = {"_models": [step0, step1, step2]}
    m = tmp_path / "m.toml"
    paths = save_models(res, str(m), True, "d.csv", ["diagnose", "d.csv", "--holdout", "3"], force=False)
    assert paths == [m, *step_paths(m, 3)]
    assert [p.name for p in paths[1:]] == ["m.step0.toml", "m.step1.toml", "m.step2.toml"]
    assert [n for n, _ in load_model(m).effects] == ["friction", "backlash"]
    assert [[n for n, _ in load_model(p).effects] for p in paths[1:]] == [[], ["friction"], ["friction", "backlash"]]
    assert "chainid diagnose d.csv --holdout 3" in m.read_text()
    m2 = tmp_path / "only.json"
    assert save_models(res, str(m2), False, "d.csv", ["x"], force=False) == [m2]
    assert [e["name"] for e in json.loads(m2.read_text())["effects"]] == ["friction", "backlash"]
    assert not (tmp_path / "only.step0.json").exists()


@pytest.mark.parametrize("max_combo", [1, 2, 3])
def test_diagnose_checks_every_step_file_before_it_runs(tmp_path, capsys, max_combo):
    """A chain of ``--max-combo`` K effects has K + 1 steps (baseline + K): the last step file M.stepK.toml is
    checked before anything else (here the data does not even exist, so any later check names the data)."""
    m = tmp_path / "m.toml"
    last = step_paths(m, max_combo + 1)[-1]
    assert last.name == f"m.step{max_combo}.toml"
    last.write_text("mine")
    rc = main(["diagnose", str(tmp_path / "missing.csv"), "--holdout", "1", "--max-combo", str(max_combo),
               "--save-model", str(m), "--save-steps"])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and last.name in err[0] and "missing.csv" not in err[0], err
    assert last.read_text() == "mine"
    # one step more is not checked: the data error comes first
    last.unlink()
    step_paths(m, max_combo + 2)[-1].write_text("mine")
    rc = main(["diagnose", str(tmp_path / "missing.csv"), "--holdout", "1", "--max-combo", str(max_combo),
               "--save-model", str(m), "--save-steps"])
    assert rc == 2 and "missing.csv" in capsys.readouterr().err


def test_predict_plots_show_the_residuals_over_t_and_x(tmp_path):
    import chainid.infra.fileio

    t = np.linspace(0.0, 2.0, 50)
    x = 1.0 + 0.5 * np.sin(np.pi * t)
    F, Fm, Fb = 200 * x + 3.0, 200 * x + 1.0, 200 * x
    figs = {}
    orig = chainid.infra.fileio.save_figure

    def spy(fig, path, *a, **k):
        figs[Path(path).name] = fig
        return orig(fig, path, *a, **k)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(chainid.infra.fileio, "save_figure", spy)
        out = plot_predictions({"a/1": (t, x, F, Fm, Fb)}, str(tmp_path / "p"))
    assert out == [tmp_path / "p" / "predict_a_1.png"] and out[0].stat().st_size > 5000
    ax = np.array(figs["predict_a_1.png"].axes).reshape(2, 2)
    panels = {(i, j): ax[i, j] for i in range(2) for j in range(2)}
    assert panels[1, 0].get_title() == "residual over time" and panels[1, 0].get_xlabel() == "t [s]"
    assert panels[1, 1].get_title() == "residual over x" and panels[1, 1].get_xlabel() == "x [mm]"
    assert panels[0, 1].get_title() == "force over x" and panels[0, 0].get_title() == "test a/1: force over time"
    base, model = panels[1, 0].lines
    np.testing.assert_allclose(base.get_ydata(), 3.0)  # measured - baseline
    np.testing.assert_allclose(model.get_ydata(), 2.0)  # measured - model
    np.testing.assert_allclose(base.get_xdata(), t)
    np.testing.assert_allclose(panels[1, 1].lines[1].get_xdata(), x)
    np.testing.assert_allclose(panels[1, 1].lines[1].get_ydata(), 2.0)
    assert [ln.get_label() for ln in panels[0, 1].lines] == ["measured", "baseline", "model"]
    assert [ln.get_label() for ln in panels[0, 0].lines] == ["measured", "baseline", "model"]
    for ln, y in zip(panels[0, 0].lines, (F, Fb, Fm)):
        np.testing.assert_allclose(ln.get_xdata(), t)
        np.testing.assert_allclose(ln.get_ydata(), y)


def test_parser_module_runs_as_a_script():
    res = subprocess.run([sys.executable, "-m", "chainid.cli.parser", "--help"], capture_output=True, text=True,
                         timeout=120, cwd=ROOT, env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"})
    assert res.returncode == 0 and res.stdout.startswith("usage:"), res.stderr


def _actions(parser, path=()):
    import argparse

    for a in parser._actions:
        if isinstance(a, argparse._SubParsersAction):
            for name, sub in a.choices.items():
                yield from _actions(sub, path + (name,))
        elif a.option_strings:
            yield path, a


def test_every_default_the_help_states_is_the_default():
    """The help text is the documented contract: "(default 5000)", "default 2e10", "ramp (default) | sine". Each
    number or word it names as the default must be the option's actual default."""
    import re

    from chainid.cli.parser import build_parser

    checked = []
    for path, a in _actions(build_parser()):
        h = a.help or ""
        m = re.search(r"default:? (-?[0-9][0-9.e+-]*)(?=[ ,)%]|$)", h)
        if m and a.default is not None and not isinstance(a.default, (list, bool)):
            assert float(a.default) == pytest.approx(float(m.group(1).rstrip(".")), rel=1e-12), (path, a.dest, h)
            checked.append((path, a.dest))
        m = re.search(r"(\w+) \(default\)", h)
        if m:
            assert a.default == m.group(1), (path, a.dest, h)
            checked.append((path, a.dest))
    names = {(p[-1], d) for p, d in checked}
    assert {("dynamics", "pretension"), ("dynamics", "max_work"), ("dynamics", "refine"), ("dynamics", "drive"),
            ("dynamics", "far_end"), ("dynamics", "scheme"), ("simulate", "max_memory")} <= names, sorted(names)
    assert len(checked) >= 15


def test_simulate_defaults_are_the_papers_test():
    """``simulate`` without options simulates the paper's test: the ramp rate of Eq. 25 (0.08973 mm/s), Table 1's
    plan, viscous damping; six cycles of 200 samples."""
    from chainid.cli.parser import build_parser

    args = build_parser().parse_args(["simulate", "out.csv"])
    assert args.ramp_rate == 0.08973 and args.plan == "paper" and args.law == "viscous"
    assert args.cycles == 6 and args.samples_per_cycle == 200
    assert args.noise_x == 0.0 and args.noise_F == 0.0 and args.seed == 0 and args.taper_cycles == 0.0
    args = build_parser().parse_args(["dynamics"])
    # 4000 links of 14x50 (pitch 50 mm) = 200 m; 400 masses; t_end 10 s; 4 modes
    assert (args.links, args.masses, args.t_end, args.modes, args.speed, args.t_ramp) == (4000, 400, 10.0, 4, 1000.0,
                                                                                          2.0)
    assert (args.kt, args.damping, args.coulomb, args.resistance, args.teeth) == (0.0, 0.0, 0.0, 0.0, 8)


def test_saved_model_records_the_command_line_and_the_data_hash(tmp_path):
    """The model file's provenance is the command as typed (``main(argv)``'s argv, not the process's) and the
    SHA-256 of the data file (hashlib on the bytes)."""
    import hashlib

    data, m = tmp_path / "d.csv", tmp_path / "m.toml"
    assert main(["simulate", str(data), "--cycles", "5", "--samples-per-cycle", "48", "--noise-F", "5"]) == 0
    argv = ["diagnose", str(data), "--holdout", "3,7", "--max-combo", "1", "--save-model", str(m)]
    assert main(argv) == 0
    prov = load_model(m).info["provenance"]
    assert prov["command"] == "chainid " + " ".join(argv)
    assert prov["data_sha256"] == hashlib.sha256(data.read_bytes()).hexdigest()
    assert prov["data_file"] == str(data)


@pytest.mark.parametrize("n, ok", [(-1, False), (0, True), (1, True)])
def test_skip_rows_below_zero_is_refused(tmp_path, capsys, n, ok):
    data = tmp_path / "d.csv"
    lines = ["# a header block of one line"] if n == 1 else []
    t = np.arange(0, 20, 0.05)
    lines += ["test,t,x,F"] + [f"1,{v:.3f},{2 + 0.2 * np.sin(v):.6f},{1000 + 200 * np.sin(v):.6f}" for v in t]
    data.write_text("\n".join(lines) + "\n")
    rc = main(["identify", str(data), "--model", "linear", "--k", "1000", "--quiet", "--skip-rows", str(n)])
    err = capsys.readouterr().err
    if ok:
        assert "--skip-rows" not in err
        assert rc == 2 and "only 1 test(s) identified" in err  # read and identified; too few for a law
    else:
        assert rc == 2 and "error: --skip-rows = -1 is invalid; valid range >= 0" in err


@pytest.mark.parametrize("stamp, note", [("1.11.1", True), (None, False), ("same", False)])
def test_generate_check_names_the_sympy_of_a_stale_file(tmp_path, capsys, monkeypatch, stamp, note):
    """``generate --check`` on a stale file names the SymPy that wrote it (the last word of its
    ``# generator: SymPy X`` header line) when that is not the SymPy this generator needs. The emitter is
    stubbed: the CLI's own reading of the header is under test."""
    from chainid.derive import emit

    stamp = emit.REQUIRED_SYMPY if stamp == "same" else stamp
    out = tmp_path / "gen"
    out.mkdir()
    head = ["# GENERATED FILE - DO NOT EDIT.", "# variant: paper"] + ([f"# generator: SymPy {stamp}"] if stamp else [])
    (out / "stiffness_paper.py").write_text("\n".join(head + ["x = 1"]) + "\n")
    monkeypatch.setattr(emit, "generate", lambda o, check=False: {"stiffness_paper.py": "stale", "b.py": "unchanged"})
    assert main(["generate", "--check", "--out", str(out)]) == 1
    err = capsys.readouterr().err.strip()
    assert err.startswith("generated/ is stale: stiffness_paper.py")
    extra = f" (the file was generated with SymPy {stamp}; this generator needs {emit.REQUIRED_SYMPY})"
    assert (extra in err) is note
    assert err.endswith("; run `chainid generate` and commit")


def test_a_missing_subcommand_module_is_skipped_a_broken_one_is_not(monkeypatch):
    """Optional subcommands live in their own modules: a module that is not there (a build without it) is left out
    of the parser; a module that is there but fails to import raises (a real bug must not hide)."""
    from chainid.cli import parser

    monkeypatch.setattr(parser, "SUBCOMMAND_MODULES", (*parser.SUBCOMMAND_MODULES, "chainid.cli.no_such_module"))
    p = parser.build_parser()
    assert p.parse_args(["stiffness", "--x", "2.2"]).command == "stiffness"
    real = parser.importlib.import_module

    def fake_import(name, *a, **k):
        if name == "chainid.cli.broken_sub":  # it exists, but a dependency of it is missing
            raise ModuleNotFoundError("No module named 'some_dependency'", name="some_dependency")
        return real(name, *a, **k)

    monkeypatch.setattr(parser.importlib, "import_module", fake_import)
    monkeypatch.setattr(parser, "SUBCOMMAND_MODULES", (*parser.SUBCOMMAND_MODULES, "chainid.cli.broken_sub"))
    with pytest.raises(ModuleNotFoundError, match="some_dependency"):
        parser.build_parser()


def test_convert_writes_the_canonical_file_and_refuses_a_bad_cell_in_one_line(tmp_path, capsys):
    src = tmp_path / "rig.csv"
    src.write_text("Time;Disp;Load\n0,0;2,2;11000\n0,1;2,3;11500,5\n0,2;2,25;11250\n")
    out = tmp_path / "o.csv"
    rc = main(["convert", str(src), "--to", str(out), "--columns", "t=Time,x=Disp,F=Load", "--delimiter", ";",
               "--decimal", ","])
    cap = capsys.readouterr()
    assert rc == 0, cap.err
    assert cap.out.strip() == f"wrote {out}: 1 test(s), 3 rows (test,t,x,F in s, mm, N)"
    # the contract is the value, not its spelling (pyarrow writes 0, polars 0.0): every number reads back exactly
    lines = out.read_text().splitlines()
    assert lines[0] == "test,t,x,F"
    rows = [ln.split(",") for ln in lines[1:]]
    assert [r[0] for r in rows] == ["rig"] * 3
    assert [[float(v) for v in r[1:]] for r in rows] == [[0.0, 2.2, 11000.0], [0.1, 2.3, 11500.5], [0.2, 2.25, 11250.0]]
    src.write_text("Time;Disp;Load\n0,0;2,2;11000\n0,1;abc;11500\n")
    rc = main(["convert", str(src), "--to", str(tmp_path / "o2.csv"), "--columns", "t=Time,x=Disp,F=Load",
               "--delimiter", ";", "--decimal", ","])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and err[0].startswith("chainid convert: error: ") and "abc" in err[0], err
    assert not (tmp_path / "o2.csv").exists()


def test_identify_progress_counts_every_test(tmp_path, capsys):
    data = _mixed(tmp_path)
    assert main(["identify", str(data), "--model", "linear", "--k", "200", "--x-ref", "0", "--mass", "0"]) == 0
    lines = [ln for ln in capsys.readouterr().err.splitlines() if "identifying test" in ln]
    assert lines == [f"[{i}/6] identifying test {t}" for i, t in enumerate(["v1", "v2", "v3", "f1", "f2", "f3"], 1)]


def test_identify_linear_without_k_fits_the_spring(tmp_path):
    """``--model linear`` without ``--k``: k is fitted on the steady cycles (the records' spring is 200 N/mm)."""
    data = _mixed(tmp_path)
    out = tmp_path / "r.json"
    assert main(["identify", str(data), "--model", "linear", "--mass", "0", "--json", str(out), "--quiet"]) == 0
    doc = json.loads(out.read_text())
    assert doc["model"]["name"].startswith("linear")
    ce = {t["test"]: t["c_e"] for t in doc["tests"]}
    assert [ce[f"v{i}"] for i in (1, 2, 3)] == pytest.approx([20.0] * 3, rel=0.02)  # viscous c_e through the fit
    out2 = tmp_path / "r2.json"
    assert main(["identify", str(data), "--model", "linear", "--k", "200", "--mass", "0", "--json", str(out2),
                 "--quiet"]) == 0
    assert json.loads(out2.read_text())["model"]["name"].startswith("linear")


def test_strict_makes_implausible_records_one_error_line(tmp_path, capsys):
    """x in µm read as mm (a 500 mm span on the 14x50 chain): a warning, and with ``--strict`` the one error
    line that lists it."""
    t = np.linspace(0, 20, 2000)
    p = tmp_path / "um.csv"
    from chainid.records.record import Record

    write_records(p, [Record("u", t, 2200 + 250 * np.sin(t), 11000 + 1000 * np.sin(t))])
    rc = main(["identify", str(p), "--quiet", "--strict"])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1, err
    assert err[0].startswith("chainid identify: error: --strict: implausible records: test 'u': x spans 500 mm")
    assert "; test 'u': " in err[0]  # the second warning, joined on the same line


def test_predict_table_lists_each_test_and_the_pooled_row(tmp_path, capsys):
    data, m, js = tmp_path / "d.csv", tmp_path / "m.toml", tmp_path / "p.json"
    assert main(["simulate", str(data), "--cycles", "5", "--samples-per-cycle", "48", "--noise-F", "5"]) == 0
    assert main(["diagnose", str(data), "--holdout", "3,7", "--max-combo", "1", "--save-model", str(m)]) == 0
    capsys.readouterr()
    assert main(["predict", str(m), str(data), "--tests", " 7, 3 ,", "--json", str(js)]) == 0
    out = capsys.readouterr().out.splitlines()
    doc = json.loads(js.read_text())
    assert sorted(t["test"] for t in doc["tests"]) == ["3", "7"]

    def f(v):
        return "-" if v is None else f"{v:.4g}"

    assert out[0].split() == ["test", "mode", "NRMSE", "base", "NRMSE", "model", "shrinkage"]
    for r, line in zip(doc["tests"], out[1:3]):
        assert line.split() == [r["test"], r["mode"], f(r["nrmse_baseline"]), f(r["nrmse_model"]), f(r["shrinkage"])]
    p = doc["pooled"]
    assert out[3].split()[:4] == ["pooled", f(p["nrmse_baseline"]), f(p["nrmse_model"]), f(p["shrinkage"])]
    assert out[3].endswith(f"(damping: {doc['damping_used']})") and out[4] == f"wrote {js}"


def test_default_generated_dir_is_the_packages_generated_folder():
    from chainid.cli.parser import default_generated_dir

    import chainid.generated.stiffness_paper as kernels

    d = default_generated_dir()
    # the folder the import system loads the kernels from (the repository's generated/ in an editable install,
    # site-packages/chainid/generated in a plain one, as CI installs it)
    assert d == Path(kernels.__file__).parent and (d / "stiffness_paper.py").is_file()


def test_benchmark_gap_seed_defaults_to_the_librarys():
    """``benchmark-gap`` without ``--seed`` runs :func:`chainid.gap.benchmark.grid.run_benchmark`'s default seed 0 (the
    README's quoted runs give no ``--seed``), and its help says so."""
    import inspect

    from chainid.cli.parser import build_parser
    from chainid.gap.benchmark.grid import run_benchmark

    args = build_parser().parse_args(["benchmark-gap"])
    assert args.seed == 0 == inspect.signature(run_benchmark).parameters["seed"].default


@pytest.mark.parametrize("first, second", [("-o", "--out"), ("--out", "-o")])
def test_an_option_repeated_under_its_other_spelling_names_both(first, second, capsys):
    """The parser's repeat guard (every single-valued option given once) on an option with two spellings: the
    error names the spelling given second and, in brackets, the first, in either order; the same spelling twice
    has no bracket.  (chainid's own options have one spelling each, so the guard is tried on a small parser.)"""
    import argparse

    from chainid.cli import parser as cli_parser

    p = argparse.ArgumentParser(prog="t")
    p.add_argument("-o", "--out")
    cli_parser._refuse_repeats(p)
    for argv, msg in (([first, "a", second, "b"], f"error: {second} given twice (also as {first}); give it once"),
                      ([second, "a", second, "b"], f"error: {second} given twice; give it once")):
        with pytest.raises(SystemExit) as exc:
            p.parse_args(argv)
        assert exc.value.code == 2
        assert capsys.readouterr().err.strip().splitlines()[-1] == f"t: {msg}"


def test_generate_check_on_fresh_files_exits_0(tmp_path, capsys, monkeypatch):
    """``generate --check`` exits 0 and says "fresh" with the source hash when every generated file is unchanged
    (the documented exit codes: 0 fresh, 1 stale, 2 a SymPy mismatch).  The emitter is stubbed: the CLI's exit code
    is under test."""
    from chainid.derive import emit

    out = tmp_path / "gen"
    out.mkdir()
    monkeypatch.setattr(emit, "generate", lambda o, check=False: {"a.py": "unchanged", "b.py": "unchanged"})
    monkeypatch.setattr(emit, "source_hash", lambda: "abc123")
    assert main(["generate", "--check", "--out", str(out)]) == 0
    cap = capsys.readouterr()
    assert cap.out.strip().splitlines()[-1] == "generated/ is fresh (source hash abc123)" and cap.err == ""


def test_audit_data_with_a_fitted_linear_spring_names_each_excluded_test(tmp_path, capsys):
    """``audit --data R --model linear`` without ``--k`` fits the spring on the records (as ``identify`` does) and
    audits Eq. 21 on the c_e identified through it: nine tests of a spring 200 N/mm and the law c_e = 2 ω² − 3 ω +
    50 A² − 10 A + 20 [N·s/mm] give the law's α back (rtol 1e-3); a tenth test with no oscillation is left out, one
    ``excluded test ID: reason`` line on stderr and in the JSON's ``excluded``.
    Bugs caught: the linear spring not fitted, the exclusion lines dropped, the data path not in the report."""
    from chainid.model.laws import PolynomialLaw
    from chainid.records.files import Record

    alpha = [2.0, -3.0, 50.0, -10.0, 20.0]
    plan = [TestSpec(f"T{i}", w, 2.0, A) for i, (w, A) in enumerate(
        [(w, A) for w in (1.0, 2.0, 4.0) for A in (0.1, 0.2, 0.3)])]
    recs = simulate(plan, SPRING, PolynomialLaw(alpha), n_cycles=4, samples_per_cycle=100, ramp_rate=None)
    t = np.linspace(0.0, 20.0, 2000)
    x = 2.0 + np.random.default_rng(4).normal(0.0, 1e-3, t.size)
    recs.append(Record("FLAT", t, x, 200.0 * x))
    data = write_records(tmp_path / "d.csv", recs)
    out = tmp_path / "a.json"
    assert main(["audit", "--data", str(data), "--model", "linear", "--mass", "0", "--json", str(out), "--quiet"]) == 0
    err = [ln for ln in capsys.readouterr().err.splitlines() if ln.startswith("excluded test")]
    assert len(err) == 1 and err[0].startswith("excluded test FLAT: ")
    doc = json.loads(out.read_text())
    assert [e["test"] for e in doc["excluded"]] == ["FLAT"] and len(doc["tests"]) == 9
    assert doc["data"] == str(data)
    np.testing.assert_allclose(doc["eq28_alpha"], alpha, rtol=1e-3)
