"""``chainid dynamics`` on bad and edge input (issue 20 §1, §3, §5): checks before work, strict, JSON, warnings."""
import json
import os

import pytest

from chainid.cli import main

SMALL = ["dynamics", "--links", "100", "--masses", "10", "--pretension", "1000", "--speed", "200",
         "--t-ramp", "0.05", "--t-end", "0.1", "--quiet"]


def _fail_if_simulated(monkeypatch):
    import chainid.dynamics as dyn

    def boom(*a, **k):
        raise AssertionError("simulate() was called: the check must come first")
    monkeypatch.setattr(dyn, "simulate", boom)


@pytest.mark.parametrize("extra, needle", [
    (["--modes", "0"], "--modes = 0"),
    (["--refine", "11"], "--refine = 11"),
    (["--max-memory", "0"], "--max-memory"),
])
def test_bad_options_are_refused_before_work(monkeypatch, capsys, extra, needle):
    _fail_if_simulated(monkeypatch)
    assert main(SMALL + extra) == 2
    assert needle in capsys.readouterr().err


def test_sweep_masses_must_be_whole(capsys):
    with pytest.raises(SystemExit) as e:
        main(SMALL + ["--sweep-masses", "1.5"])
    assert e.value.code == 2
    assert "whole numbers" in capsys.readouterr().err


def test_outputs_checked_before_simulating(monkeypatch, tmp_path, capsys):
    _fail_if_simulated(monkeypatch)
    out = tmp_path / "r.json"
    out.write_text("{}")
    assert main(SMALL + ["--json", str(out)]) == 2
    assert "already exists" in capsys.readouterr().err and out.read_text() == "{}"
    f = tmp_path / "plots_is_a_file"
    f.write_text("x")
    assert main(SMALL + ["--plots", str(f)]) == 2
    assert "is a file" in capsys.readouterr().err


def test_huge_damping_is_one_line_not_a_traceback(capsys):
    assert main(SMALL + ["--damping", "1e9"]) == 2
    err = capsys.readouterr().err
    assert "max_work" in err and "Traceback" not in err


def test_huge_pretension_warns(tmp_path, capsys):
    out = tmp_path / "r.json"
    assert main(SMALL[:6] + ["1e12"] + SMALL[7:] + ["--refine", "0", "--json", str(out)]) == 0
    err = capsys.readouterr().err
    assert "exceeds the minimum breaking force" in err
    assert any("breaking force" in w for w in json.loads(out.read_text())["warnings"])


def test_json_nan_is_null_and_stdout_is_pure_json(capsys):
    """No static tension (drive 'none', no pretension): dynamic_factor is NaN → null; --json - is parseable."""
    argv = ["dynamics", "--links", "20", "--masses", "2", "--pretension", "0", "--drive", "none",
            "--t-end", "0.01", "--quiet", "--json", "-"]
    assert main(argv) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["summary"]["dynamic_factor"] is None


def test_json_write_is_atomic(monkeypatch, tmp_path):
    """The JSON goes through chainid.infra.fileio: a failure at the final link/rename leaves no file, no temp."""
    import chainid.infra.fileio as fio

    def fail(*a, **k):
        raise OSError(28, "No space left on device")
    monkeypatch.setattr(fio.os, "replace", fail)
    monkeypatch.setattr(fio.os, "link", fail)
    out = tmp_path / "r.json"
    assert main(SMALL + ["--json", str(out)]) == 2
    assert os.listdir(tmp_path) == []


def test_strict_turns_the_check_into_an_exit_code(capsys):
    """A coarse implicit run of a slack polygon drive fails its energy balance: warning (0), --strict (2)."""
    argv = ["dynamics", "--links", "200", "--masses", "20", "--pretension", "500", "--drive", "polygon",
            "--teeth", "6", "--speed", "1500", "--t-ramp", "0.2", "--t-end", "1", "--scheme", "implicit",
            "--dt", "5e-3", "--refine", "0", "--quiet"]
    assert main(argv) == 0
    assert "energy balance error" in capsys.readouterr().err
    assert main(argv + ["--strict"]) == 2
    assert "strict" in capsys.readouterr().err
