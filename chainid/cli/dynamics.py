"""``chainid dynamics``: multi-mass chain simulation (start-up, sinusoid, polygon effect) and sweeps.

Units on the command line: mm, N, s, kg (speeds mm/s, damping N·s/mm).  ``--json FILE`` (or ``-``) for
machines; ``--plots DIR`` writes the tension heat map, the drive-end tension and the first mode shapes.
Outputs are written atomically (chainid.fileio) and never overwrite an existing file without ``--force``;
the targets are checked before the simulation starts.  Every run is checked (finite, energy balance within
1e-3 at its worst time, peak converged under step halving with ``--refine``); a failed check is a warning,
and with ``--strict`` an error (exit code 2).  Loads beyond the chain's limits are warned about as in the
other commands.
"""
from __future__ import annotations

import argparse
import math
import re
import sys
import warnings
from pathlib import Path
from typing import Any

from chainid.infra.runlog import note

__all__ = ["add_subparsers", "cmd_dynamics"]

_FIGS = ("dynamics_heatmap.png", "dynamics_drive_tension.png", "dynamics_modes.png")


def _floats(text: str) -> list[float]:
    try:
        return [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a comma-separated list of numbers") from None


def _ints(text: str) -> list[int]:
    vals = _floats(text)
    bad = [v for v in vals if v != int(v) or v < 1]
    if bad:
        raise argparse.ArgumentTypeError(f"{text!r}: the numbers of masses must be whole numbers >= 1 (got {bad[0]:g})")
    return [int(v) for v in vals]


def _element(text: str) -> tuple[float, float]:
    try:
        k, f = (float(v) for v in text.split(":"))
        return (k, f)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: expected two numbers A:B (--hysteresis K_N_PER_MM:F_N, e.g. "
                                         "2000:150; --dahl F_H_N:X_H_MM, e.g. 120:0.05)") from None


def _covariate(text: str) -> tuple[str, float]:
    name, eq, value = text.partition("=")
    try:
        v = float(value)
    except ValueError:
        v = math.nan
    if not (eq and name.strip() and math.isfinite(v)):
        raise argparse.ArgumentTypeError(f"--segment-covariate {text!r}: expected NAME=VALUE with a finite number, "
                                         "e.g. i=1.5")
    return name.strip(), v


def _load(text: str):
    from chainid.dynamics import LoadStep

    try:
        node, force, t_on = text.split(":")
        return LoadStep(int(node), float(force), float(t_on))
    except ValueError:
        raise argparse.ArgumentTypeError(f"--load {text!r}: expected NODE:FORCE_N:T_ON_S, e.g. 200:5000:2.0") from None


def add_subparsers(subparsers: Any) -> None:
    """Add ``dynamics`` to the chainid CLI."""
    p = subparsers.add_parser("dynamics",
                              help="multi-mass chain dynamics: start-up, polygon effect, load steps, sweeps")
    _add_chain_options(p)
    _add_run_options(p)
    p.set_defaults(func=cmd_dynamics)


def _add_chain_options(p: argparse.ArgumentParser) -> None:
    """The "chain" option group of ``dynamics``: the line, its segments and their elements (mm, N, s, kg)."""
    g = p.add_argument_group("chain")
    g.add_argument("--chain", metavar="FILE.toml", help="chain TOML file (default: the built-in 14x50 chain)")
    g.add_argument("--variant", default="paper", help="kernel variant (default paper)")
    g.add_argument("--length", type=float, metavar="MM", help="chain length [mm] (default: --links)")
    g.add_argument("--links", type=int, default=4000, help="number of links (default 4000 = 200 m of 14x50)")
    g.add_argument("--masses", type=int, default=400, help="number of lumped masses / segments N (default 400)")
    g.add_argument("--pretension", type=float, default=5000.0, help="pretension [N] (default 5000)")
    g.add_argument("--far-end", dest="far_end", default="tensioner", help="fixed | tensioner (default)")
    g.add_argument("--tensioner-stiffness", dest="kt", type=float, default=0.0, help="take-up spring [N/mm]")
    g.add_argument("--damping", type=float, default=0.0,
                   help="viscous-equivalent c_e of the tested specimen [N·s/mm] (default 0)")
    g.add_argument("--segment-model", dest="segment_model", metavar="M.toml",
                   help="diagnosed model file of the tested specimen: its chain, kernel (with the stiffness-side "
                        "effects), effects and time-domain damping go into every segment, scaled in series (see "
                        "chainid.dynamics.segment_model)")
    g.add_argument("--segment-omega", dest="seg_omega", type=float, metavar="RAD_S",
                   help="operating circular frequency of a model file's damping law or feature law (e.g. the first "
                        "natural frequency or the polygon frequency 2*pi*v/p)")
    g.add_argument("--segment-amplitude", dest="seg_amplitude", type=float, metavar="MM",
                   help="operating elongation amplitude of the specimen for a model file's damping law or feature law "
                        "[mm]")
    g.add_argument("--segment-covariate", dest="seg_cov", action="append", type=_covariate, default=[],
                   metavar="NAME=VALUE",
                   help="operating condition of a model file's covariate terms (e.g. i=1.5 for a coil current in A; "
                        "repeatable; required for each covariate the model depends on)")
    g.add_argument("--damping-ref-links", dest="ref_links", type=int, metavar="N",
                   help="links of the specimen the damping data belong to (default: the chain file's n)")
    g.add_argument("--hysteresis", action="append", type=_element, default=[], metavar="K:F",
                   help="Jenkins element of the specimen: spring K [N/mm] in series with a slider of force F [N] "
                        "(repeatable: an Iwan model of hysteretic damping)")
    g.add_argument("--dahl", action="append", type=_element, default=[], metavar="F_H:X_H",
                   help="Dahl hysteresis of the specimen: force F_H [N] reached over a travel X_H [mm] after each "
                        "reversal (repeatable)")
    g.add_argument("--coulomb", type=float, default=0.0, metavar="F",
                   help="Coulomb friction with stick of the specimen [N] (default 0)")
    g.add_argument("--coulomb-stiffness", dest="coulomb_k", type=float, metavar="K",
                   help="stick stiffness of the Coulomb element [N/mm] (default: the specimen's link stiffness)")
    g.add_argument("--resistance", type=float, default=0.0, help="total moving resistance [N] (default 0)")
    g.add_argument("--load", action="append", type=_load, default=[], metavar="NODE:F:T",
                   help="load step of F [N] on a node from time T [s] (repeatable)")


def _add_run_options(p: argparse.ArgumentParser) -> None:
    """The "drive", "integration", "sweep" and "output" option groups of ``dynamics`` (mm/s, s, N, GiB)."""
    d = p.add_argument_group("drive")
    d.add_argument("--drive", default="ramp", help="none | ramp (default) | sine | polygon")
    d.add_argument("--speed", type=float, default=1000.0, help="(mean) chain speed [mm/s] (default 1000)")
    d.add_argument("--t-ramp", dest="t_ramp", type=float, default=2.0, help="start-up time [s] (default 2)")
    d.add_argument("--amplitude", type=float, default=0.0, help="sine amplitude [mm]")
    d.add_argument("--omega", type=float, default=1.0, help="sine circular frequency [rad/s] (default 1)")
    d.add_argument("--teeth", type=int, default=8, help="sprocket teeth (polygon sides) for --drive polygon")
    s = p.add_argument_group("integration")
    s.add_argument("--t-end", dest="t_end", type=float, default=10.0, help="simulated time [s] (default 10)")
    s.add_argument("--dt", type=float, help="step [s] (default: 0.9 x the stable step)")
    s.add_argument("--scheme", default="explicit", help="explicit (default) | implicit")
    s.add_argument("--peak-force", dest="peak_force", type=float,
                   help="expected peak tension [N] for the stable step (default: the load-independent bound)")
    s.add_argument("--modes", type=int, default=4, help="natural frequencies to report (>= 1, default 4)")
    s.add_argument("--refine", type=int, default=5,
                   help="step halvings allowed until the energy balance is within 1e-3 and the peak changes by "
                        "<= 2 %% under halving (0..10, default 5)")
    s.add_argument("--strict", action="store_true",
                   help="a run that fails its checks (energy balance, peak convergence) is an error (exit 2)")
    s.add_argument("--max-memory", dest="max_memory", type=float, default=2.0, metavar="GIB",
                   help="refuse runs estimated above this memory [GiB] (default 2)")
    s.add_argument("--max-work", dest="max_work", type=float, default=2e10, metavar="NODE_STEPS",
                   help="refuse runs estimated above this many node-steps (default 2e10, about 10 min)")
    w = p.add_argument_group("sweep (any of these runs a sweep over their product)")
    w.add_argument("--sweep-pretension", dest="sw_p", type=_floats, metavar="N,N,..")
    w.add_argument("--sweep-speed", dest="sw_v", type=_floats, metavar="V,V,..")
    w.add_argument("--sweep-masses", dest="sw_n", type=_ints, metavar="N,N,..")
    w.add_argument("--scheduler", help="local (default: dask LocalCluster or a process pool) | processes | "
                                       "serial | the address of a dask scheduler")
    w.add_argument("--workers", type=int, help="worker processes (default: the number of cores)")
    o = p.add_argument_group("output")
    o.add_argument("--json", metavar="FILE", help="write the JSON result ('-' for stdout)")
    o.add_argument("--plots", metavar="DIR", help="write figures to DIR")
    o.add_argument("--force", action="store_true", help="overwrite existing output files")
    o.add_argument("--quiet", action="store_true", help="no progress bar")


def _check_args(args: argparse.Namespace, sweeping: bool) -> None:
    """Options and output targets, before any work."""
    from chainid.cli.common import check_json_target
    from chainid.infra.fileio import check_output_dir

    from chainid.cli.gap import check_workers

    check_workers(args.workers)
    if args.modes < 1:
        raise ValueError(f"--modes = {args.modes} is invalid: valid range an int >= 1")
    if not 0 <= args.refine <= 10:
        raise ValueError(f"--refine = {args.refine} is invalid: valid range 0 .. 10")
    for name, v in (("--max-memory", args.max_memory), ("--max-work", args.max_work)):
        if not (v > 0 and v < float("inf")):
            raise ValueError(f"{name} = {v!r} is invalid: valid range > 0 (finite)")
    if sweeping and args.plots:
        raise ValueError(f"--plots = {args.plots!r} is invalid with a sweep: figures are drawn for a single run "
                         "(use --json for the sweep table)")
    seen: set[str] = set()
    for name, _ in args.seg_cov:
        if name in seen:
            raise ValueError(f"--segment-covariate {name!r} is given twice; valid: once per covariate")
        seen.add(name)
    if args.seg_cov and not args.segment_model:
        raise ValueError("--segment-covariate needs --segment-model (the model file whose covariate terms it resolves)")
    if args.segment_model:
        given = [o for o, v in (("--chain", args.chain), ("--variant", args.variant != "paper"),
                                ("--damping", args.damping), ("--damping-ref-links", args.ref_links),
                                ("--hysteresis", args.hysteresis), ("--dahl", args.dahl), ("--coulomb", args.coulomb),
                                ("--coulomb-stiffness", args.coulomb_k)) if v]
        if given:
            raise ValueError(f"--segment-model comes with its own chain and damping: {', '.join(given)} cannot be "
                             "given with it")
    check_json_target(args.json, args.force)
    if args.plots:
        check_output_dir(args.plots, "--plots", _FIGS, force=args.force)


def _limit_kind(msg: str) -> str:
    """A load warning without its numbers (which limit it names)."""
    return re.sub(r"\d[\d.e+-]*", "#", msg)


def _say(args: argparse.Namespace, text: str) -> None:
    """The text report: stdout, or stderr when the JSON goes to stdout."""
    print(text, file=sys.stderr if args.json == "-" else sys.stdout)


def cmd_dynamics(args: argparse.Namespace) -> int:
    import dataclasses

    from chainid.cli.chains import warn_loads
    from chainid.cli.common import write_json
    from chainid.dynamics import Drive

    sweeping = any(v is not None for v in (args.sw_p, args.sw_v, args.sw_n))
    _check_args(args, sweeping)
    line, chain, seg_notes = _chain_line(args)
    drive = Drive(args.drive, v=args.speed, t_ramp=args.t_ramp, A=args.amplitude, omega=args.omega, z=args.teeth)
    sim_kw = dict(dt=args.dt, scheme=args.scheme, peak_force=args.peak_force, refine=args.refine,
                  strict=args.strict, max_memory=args.max_memory * 1024**3, max_work=args.max_work)
    doc: dict[str, Any] = {"segment_model": args.segment_model, "segment_model_notes": seg_notes,
                           "line": {k: v for k, v in dataclasses.asdict(line).items() if k not in ("chain", "loads")},
                           "chain": chain.to_dict(), "drive": dataclasses.asdict(drive),
                           "loads": [dataclasses.asdict(ld) for ld in line.loads]}
    loads_before = warn_loads(max(args.pretension, max((ld.force_N for ld in line.loads), default=0.0)), chain, doc)
    if sweeping:
        _run_sweep(args, line, drive, sim_kw, doc)
    else:
        _run_single(args, line, drive, sim_kw, doc, chain, loads_before)
    if args.json:
        write_json(doc, args.json, args.force)
    return 0


def _chain_line(args: argparse.Namespace) -> tuple[Any, Any, list[str]]:
    """The chain line of the options (lengths mm, forces N): (ChainLine, its ChainSpec, the segment model's notes)."""
    from chainid.chain.spec import load_chain
    from chainid.dynamics import ChainLine

    seg_notes: list[str] = []
    kw = dict(pretension_N=args.pretension, far_end=args.far_end, tensioner_stiffness=args.kt,
              resistance_N=args.resistance, loads=tuple(args.load))
    if args.segment_model:
        from chainid.dynamics.segment_model import segment_kwargs

        seg, notes = segment_kwargs(args.segment_model, pretension_N=args.pretension, omega=args.seg_omega,
                                    amplitude=args.seg_amplitude, covariates=dict(args.seg_cov))
        kw.update(seg)
        chain = kw["chain"]
        for m in notes:
            note(m)
        seg_notes = notes
    else:
        chain = load_chain(args.chain)
        kw.update(chain=chain, variant=args.variant, damping=args.damping, damping_ref_links=args.ref_links,
                  hysteresis=tuple(args.hysteresis), dahl=tuple(args.dahl), coulomb_N=args.coulomb,
                  coulomb_stiffness=args.coulomb_k)
    if args.length is not None:
        line = ChainLine.from_length(args.length, args.masses, **kw)
    else:
        line = ChainLine(n_links=args.links, n_masses=args.masses, **kw)
    return line, chain, seg_notes


def _run_sweep(args: argparse.Namespace, line: Any, drive: Any, sim_kw: dict[str, Any], doc: dict[str, Any]) -> None:
    """Run the sweep, print its table (N, mm/s, N) and warn per case; the rows go to doc["cases"]."""
    from chainid.dynamics.sweeps import sweep
    from chainid.infra.runlog import warn

    rows = sweep(line, drive, args.t_end, pretensions=args.sw_p, speeds=args.sw_v, n_masses=args.sw_n,
                 scheduler=args.scheduler, n_workers=args.workers, progress=not args.quiet, **sim_kw)
    doc["cases"] = rows
    _say(args, f"{'pretension N':>13} {'v mm/s':>8} {'N':>5} {'peak N':>10} {'dyn.factor':>10} {'ripple N':>9}")
    for r in rows:
        _say(args, f"{r['pretension_N']:13.6g} {r['v']:8.4g} {r['n_masses']:5d} {r['peak_tension_N']:10.5g} "
             f"{r['dynamic_factor']:10.4g} {r['drive_tension_ripple_N']:9.4g}")
        for m in r.get("warnings", []):
            warn(f"case P = {r['pretension_N']:g} N, v = {r['v']:g} mm/s, N = {r['n_masses']}: {m}")


def _run_single(args: argparse.Namespace, line: Any, drive: Any, sim_kw: dict[str, Any], doc: dict[str, Any],
                chain: Any, loads_before: list[str]) -> None:
    """Run one simulation, print its report (N, Hz, N·mm), warn (its checks, peak loads) and draw the figures."""
    from chainid.dynamics import simulate
    from chainid.dynamics.modes import modes
    from chainid.infra.runlog import warn
    from chainid.model.practice import load_warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # reported below from res.warnings
        res = simulate(line, drive, args.t_end, **sim_kw)
    md = modes(line, n_modes=args.modes)
    doc["summary"] = res.summary()
    doc["modes"] = {"frequency_hz": md.frequency_hz.tolist()}
    doc["tension_final_N"] = res.tension[-1].tolist()
    s = doc["summary"]
    eb = s["energy_N_mm"]
    _say(args, f"chain {line.n_links} links ({line.length_mm / 1000:.4g} m) in {line.n_masses} masses, "
         f"{args.scheme}, dt = {res.dt:.3g} s ({res.n_steps} steps, {res.refinements} refinement(s))")
    _say(args, f"peak tension {res.peak_tension:.6g} N, static {res.static_tension:.6g} N, "
         f"dynamic factor {res.dynamic_factor:.4g}")
    _say(args, "natural frequencies [Hz]: " + ", ".join(f"{f:.4g}" for f in md.frequency_hz))
    _say(args, f"energy [N·mm]: work in {eb['work_in']:.6g} = kinetic {eb['kinetic']:.6g} + stored "
         f"{eb['elastic']:.6g} + dissipated {eb['dissipated']:.6g} (balance error {eb['relative_error']:.2g} "
         f"at its worst, t = {eb['worst_t_s']:.4g} s)")
    for m in res.warnings:
        warn(m)
    doc.setdefault("warnings", []).extend(res.warnings)
    seen = {_limit_kind(m) for m in loads_before}
    for m in load_warnings(res.peak_tension, chain):  # limits the peak exceeds beyond those already named
        if _limit_kind(m) not in seen:
            warn(f"peak tension: {m}")
            doc["warnings"].append(f"peak tension: {m}")
    if args.plots:
        from chainid.dynamics import plots

        figs = (plots.plot_heatmap(res), plots.plot_drive_tension(res), plots.plot_modes(md))
        for fig, name in zip(figs, _FIGS):
            plots.save(fig, Path(args.plots) / name, force=args.force)
        print(f"figures written to {args.plots}", file=sys.stderr)
