"""The command-line parser (chainid.cli.parser): every default the help states is the default, the paper's test as
simulate's default, options repeated under another spelling, missing or broken subcommand modules, run as a script."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from repo_paths import REPO as ROOT


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
