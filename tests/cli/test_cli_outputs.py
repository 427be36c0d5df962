"""Output paths of every command: checked before the work, one error line and rc 2, atomic, SIGINT → 130."""
from __future__ import annotations

import json
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from chainid import cli
from repo_paths import REPO



def _run(capsys, argv):
    rc = cli.main([str(a) for a in argv])
    cap = capsys.readouterr()
    return rc, cap.out, cap.err


def _one_error_line(err: str) -> str:
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1, err
    assert "Traceback" not in err
    return lines[0]


@pytest.fixture
def no_work(monkeypatch):
    """Make the expensive part of each command fail loudly: the target check must come first."""
    import chainid.derive.verify as verify
    import chainid.gap.benchmark.grid as bench
    import chainid.records.files as records

    def boom(*a, **k):
        raise AssertionError("the work started before the output target was checked")

    monkeypatch.setattr(verify, "run_checks", boom)
    monkeypatch.setattr(bench, "grid", boom)
    monkeypatch.setattr(records, "read_records", boom)


@pytest.mark.parametrize("argv, expect", [
    (["stiffness", "--x", "1", "--json", "{dir}"], "is a directory"),
    (["audit", "--json", "{dir}"], "is a directory"),
    (["verify", "--json", "{dir}"], "is a directory"),
    (["benchmark-gap", "--small", "--json", "{dir}"], "is a directory"),
    (["simulate", "{dir}"], "is a directory"),
    (["identify", "{data}", "--json", "{dir}"], "is a directory"),
    (["identify", "{data}", "--plots", "{file}"], "is a file"),
    (["identify", "{data}", "--write-side", "{dir}"], "is a directory"),
    (["diagnose", "--resamples", "0", "{data}", "--holdout", "1", "--json", "{dir}"], "is a directory"),
    (["diagnose", "--resamples", "0", "{data}", "--holdout", "1", "--plots", "{file}"], "is a file"),
    (["generate", "--out", "{file}"], "is a file"),
    (["report", "--out", "{file}"], "is a file"),
    (["stiffness", "--x", "1", "--json", "{file}/x.json"], "not a directory"),
    (["verify", "--json", "{file}"], "already exists"),
    (["benchmark-gap", "--small", "--json", "{file}"], "already exists"),
    (["stiffness", "--x", "1", "--json", "/proc/chainid-test.json"], "not writable"),
    (["simulate", "/proc/chainid-test.csv"], "not writable"),
])
def test_bad_output_target_is_one_line_rc2_before_work(tmp_path, capsys, no_work, argv, expect):
    if "/proc" in " ".join(argv) and not Path("/proc/self").is_dir():
        pytest.skip("needs Linux /proc")
    (tmp_path / "dir").mkdir()
    (tmp_path / "file").write_text("user data\n")
    (tmp_path / "data.csv").write_text("test,t,x,F\n")
    sub = {"{dir}": tmp_path / "dir", "{file}": tmp_path / "file", "{data}": tmp_path / "data.csv"}
    args = []
    for a in argv:
        for k, v in sub.items():
            a = a.replace(k, str(v))
        args.append(a)
    rc, _, err = _run(capsys, args)
    assert rc == 2
    assert expect in _one_error_line(err)
    assert (tmp_path / "file").read_text() == "user data\n"
    assert list((tmp_path / "dir").iterdir()) == []


def test_stiffness_json_is_strict_with_null_for_non_finite(tmp_path, capsys, monkeypatch):
    import numpy as np

    from chainid.model import kernels

    monkeypatch.setattr(kernels, "force", lambda x, *a, **k: np.full(np.shape(x), np.nan))
    monkeypatch.setattr(kernels, "stiffness", lambda x, *a, **k: np.full(np.shape(x), np.inf))
    out = tmp_path / "s.json"
    rc, _, _ = _run(capsys, ["stiffness", "--x", "1", "2", "--json", out])
    assert rc == 0
    text = out.read_text()
    assert "NaN" not in text and "Infinity" not in text
    doc = json.loads(text, parse_constant=lambda tok: pytest.fail(f"non-JSON token {tok}"))
    assert [p["F_k_N"] for p in doc["points"]] == [None, None]
    assert [p["k_e_N_per_mm"] for p in doc["points"]] == [None, None]
    assert [p["x_mm"] for p in doc["points"]] == [1.0, 2.0]


# -- simulate: options validated like the reader validates files -------------------------------------------

@pytest.mark.parametrize("extra, plan, field", [
    (["--params", "nan"], None, "--params"),
    (["--params", "1,inf"], None, "--params"),
    (["--noise-x", "nan"], None, "--noise-x"),
    (["--noise-F", "-1"], None, "--noise-F"),
    (["--mass", "-1"], None, "--mass"),
    (["--cycles", "nan"], None, "--cycles"),
    (["--taper-cycles", "nan"], None, "--taper-cycles"),
    (["--max-memory", "0"], None, "--max-memory"),
    ([], "test,omega,x0,A\n1,2,2.2,0.3\n1,3,2.2,0.3\n", "repeated"),
    ([], "test,omega,x0,A\n1,2,0.2,0.3\n", "compressive"),
])
def test_simulate_refuses_bad_options_and_writes_nothing(tmp_path, capsys, extra, plan, field):
    argv = ["simulate", tmp_path / "out.csv", "--samples-per-cycle", "32", "--ramp-rate", "0"]
    if "--cycles" not in extra:  # (an option given twice is refused by the parser itself)
        argv += ["--cycles", "3"]
    if plan is not None:
        (tmp_path / "plan.csv").write_text(plan)
        argv += ["--plan", tmp_path / "plan.csv"]
    rc, _, err = _run(capsys, argv + extra)
    assert rc == 2
    line = _one_error_line(err)
    assert field in line and ("valid range" in line or "unique" in line)
    assert not (tmp_path / "out.csv").exists()


def test_simulate_compressive_plan_is_fine_with_a_linear_model(tmp_path, capsys):
    from chainid.records.files import read_records

    (tmp_path / "plan.csv").write_text("test,omega,x0,A\n1,2,0.2,0.3\n")
    rc, _, _ = _run(capsys, ["simulate", tmp_path / "out.csv", "--plan", tmp_path / "plan.csv", "--model", "linear",
                             "--k", "1000", "--ramp-rate", "0", "--cycles", "3"])
    assert rc == 0
    (rec,) = read_records(tmp_path / "out.csv", allow_compression=True)
    assert rec.F.min() < 0  # F = 1000 (x) + c_e xdot swings below zero: allowed for a spring


def test_simulate_memory_estimate_matches_the_allocation():
    """n_samples is the size simulate_test allocates: (x0/ramp + cycles·2π/ω) / (2π/(ω·spc)), hand-computed."""
    import math

    from chainid.model.base import model_for
    from chainid.records.simulate import TestSpec, n_samples, simulate_test

    spec = TestSpec("1", 2.0, 2.2, 0.3)
    n_hand = (2.2 / 0.08973 + 6 * math.pi) / (math.pi / 200)  # = 2760.6...
    assert n_samples(spec, 6, 200, 0.08973) == pytest.approx(n_hand, rel=1e-12)
    rec = simulate_test(spec, model_for(), 100.0, n_cycles=6, samples_per_cycle=200, ramp_rate=0.08973)
    assert rec.t.size == round(n_hand)


def test_simulate_refuses_a_huge_plan_fast_and_max_memory_raises_the_limit(tmp_path, capsys, monkeypatch):
    import chainid.records.simulate as sim

    real = sim.simulate_test

    def guarded(spec, *a, **k):  # a regression must fail here, not allocate 160 GiB
        assert spec.omega < 1e5, "simulate started a test beyond the memory limit"
        return real(spec, *a, **k)

    monkeypatch.setattr(sim, "simulate_test", guarded)
    (tmp_path / "fast.csv").write_text("test,omega,x0,A\n1,1e6,2.2,0.3\n")
    rc, _, err = _run(capsys, ["simulate", tmp_path / "a.csv", "--plan", tmp_path / "fast.csv"])
    assert rc == 2
    line = _one_error_line(err)
    # 7.8e8 samples: 2.2/0.08973 s of ramp at dt = 2π/(1e6·200) s
    assert "7.804e+08 samples" in line and "--max-memory" in line and "GiB" in line
    assert not (tmp_path / "a.csv").exists()
    # the limit is the option: 1 test of 3·64 samples (no ramp) needs ~ 192·(200+24) B = 43 kB
    (tmp_path / "one.csv").write_text("test,omega,x0,A\n1,2,2.2,0.3\n")
    small = ["--plan", tmp_path / "one.csv", "--ramp-rate", "0", "--cycles", "3", "--samples-per-cycle", "64"]
    rc, _, err = _run(capsys, ["simulate", tmp_path / "b.csv", *small, "--max-memory", str(40e3 / 1024**3)])
    assert rc == 2 and "over the limit" in err
    rc, _, _ = _run(capsys, ["simulate", tmp_path / "b.csv", *small, "--max-memory", str(50e3 / 1024**3)])
    assert rc == 0 and (tmp_path / "b.csv").exists()


# -- identify --plots: one file per test id, no silent overwrite ----------------------------------------------

@pytest.mark.slow
def test_identify_plots_names_do_not_collide_and_need_force(tmp_path, capsys):
    from chainid.model.base import model_for
    from chainid.records.files import write_records
    from chainid.records.simulate import TestSpec, simulate

    ids = ["T 1", "T_1", "T/1", "T-1", "t 1", "T.1"]
    plan = [TestSpec(i, w, 2.2, A) for i, (w, A) in zip(ids, [(1, .2), (2, .2), (3, .3), (1, .3), (2, .4), (3, .4)])]
    recs = simulate(plan, model_for(), 300.0, n_cycles=4, samples_per_cycle=64, noise_F=1.0, seed=1)
    data = write_records(tmp_path / "d.csv", recs)
    plots = tmp_path / "plots"
    rc, out, _ = _run(capsys, ["identify", data, "--plots", plots, "--quiet"])
    assert rc == 0
    files = sorted(p.name for p in plots.iterdir())
    assert len(files) == len(ids) + 1  # a loop per test and the damping surface
    assert f"wrote {len(files)} plot(s)" in out
    before = {p.name: p.read_bytes() for p in plots.iterdir()}
    rc, _, err = _run(capsys, ["identify", data, "--plots", plots, "--quiet"])
    assert rc == 2 and "already exists" in _one_error_line(err)
    assert {p.name: p.read_bytes() for p in plots.iterdir()} == before


# -- SIGINT with the rows written, before the commit: rc 130, one line, no partial output -----------------------------

_INTERRUPTED_WRITER = textwrap.dedent("""
    import contextlib, os, signal, sys
    import chainid.infra.fileio as fio
    # a process started with SIGINT ignored (a runner in the background of a non-interactive shell) gets no
    # KeyboardInterrupt handler from Python: install it, as a terminal's program has it
    signal.signal(signal.SIGINT, signal.default_int_handler)
    _orig = fio.atomic_open

    @contextlib.contextmanager
    def interrupted_before_commit(path, *a, **k):
        with _orig(path, *a, **k) as fh:
            yield fh
            # every row is in the temporary file and the commit is next: SIGINT now, from Python code in the
            # main thread, so the handler runs at once (a signal sent from inside the CSV writer's callback was
            # seen by polars' own handler only when its query had not finished yet: a race under load)
            assert fh.tell() > 0
            os.kill(os.getpid(), signal.SIGINT)  # the handler raises KeyboardInterrupt here

    fio.atomic_open = interrupted_before_commit
    from chainid.cli import main
    sys.exit(main(sys.argv[1:]))
""")


@pytest.mark.slow
@pytest.mark.parametrize("existing", [None, "old content\n"])
def test_sigint_before_the_commit_exits_130_and_leaves_no_partial_output(tmp_path, existing):
    import os

    out = tmp_path / "out.csv"
    if existing is not None:
        out.write_text(existing)
    env = dict(os.environ, PYTHONPATH=str(REPO) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    p = subprocess.run([sys.executable, "-c", _INTERRUPTED_WRITER, "simulate", str(out), "--force", "--ramp-rate", "0",
                        "--cycles", "4", "--samples-per-cycle", "64"],
                       capture_output=True, text=True, env=env, timeout=120)
    assert p.returncode == 130, p.stderr
    assert [ln for ln in p.stderr.splitlines() if ln.strip()] == [
        "chainid simulate: interrupted; no partial output was written"]
    if existing is None:
        assert list(tmp_path.iterdir()) == []
    else:
        assert out.read_text() == existing
        assert sorted(x.name for x in tmp_path.iterdir()) == ["out.csv"]


# -- report: validate first, build beside the target, replace only its own files -------------------------------

@pytest.fixture
def fake_steps(monkeypatch):
    """Fast stand-ins for the report steps; ``state['figs']`` names the figures step 2 writes."""
    from chainid.report import build as report

    state = {"figs": ["a.png"], "fail": None}

    def verification(folder, say):
        report.dump_json(folder, "verify.json", {"ok": True})
        return "## 1. Verification\n"

    def stiffness(folder, chain, say):
        for n in state["figs"]:
            (folder / "figures" / n).write_bytes(b"png " + n.encode())
        return "## 2. Stiffness\n"

    def practice(folder, chain, say):
        return "## 2b. Practice\n"

    def damping(folder, model, say):
        return "## 3. Damping\n"

    def gap(folder, model, data, say):
        if state["fail"] is not None:
            raise state["fail"]
        return "## 4. Gap\n"

    for name, fn in (("step_verification", verification), ("step_stiffness", stiffness),
                     ("step_practice", practice), ("step_damping", damping), ("step_gap", gap)):
        monkeypatch.setattr(report, name, fn)
    return state


def _tree(root: Path) -> dict[str, bytes]:
    return {p.relative_to(root).as_posix(): p.read_bytes() for p in sorted(root.rglob("*")) if p.is_file()}


def test_report_force_with_a_bad_input_keeps_every_file(tmp_path, capsys):
    out = tmp_path / "P"
    (out / "figures").mkdir(parents=True)
    (out / "json").mkdir()
    (out / "figures" / "mine.png").write_text("x")
    (out / "json" / "mine.json").write_text("{}")
    (out / "report.md").write_text("old report")
    before = _tree(out)
    rc, _, err = _run(capsys, ["report", "--out", out, "--force", "--chain", "/nonexistent.toml"])
    assert rc == 2 and "nonexistent" in _one_error_line(err)
    assert _tree(out) == before
    (tmp_path / "bad.csv").write_text("test,t,x,F\n1,0,1,2\n1,0.1,1,abc\n")
    rc, _, err = _run(capsys, ["report", "--out", out, "--force", "--data", tmp_path / "bad.csv"])
    assert rc == 2 and "bad.csv" in _one_error_line(err)
    assert _tree(out) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["P", "bad.csv"]


@pytest.mark.parametrize("fault, rc_expected", [(ValueError("late failure in step 4"), 2), (KeyboardInterrupt(), 130)])
def test_report_late_failure_or_sigint_leaves_the_old_report(tmp_path, capsys, fake_steps, fault, rc_expected):
    out = tmp_path / "P"
    rc, _, _ = _run(capsys, ["report", "--out", out])
    assert rc == 0
    before = _tree(out)
    assert "report.md" in before and "figures/a.png" in before and ".chainid-manifest.json" in before
    fake_steps["figs"] = ["b.png"]
    fake_steps["fail"] = fault
    rc, _, err = _run(capsys, ["report", "--out", out, "--force"])
    assert rc == rc_expected
    _one_error_line(err)
    assert _tree(out) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["P"]  # no temporary folder left


def test_report_force_replaces_only_the_files_it_wrote(tmp_path, capsys, fake_steps):
    out = tmp_path / "P"
    assert _run(capsys, ["report", "--out", out])[0] == 0
    (out / "figures" / "mine.png").write_text("user figure")
    (out / "notes.txt").write_text("user notes")
    rc, _, _ = _run(capsys, ["report", "--out", out])
    assert rc == 2  # not empty, no --force
    fake_steps["figs"] = ["b.png"]
    assert _run(capsys, ["report", "--out", out, "--force"])[0] == 0
    tree = _tree(out)
    assert "figures/a.png" not in tree  # the previous report's, no longer written
    assert tree["figures/b.png"] == b"png b.png"
    assert tree["figures/mine.png"] == b"user figure" and tree["notes.txt"] == b"user notes"
    manifest = json.loads(tree[".chainid-manifest.json"])
    assert manifest["files"] == ["figures/b.png", "json/verify.json", "report.md"]


def test_report_into_the_current_folder(tmp_path, capsys, fake_steps, monkeypatch):
    here = tmp_path / "P"
    here.mkdir()
    monkeypatch.chdir(here)
    assert _run(capsys, ["report", "--out", "."])[0] == 0
    assert sorted(_tree(here)) == [".chainid-manifest.json", "figures/a.png", "json/verify.json", "report.md"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["P"]
