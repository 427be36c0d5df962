"""The ``chainid`` command line.

Subcommands: verify, generate, stiffness (this module); identify, simulate,
audit (:mod:`chainid.cli.identify`); diagnose, benchmark-gap
(:mod:`chainid.cli.gap`); report (:mod:`chainid.report`).  Every main job
takes ``--json`` for machines; the table on the terminal is for people.
"""
from __future__ import annotations

import argparse
import importlib
import sys
from pathlib import Path
from typing import Any, Sequence

from chainid.cli.common import check_json_target, progress, write_json

__all__ = ["main", "build_parser"]

#: Modules that add their own subcommands via ``add_subparsers(subparsers)``.
SUBCOMMAND_MODULES = ("chainid.cli.identify", "chainid.cli.gap", "chainid.cli.report", "chainid.cli.chains",
                      "chainid.cli.dynamics", "chainid.cli.model", "chainid.cli.convert")











# -- verify ------------------------------------------------------------------

def cmd_verify(args: argparse.Namespace) -> int:
    check_json_target(args.json, args.force)
    from chainid.derive import verify  # SymPy is imported here, and only here (and in generate)

    checks = verify.run_checks(progress=progress)
    w = max(len(c.equation) for c in checks)
    print(f"{'Eq.'.ljust(w)}  status   detail")
    for c in checks:
        print(f"{c.equation.ljust(w)}  {c.status:<7}  {c.detail}")
    doc = verify.as_json(checks)
    print(f"\n{doc['summary']['agrees']} agree, {doc['summary']['differs']} differ (findings, not failures)")
    write_json(doc, args.json, args.force)
    return 0


# -- generate ----------------------------------------------------------------

def default_generated_dir() -> Path:
    """Directory of the ``chainid.generated`` package (the repository's generated/ in an editable install)."""
    import importlib.util

    spec = importlib.util.find_spec("chainid.generated")
    assert spec is not None and spec.submodule_search_locations
    return Path(list(spec.submodule_search_locations)[0])


def cmd_generate(args: argparse.Namespace) -> int:
    from chainid.infra.fileio import check_output_dir

    out = Path(args.out) if args.out else default_generated_dir()
    if not args.check:
        check_output_dir(out, what="--out")  # generate always refreshes its own files
    elif out.exists() and not out.is_dir():
        raise ValueError(f"--out {str(out)!r} is a file; give the generated/ folder")
    from chainid.derive import emit

    try:
        res = emit.generate(out, check=args.check)
    except RuntimeError as exc:  # SymPy version mismatch
        print(f"chainid generate: error: {exc}", file=sys.stderr)
        return 2
    for fname, status in res.items():
        print(f"{status:>9}  {out / fname}")
    if args.check:
        bad = [f for f, s in res.items() if s != "unchanged"]
        if bad:
            stamp = _header_sympy(out / bad[0])
            extra = ""
            if stamp and stamp != emit.REQUIRED_SYMPY:
                extra = f" (the file was generated with SymPy {stamp}; this generator needs {emit.REQUIRED_SYMPY})"
            print(f"generated/ is stale: {', '.join(bad)}{extra}; run `chainid generate` and commit", file=sys.stderr)
            return 1
        print(f"generated/ is fresh (source hash {emit.source_hash()})")
    return 0


def _header_sympy(path: Path) -> str | None:
    if not path.exists():
        return None
    for line in path.read_text(encoding="utf-8").splitlines()[:8]:
        if line.startswith("# generator: SymPy "):
            return line.split()[-1]
    return None


# -- stiffness ---------------------------------------------------------------

def cmd_stiffness(args: argparse.Namespace) -> int:
    import numpy as np

    from chainid.model import kernels
    from chainid.chain.spec import load_chain

    check_json_target(args.json, args.force)
    chain = load_chain(args.chain)
    if args.x is None and args.F is None:
        raise ValueError("give --x X [X ...] (elongations, mm) and/or --F F [F ...] (tensions, N)")
    xs = list(args.x or [])
    if args.F:
        xs += [float(v) for v in np.atleast_1d(kernels.displacement(np.asarray(args.F, dtype=float), chain, args.variant))]
    x = np.asarray(xs, dtype=float)
    F = kernels.force(x, chain, args.variant)
    k = kernels.stiffness(x, chain, args.variant)
    c_lin, c_h = kernels.coefficients(chain, args.variant)
    rows = [{"x_mm": float(a), "F_k_N": float(b), "k_e_N_per_mm": float(c)} for a, b, c in zip(x, F, k)]
    doc = {"chain": chain.to_dict(), "variant": args.variant, "c_lin_mm_per_N": c_lin,
           "c_hertz_mm_per_N23": c_h, "points": rows}
    if len(F) and np.isfinite(F).any():
        from chainid.cli.chains import warn_loads

        warn_loads(float(np.nanmax(F)), chain, doc)
    if args.json == "-":
        write_json(doc, "-")
        return 0
    print(f"chain: d={chain.d} mm, pitch={chain.pitch} mm, width={chain.width} mm, n={chain.n}, "
          f"E={chain.E} MPa, nu={chain.nu}"
          + (f", {chain.family or 'family not stated'} grade {chain.grade}" if chain.grade else "")
          + f"; variant {args.variant}")
    print(f"x = {c_lin:.6e}·F + {c_h:.6e}·F^(2/3)  [mm, N]")
    print(f"{'x [mm]':>12} {'F_k [N]':>14} {'k_e [N/mm]':>14}")
    for r in rows:
        print(f"{r['x_mm']:12.6g} {r['F_k_N']:14.6g} {r['k_e_N_per_mm']:14.6g}")
    write_json(doc, args.json, args.force)
    return 0


def build_parser() -> argparse.ArgumentParser:
    """The argparse parser with every subcommand."""
    from chainid.model.kernels import VARIANTS

    p = argparse.ArgumentParser(prog="chainid", description="Axial dynamics of round link chains (mm, N, s, MPa, kg).")
    sub = p.add_subparsers(dest="command", required=True)

    v = sub.add_parser("verify", help="re-derive the stiffness with SymPy and check the paper equation by equation")
    v.add_argument("--json", metavar="FILE", help="write the table as JSON ('-' for stdout)")
    v.add_argument("--force", action="store_true", help="overwrite an existing output file")
    v.set_defaults(func=cmd_verify)

    g = sub.add_parser("generate", help="emit the numba kernels into generated/")
    g.add_argument("--check", action="store_true", help="exit 1 if generated/ is stale (2 on a SymPy version mismatch)")
    g.add_argument("--out", metavar="DIR", help="target directory (default: the chainid.generated package)")
    g.set_defaults(func=cmd_generate)

    s = sub.add_parser("stiffness", help="F_k and k_e at given elongations (or tensions)")
    s.add_argument("--x", type=float, nargs="+", metavar="X", help="elongations [mm]")
    s.add_argument("--F", type=float, nargs="+", metavar="F", help="tensions [N] (their elongations are added)")
    s.add_argument("--chain", metavar="FILE.toml", help="chain file or preset name, e.g. din22252:26x92 (default: the built-in 14x50 chain)")
    s.add_argument("--variant", default="paper", choices=VARIANTS, help="model variant")
    s.add_argument("--json", nargs="?", const="-", metavar="FILE", help="JSON to FILE, or to stdout with no FILE")
    s.add_argument("--force", action="store_true", help="overwrite an existing output file")
    s.set_defaults(func=cmd_stiffness)

    for modname in SUBCOMMAND_MODULES:
        try:
            mod = importlib.import_module(modname)
        except ModuleNotFoundError as exc:
            if exc.name != modname:
                raise
            continue
        mod.add_subparsers(sub)
    _refuse_repeats(p)
    return p


#: Actions that may be given more than once (``--load``, ``--hysteresis``, ``-h``); any other option twice is
#: an error (argparse would silently keep the last value).
_REPEATABLE = tuple(getattr(argparse, n) for n in ("_AppendAction", "_AppendConstAction", "_CountAction",
                                                    "_HelpAction", "_VersionAction", "_SubParsersAction"))
_ONCE_CLASSES: dict[type, type] = {}


def _once(cls: type) -> type:
    """``cls`` that refuses a second occurrence of its option on one command line."""
    if cls not in _ONCE_CLASSES:
        def __call__(self: Any, parser: argparse.ArgumentParser, namespace: argparse.Namespace, values: Any,
                     option_string: str | None = None) -> None:
            seen = namespace.__dict__.setdefault("_given_once", {})
            if self.dest in seen:
                first = seen[self.dest]
                also = f" (also as {first})" if first != option_string else ""
                parser.error(f"{option_string} given twice{also}; give it once")
            seen[self.dest] = option_string
            cls.__call__(self, parser, namespace, values, option_string)

        _ONCE_CLASSES[cls] = type(f"Once{cls.__name__}", (cls,), {"__call__": __call__})
    return _ONCE_CLASSES[cls]


def _refuse_repeats(parser: argparse.ArgumentParser) -> None:
    """Make every single-valued option of ``parser`` and its subcommands refuse a repetition."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub in set(action.choices.values()):
                _refuse_repeats(sub)
        elif action.option_strings and not isinstance(action, _REPEATABLE):
            action.__class__ = _once(type(action))


def _subparser(parser: argparse.ArgumentParser, command: str) -> argparse.ArgumentParser:
    """The parser of subcommand ``command`` (its errors read ``chainid COMMAND: error: ...``)."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction) and command in action.choices:
            return action.choices[command]
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``chainid`` command."""
    parser = build_parser()
    args, extra = parser.parse_known_args(argv)
    if extra:  # named by the subcommand (argparse's own message would say "chainid: error:")
        _subparser(parser, args.command).error(f"unrecognized arguments: {' '.join(extra)}")
    # (the bookkeeping of _refuse_repeats): the options given on the command line, by destination, for commands
    # that refuse an option that does not apply (simulate --model M.toml --chain P)
    args.given = frozenset(vars(args).pop("_given_once", None) or ())
    args.argv = list(argv) if argv is not None else sys.argv[1:]  # the command line, for model-file provenance
    try:
        from chainid.cli.common import check_io
        from chainid.infra.runlog import collecting

        check_io(args)  # an output that is an input of the same run (or of another output): refused before any work
        with collecting(args.command):  # warnings: once on stderr, and in every JSON the run writes
            if getattr(args, "json", None) == "-":  # the JSON alone on stdout, every other line on stderr
                from chainid.infra.fileio import json_to_stdout

                with json_to_stdout():
                    return int(args.func(args) or 0)
            return int(args.func(args) or 0)
    except ValueError as exc:
        print(f"chainid {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # e.g. `chainid audit | head`
        sys.stderr.close()
        return 0
    except OSError as exc:  # a file system fault not caught by chainid.infra.fileio: one line, no traceback
        name = f" {exc.filename!r}" if getattr(exc, "filename", None) else ""
        print(f"chainid {args.command}: error:{name} {exc.strerror or exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:  # SIGINT: outputs are atomic, so nothing partial is left
        from chainid.infra.fileio import interrupted

        return interrupted(args.command)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
