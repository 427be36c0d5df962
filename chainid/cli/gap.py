"""CLI: ``chainid diagnose`` and ``chainid benchmark-gap`` (see :mod:`chainid.gap`)."""

from __future__ import annotations

import argparse
import sys
from typing import Any


def cmd_diagnose(args: argparse.Namespace) -> int:
    try:
        _check_diagnose_options(args)
        recs, read_doc, model, holdout, other = _diagnose_inputs(args)
        res = _run_diagnosis(args, recs, holdout, model, other)
        if read_doc.get("warnings"):  # what reading noticed goes into the JSON too
            res.setdefault("warnings", []).extend(read_doc["warnings"])
        if model is not None and not getattr(args, "not_a_chain", None):  # loads beyond the elastic contact or
            from chainid.cli.chains import warn_loads  # the working load (as stiffness, identify)

            warn_loads(max(float(r.F.max()) for r in recs), model.chain, res)
        _write_diagnosis(args, res)
    except ValueError as exc:
        print(f"chainid diagnose: error: {exc}", file=sys.stderr)
        return 2
    return 0


def _check_diagnose_options(args: argparse.Namespace) -> None:
    """Check ``diagnose``'s --steady-tol (a fraction) and its output targets before the diagnosis starts."""
    if args.steady_tol is not None and not (0.0 < args.steady_tol < 1.0):
        raise ValueError(f"--steady-tol = {args.steady_tol!r} is out of range; valid range 0 < tol < 1 "
                         "(a fraction of the plateau, e.g. 0.05)")
    from chainid.infra.fileio import check_output_dir, check_output_file

    if args.json:  # output targets first: the diagnosis takes a while
        check_output_file(args.json, force=args.force, what="--json")
    if args.plots:
        from chainid.gap.plots import PLOT_NAMES

        check_output_dir(args.plots, "--plots", PLOT_NAMES, force=args.force)
    from chainid.cli.model import check_model_targets

    check_model_targets(args.save_model, args.save_steps, args.force, max_steps=int(args.max_combo) + 1)


def _diagnose_inputs(args: argparse.Namespace) -> tuple[list[Any], dict[str, Any], Any, list[str], list[Any] | None]:
    """Read ``diagnose``'s records (s, mm, N) and options: (records, read doc, model or None, holdout, other set)."""
    # per-test problems are reported (and the test left out) by the diagnosis; data errors stop it
    from chainid.cli.readopts import chain_for_checks, load_records
    from chainid.gap.diagnose import check_magnitudes

    chain = chain_for_checks(args)
    read_doc: dict[str, Any] = {}
    recs = load_records(args, args.data, chain, doc=read_doc, check=check_magnitudes)
    if args.model == "linear":
        model = None
    else:
        from chainid.model import base as models
        from chainid.chain.spec import load_chain

        model = models.model_for(load_chain(args.chain), args.variant)
    holdout = [h for h in (args.holdout or "").split(",") if h.strip()]
    if args.holdout is None and not args.holdout_blocks:
        raise ValueError("give --holdout IDS (whole tests) and/or --holdout-blocks K (time blocks)")
    other = load_records(args, args.validate, chain, doc=read_doc, check=check_magnitudes, select=False) \
        if args.validate else None
    if args.resamples < 0:
        raise ValueError(f"--resamples = {args.resamples} is invalid; valid range >= 0 (0: no resampling)")
    return recs, read_doc, model, holdout, other


def _run_diagnosis(args: argparse.Namespace, recs: list[Any], holdout: list[str], model: Any,
                   other: list[Any] | None) -> dict[str, Any]:
    """Run the diagnosis with progress; the records' warnings are reported, the stage times [s] kept in timing_s."""
    import warnings

    from chainid.gap.diagnose import diagnose
    from chainid.infra.progress import tracking
    from chainid.infra.runlog import warn
    from chainid.records.validate import RecordWarning

    with tracking("chainid diagnose", quiet=getattr(args, "quiet", False)) as stages, \
            warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("ignore")  # the diagnosis' warnings are in its result (printed, and in the JSON)
        warnings.simplefilter("always", RecordWarning)  # ... the records' own are not: kept for the run's channel
        res = diagnose(recs, holdout, model, max_combo=args.max_combo, damping_law=args.damping_law,
                       allow_compression=args.allow_compression, steady_tol=args.steady_tol, strict=args.strict,
                       holdout_blocks=args.holdout_blocks, validate=other, mass_kg=args.mass,
                       resamples=args.resamples, seed=args.seed)
    for w in caught:  # a record valid but implausible for the model (a chain force that dips below zero, ...):
        warn(str(w.message))  # on stderr and in the JSON warnings, as identify reports it
    res["timing_s"] = stages.times
    return res


def _write_diagnosis(args: argparse.Namespace, res: dict[str, Any]) -> None:
    """Print the diagnosis' summary and write its JSON, model files and figures."""
    from chainid.cli.model import save_models
    from chainid.gap.core.summary import summary, write_json

    print(summary(res))
    if "transfer" in res:
        print(f"\nTRANSFER to {args.validate}: {res['transfer']['verdict_text']}")
    if args.json:
        write_json(res, args.json, overwrite=args.force)
    if args.save_model:
        for p in save_models(res, args.save_model, args.save_steps, args.data, getattr(args, "argv", None),
                             args.force):
            print(f"wrote {p}")
    if args.plots:
        from chainid.gap.plots import make_plots

        for p in make_plots(res, args.plots, force=args.force):
            print(f"wrote {p}")


def check_workers(n: int | None) -> None:
    """``--workers``: None (the cores) or an int >= 1 (capped at the cases and at chainid.infra.parallel.MAX_WORKERS)."""
    if n is not None and n < 1:
        from chainid.infra.parallel import MAX_WORKERS

        raise ValueError(f"--workers = {n} is invalid: valid range >= 1 (more than {MAX_WORKERS} are capped)")


#: the simulated worlds of ``benchmark-gap --generator``
GENERATORS = ("sim", "ode", "both")
#: the sim generator's excitations when --excitations is not given
SIM_EXCITATIONS = "harmonic,random,sweep,startup,quake,transfer"


def _check_generator(args: argparse.Namespace) -> None:
    if args.generator not in GENERATORS:
        raise ValueError(f"--generator {args.generator!r} is unknown; valid: {', '.join(GENERATORS)}")
    if args.generator == "ode" and (args.chain or args.excitations is not None):
        raise ValueError("--chain and --excitations choose the sim generator's cases; the ODE world "
                         "(--generator ode) has its own bases and excitations")
    if args.seed < 0:
        raise ValueError(f"--seed = {args.seed} is out of range; valid range >= 0")


def _check_cases(args: argparse.Namespace, exc: tuple[str, ...]) -> None:
    """``--cases TEXT`` must match a case label of every world that runs (both: each), before any case runs: each
    world's own selection refuses it."""
    if args.cases is None:
        return
    if args.generator in ("sim", "both"):
        from chainid.gap.benchmark.grid import selected_cases

        selected_cases(args.small, args.seed, exc, only=args.cases)
    if args.generator in ("ode", "both"):
        from chainid.gap.benchmark.odeworld import selected_world_cases

        selected_world_cases(args.small, args.seed, args.cases)


def cmd_benchmark(args: argparse.Namespace) -> int:
    from chainid.gap.benchmark.grid import run_benchmark

    if args.summary:
        from chainid.gap.benchmark.resummary import summary_text

        try:
            print(summary_text(args.summary))
        except ValueError as exc:
            print(f"chainid benchmark-gap: error: {exc}", file=sys.stderr)
            return 2
        return 0
    try:
        check_workers(args.workers)
        _check_generator(args)
        if args.resamples != 0 and not 20 <= args.resamples <= 10000:
            raise ValueError(f"--resamples = {args.resamples} is out of range; valid: 0 (none) or 20 to 10000")
        if args.json:  # before the grid runs (minutes)
            from chainid.infra.fileio import check_output_file

            check_output_file(args.json, force=args.force, what="--json")
        exc = tuple(e.strip() for e in (args.excitations or SIM_EXCITATIONS).split(",") if e.strip())
        from chainid.gap.benchmark.grid import grid

        grid(True, 0, exc)  # an unknown excitation is refused before the run
        _check_cases(args, exc)
        chain = None
        if args.chain:
            from chainid.chain.spec import load_chain

            chain = load_chain(args.chain)
        both = args.generator == "both"
        out = {}
        if args.generator in ("sim", "both"):
            if both:
                print("== generator sim (the project's simulator) ==")
            out["sim"] = run_benchmark(small=args.small, json_path=None if both else args.json, overwrite=args.force,
                                       seed=args.seed, scheduler=args.scheduler, n_workers=args.workers,
                                       progress=not args.no_progress, excitations=exc, chain=chain,
                                       resamples=args.resamples, only=args.cases)
        if args.generator in ("ode", "both"):
            from chainid.gap.benchmark.odeworld import run_world

            if both:
                print("\n== generator ode (the independent ODE world) ==")
            out["ode"] = run_world(small=args.small, seed=args.seed, jobs=args.workers,
                                   json_path=None if both else args.json, overwrite=args.force,
                                   scheduler=args.scheduler, progress=not args.no_progress,
                                   resamples=args.resamples, only=getattr(args, "cases", None))
        if both and args.json:
            from chainid.infra.fileio import write_json

            write_json({"generator": "both", **out}, args.json, force=args.force, what="--json")
    except ValueError as exc:
        print(f"chainid benchmark-gap: error: {exc}", file=sys.stderr)
        return 2
    return 0


def add_subparsers(subparsers: Any) -> None:
    """Add ``diagnose`` and ``benchmark-gap`` to the chainid CLI."""
    _add_diagnose_parser(subparsers)
    _add_benchmark_parser(subparsers)


def _add_diagnose_parser(subparsers: Any) -> None:
    """The ``diagnose`` subcommand and its options (records in s, mm, N; mass kg)."""
    p = subparsers.add_parser("diagnose", help="sim-to-real gap: where the model misses, which effect, how much")
    p.add_argument("data", help="records: CSV test,t,x,F (s, mm, N), or a file/directory/glob in the rig's layout "
                                "(see the reading options)")
    p.add_argument("--holdout", help="held-out test id(s), comma separated (whole tests)")
    p.add_argument("--holdout-blocks", dest="holdout_blocks", type=int, default=0, metavar="K",
                   help="cut every record into K contiguous time blocks and hold out the last one of each "
                        "(time-domain route; K >= 2)")
    p.add_argument("--validate", metavar="OTHER.csv",
                   help="score the fitted chain on another set (another excitation): does the chain transfer? "
                        "(read with the same reading options as DATA)")
    p.add_argument("--chain", metavar="FILE.toml|PRESET",
                   help="chain TOML file or preset, e.g. din22252:26x92 (default: the paper's chain)")
    p.add_argument("--variant", default="paper", help="chain kernel variant (default paper)")
    p.add_argument("--model", choices=("chain", "linear"), default="chain",
                   help="baseline stiffness: chain (default) or a linear spring fitted on the training tests")
    p.add_argument("--max-combo", dest="max_combo", type=int, default=3, choices=(1, 2, 3),
                   help="most effects in the explanation chain (default 3)")
    p.add_argument("--damping-law", dest="damping_law", default="auto",
                   choices=("auto", "polynomial", "viscous", "coulomb", "viscous+coulomb", "hysteretic"),
                   help="baseline damping law (default auto: Eq. 21 when the plan separates it, else the "
                        "leave-one-out best simple law; time route: the dashpot follows the records' band centre "
                        "and amplitude, viscous: one c)")
    p.add_argument("--mass", type=float, default=None, metavar="KG",
                   help="the moving mass of a linear base [kg], given instead of fitted (--model linear)")
    p.add_argument("--resamples", type=int, default=200, metavar="N",
                   help="resamples of the training tests and time blocks for the stability of every step and the "
                        "90 %% intervals of every parameter (default 200; 0: none)")
    p.add_argument("--seed", type=int, default=0, help="seed of the resamples' draws (default 0)")
    p.add_argument("--allow-compression", dest="allow_compression", action="store_true",
                   help="accept compressive forces with the chain model (which carries none)")
    p.add_argument("--steady-tol", dest="steady_tol", type=float, default=None, metavar="TOL",
                   help="steady-cycle tolerance as a fraction of the plateau (default: adaptive per record)")
    p.add_argument("--strict", action="store_true",
                   help="a test that cannot be analysed, or a plausibility warning (unit slip), is an error (rc 2)")
    p.add_argument("--json", metavar="FILE", help="write the JSON result")
    p.add_argument("--plots", metavar="DIR", help="write figures to DIR")
    p.add_argument("--save-model", dest="save_model", metavar="M.toml",
                   help="write the chosen chain as a model file (TOML, or JSON by the .json suffix) for predict, "
                        "simulate --model and dynamics --segment-model")
    p.add_argument("--save-steps", dest="save_steps", action="store_true",
                   help="also write the model after each step: M.step0.toml (baseline), M.step1.toml, ...")
    p.add_argument("--force", action="store_true", help="overwrite existing --json / --plots / model files")
    from chainid.cli.readopts import add_reader_options

    add_reader_options(p, quiet=True)
    p.set_defaults(func=cmd_diagnose)


def _add_benchmark_parser(subparsers: Any) -> None:
    """The ``benchmark-gap`` subcommand and its options."""
    b = subparsers.add_parser("benchmark-gap", help="blind benchmark of the diagnosis on simulated effects")
    b.add_argument("--small", action="store_true", help="a small, fast grid")
    b.add_argument("--json", metavar="FILE", help="write the JSON summary")
    b.add_argument("--seed", type=int, default=0,
                   help="seed of the benchmark's random effects, noise and plans (default 0, the README's runs); runs "
                        "at different seeds draw disjoint streams: independent replicates")
    b.add_argument("--generator", default="sim", choices=GENERATORS,
                   help="which simulated world: sim (the project's simulator, default), ode (an independently "
                        "written world: effects as ODE states integrated with LSODA, multisine/filtered-noise/chirp/"
                        "harmonic excitations, force-driven resonant devices), both (each reported apart)")
    b.add_argument("--excitations", default=None, metavar="LIST",
                   help="sim generator: which excitations run, comma separated: harmonic (steady test plans), random, "
                        "sweep, startup (ramp with load steps), quake (earthquake-like), transfer (fit harmonic, "
                        "score random, and back); default all")
    b.add_argument("--cases", metavar="TEXT", default=None,
                   help="run only the cases whose label contains TEXT; sim labels read excitation/family/effects "
                        "(e.g. 'random/pair/', 'sensor_delay'), ode labels family/base/excitation/effects@levels "
                        "(e.g. '~table1', 'single/damper/'); the labels are in the --json rows")
    b.add_argument("--chain", metavar="FILE.toml|PRESET",
                   help="run every case on this chain (TOML file or preset, e.g. studless:76:grade=R4), its "
                        "displacements scaled to the 14x50 chain's nominal stress (default: the built-in 14x50 "
                        "and 10x35 chains)")
    b.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="dask scheduler address of an existing cluster, or local (default: a dask LocalCluster "
                        "when dask is installed, else a process pool), processes, serial")
    b.add_argument("--workers", type=int, default=None,
                   help="worker processes (default: the machine's cores; at most the cases and 4 x cores, <= 64)")
    b.add_argument("--resamples", type=int, default=0, metavar="N",
                   help="resample every diagnosis N times (default 0: none; >= 20): the steps' stability and the "
                        "percentile intervals, whose coverage of the true parameters both generators report per effect")
    b.add_argument("--no-progress", dest="no_progress", action="store_true", help="no progress bar")
    b.add_argument("--force", action="store_true", help="overwrite an existing --json file")
    b.add_argument("--summary", metavar="FILE.json", nargs="+", default=None,
                   help="print the summary of an earlier --json run again from its rows (no case is run); several "
                        "files are pooled, each generator's rows as one run's (a case in more than one file "
                        "with the same result counts once)")
    b.set_defaults(func=cmd_benchmark)

