"""CLI subcommands ``identify``, ``simulate`` and ``audit``.

``chainid/cli.py`` calls :func:`add_subparsers` with its argparse subparsers;
each subcommand sets ``func(args) -> int`` (exit code).

* ``chainid identify DATA.csv [--chain F.toml] [--model chain|linear] [--law NAME]
  [--side F.csv] [--steady-tol TOL] [--strict] [--json F] [--plots DIR] [--force]``
* ``chainid simulate OUT.csv [--plan F.csv|paper] [--law NAME --params ...]
  [--noise-x MM] [--noise-F N] [--seed S] [--force]``
* ``chainid audit [--chain F.toml] [--data RECORDS [reading options]] [--json F] [--force]``
"""
from __future__ import annotations

import argparse
import math
import sys
from typing import Any, Sequence

import numpy as np

__all__ = ["add_subparsers", "cmd_identify", "cmd_simulate", "cmd_audit", "main"]

LAW_NAMES = ("polynomial", "viscous", "coulomb", "hysteretic", "viscous+coulomb", "viscous+hysteretic")


# --- helpers ----------------------------------------------------------------
def _jsonable(o: Any) -> Any:
    if isinstance(o, dict):
        return {str(k): _jsonable(v) for k, v in o.items() if k != "fitted"}
    if isinstance(o, (list, tuple)):
        return [_jsonable(v) for v in o]
    if isinstance(o, np.ndarray):
        return [_jsonable(v) for v in o.tolist()]
    if isinstance(o, (np.floating, float)):
        v = float(o)
        return v if math.isfinite(v) else None
    if isinstance(o, (np.integer,)):
        return int(o)
    if isinstance(o, (np.bool_,)):
        return bool(o)
    return o


def _check_out(path: str | None, force: bool, what: str = "--json") -> None:
    """Check an output file target before the work starts (see :func:`chainid.infra.fileio.check_output_file`)."""
    from chainid.infra.fileio import check_output_file

    if path is not None and path != "-":
        check_output_file(path, force=force, what=what)


def _write_json(path: str, data: dict, force: bool) -> None:
    from chainid.infra.fileio import write_json

    write_json(_jsonable(data), path, force=force)


def _table(headers: Sequence[str], rows: Sequence[Sequence[Any]], fmts: Sequence[str]) -> str:
    cells = [[(f"{v:{f}}" if isinstance(v, (int, float, np.floating)) and f else str(v)) for v, f in zip(r, fmts)]
             for r in rows]
    widths = [max(len(h), *(len(c[i]) for c in cells)) if cells else len(h) for i, h in enumerate(headers)]
    line = "  ".join(h.rjust(w) for h, w in zip(headers, widths))
    out = [line, "  ".join("-" * w for w in widths)]
    out += ["  ".join(c.rjust(w) for c, w in zip(r, widths)) for r in cells]
    return "\n".join(out)


def _model(args: argparse.Namespace) -> Any:
    """The stiffness model selected on the command line (chain by default)."""
    from chainid.model import base as models  # the lead's module: ChainModel, LinearModel, model_for
    from chainid.chain.spec import load_chain

    if getattr(args, "model", "chain") == "linear":
        k = getattr(args, "k", None)
        if k is None:
            return None  # fitted from the data by the caller
        return models.LinearModel(float(k), float(args.x_ref), mass=float(args.mass or 0.0))
    chain = load_chain(getattr(args, "chain", None))
    return models.model_for(chain, getattr(args, "variant", "paper"))


def _steady_tol(text: str | None) -> float | None:
    """``--steady-tol``: a fraction (0.05) or a percentage (5%); None = adaptive."""
    if text is None or str(text).strip().lower() in ("", "auto", "adaptive"):
        return None
    s = str(text).strip()
    try:
        v = float(s[:-1]) / 100.0 if s.endswith("%") else float(s)
    except ValueError:
        raise ValueError(f"--steady-tol {text!r}: expected a fraction such as 0.05, a percentage such as 5%, "
                         f"or 'auto'") from None
    if not (0.0 < v < 1.0) or not math.isfinite(v):
        raise ValueError(f"--steady-tol {text!r}: must be between 0 and 1 (0 and 100 %), e.g. 0.05 or 5%")
    return v


def _law(name: str, params: Sequence[float] | None, model: Any) -> Any:
    from chainid.model.laws import law_from_dict

    return law_from_dict({"name": name, "params": params}, model=model)


# --- identify ---------------------------------------------------------------
def cmd_identify(args: argparse.Namespace) -> int:
    """``chainid identify``: per-test c_e (Eq. 17–20, 26–27), damping law (Eq. 21–24), LOO ranking.

    A test whose steady cycles, harmonic fit or damping estimate cannot be
    obtained is left out with its reason (one ``excluded test ID: reason`` line
    on stderr, ``"excluded": [{"test", "reason"}]`` in the JSON); ``--strict``
    makes any exclusion fatal (rc 2).  Data errors (bad cells, NaN, t not
    increasing, compressive force without ``--allow-compression``) always stop
    the run.  ``--steady-tol`` sets the steady-cycle tolerance (default adaptive).
    """
    from chainid.damping.identify import identify_records
    from chainid.records.files import analyse_record, write_side_file

    allow_comp, steady_tol, strict = _identify_options(args)
    records, read_doc, side = _identify_read(args)

    model = _model(args)
    if model is None:  # --model linear without --k: fit F - m xddot = k (x - x_ref) on the steady cycles
        from chainid.damping.identify import linear_model_from_records

        model = linear_model_from_records(records, float(args.mass or 0.0), side, steady_tol=steady_tol)

    def progress(i: int, n: int, test: str) -> None:
        if not args.quiet:
            print(f"[{i + 1}/{n}] identifying test {test}", file=sys.stderr, flush=True)

    mass = args.mass if args.mass is not None else None
    results = identify_records(records, model, side=side, mass_kg=mass, allow_compression=allow_comp,
                               progress=progress, steady_tol=steady_tol)
    excluded = list(results.excluded)
    for e in excluded:
        print(f"excluded test {e['test']}: {e['reason']}", file=sys.stderr, flush=True)
    if excluded and strict:
        raise ValueError(f"--strict: {len(excluded)} test(s) could not be identified: "
                         + "; ".join(f"{e['test']}: {e['reason']}" for e in excluded))
    if not results:
        raise ValueError(f"no test of {args.data!r} could be identified ({len(excluded)} excluded; see above)")

    _print_identified(model, results, excluded)
    out: dict[str, Any] = {
        "tests": [r.to_dict() for r in results],
        "model": {"name": getattr(model, "name", None), "mass_kg": results[0].mass_kg},
        "law": None,
        "excluded": [{"test": e["test"], "reason": e["reason"]} for e in excluded],
    }
    if read_doc.get("warnings"):  # what reading noticed goes into the JSON too
        out["warnings"] = list(read_doc["warnings"])
    if getattr(model, "chain", None) is not None and not getattr(args, "not_a_chain", None):
        from chainid.cli.chains import warn_loads  # record force beyond the chain's elastic/working range

        warn_loads(max(float(r.F.max()) for r in records), model.chain, out)
    if args.write_side:
        kept = {r.test for r in results}
        ests = {r.test: analyse_record(r, side.get(r.test) if side else None, allow_compression=True,
                                       steady_tol=steady_tol) for r in records if r.test in kept}
        write_side_file(args.write_side, ests, overwrite=args.force)

    rc, law = _identify_law(args, model, results, excluded, out)
    if args.plots:
        from chainid.damping.plots import plot_all

        paths = plot_all(records, results, model, args.plots, law=law, force=args.force)
        print(f"\nwrote {len(paths)} plot(s) to {args.plots}")
    if args.json:
        _write_json(args.json, out, args.force)
        if args.json != "-":
            print(f"wrote {args.json}")
    return rc


def _identify_options(args: argparse.Namespace) -> tuple[bool, float | None, bool]:
    """Check ``identify``'s numbers and output targets: (allow compression, steady tolerance [fraction], strict)."""
    _check_model_numbers(args)
    _check_out(args.json, args.force)
    if args.write_side:
        _check_out(args.write_side, args.force, "--write-side")
    allow_comp = bool(args.allow_compression or args.model == "linear")
    steady_tol = _steady_tol(getattr(args, "steady_tol", None))
    strict = bool(getattr(args, "strict", False))
    if args.plots:
        from chainid.infra.fileio import check_output_dir

        check_output_dir(args.plots, "--plots")
    return allow_comp, steady_tol, strict


def _identify_read(args: argparse.Namespace) -> tuple[list[Any], dict[str, Any], dict[str, Any] | None]:
    """Read ``identify``'s records, check the plot names and read the side file: (records, read doc, side)."""
    from chainid.model.laws import MIN_TESTS
    from chainid.records.files import read_side_file
    # per-test analysis problems are reported (and the test left out) by identify_records
    from chainid.cli.readopts import chain_for_checks, load_records
    from chainid.records.validate import check_channels

    read_doc: dict[str, Any] = {}
    records = load_records(args, args.data, chain_for_checks(args), doc=read_doc, check=check_channels)
    if args.plots:
        from chainid.damping.plots import plot_names
        from chainid.infra.fileio import check_output_dir

        check_output_dir(args.plots, "--plots", plot_names([r.test for r in records], len(records) >= MIN_TESTS),
                         force=args.force)
    side = read_side_file(args.side) if args.side else None
    if side:
        unknown = sorted(set(side) - {r.test for r in records})
        if unknown:
            raise ValueError(f"side file {args.side!r}: test(s) {unknown} are not in {args.data!r}")
    return records, read_doc, side


def _print_identified(model: Any, results: Any, excluded: list[dict[str, Any]]) -> None:
    """Print the per-test table (rad/s, mm, N, N.s/mm), the steady cycles kept, the exclusions and loop notes."""
    print(f"model: {getattr(model, 'name', type(model).__name__)}, mass m = {results[0].mass_kg:.4g} kg")
    print(_table(
        ["test", "omega rad/s", "x0 mm", "A mm", "F0 N", "F_A N", "phi rad", "R2", "F_ac N", "c_e N.s/mm",
         "W N.mm", "W/visc", "R2(F_c)", "cycles kept", "window s"],
        [[r.test, r.omega, r.x0, r.A, r.F0, r.FA, r.phi, r.r2, r.F_ac, r.c_e, r.W, r.W_ratio, r.r2_c,
          f"{r.cycles_kept[0]}-{r.cycles_kept[-1]} ({r.n_cycles})" if r.cycles_kept else "-",
          f"{r.t_start:.4g}-{r.t_end:.4g}"] for r in results],
        ["", ".5g", ".4g", ".4g", ".6g", ".6g", ".4f", ".5f", ".5g", ".5g", ".5g", ".3f", ".4f", "", ""],
    ))
    print("steady cycles kept:")
    for r in results:
        print(f"  {r.test}: {r.steady}")
    if excluded:
        print(f"{len(excluded)} test(s) excluded: " + "; ".join(f"{e['test']} ({e['reason']})" for e in excluded))
    odd = [r.test for r in results if r.r2_c < 0.97]
    if odd:
        print(f"note: F_c of test(s) {', '.join(odd)} is far from one harmonic (R2(F_c) < 0.97): the loop is not "
              f"elliptic, so the damping is not viscous (friction, backlash, ...); c_e is then the equivalent "
              f"viscous damping of the fundamental.")


def _identify_law(args: argparse.Namespace, model: Any, results: Any, excluded: list[dict[str, Any]],
                  out: dict[str, Any]) -> tuple[int, Any]:
    """Fit and print the damping law c_e(omega, A) [N.s/mm] and the LOO ranking into out: (exit code, law or None)."""
    from chainid.model.laws import MIN_TESTS, rank_laws

    omega = [r.omega for r in results]
    A = [r.A for r in results]
    ce = [r.c_e for r in results]
    x0 = [r.x0 for r in results]
    if len(results) < MIN_TESTS:
        left = f" ({len(excluded)} excluded)" if excluded else ""
        msg = (f"only {len(results)} test(s) identified{left}: fitting a damping law needs at least {MIN_TESTS} "
               f"(paper Eq. 22: M > 5); per-test results only")
        print(f"chainid identify: error: {msg}", file=sys.stderr)
        out["law_error"] = msg
        return 2, None
    law = _law(args.law, None, model)
    law.fit(omega, A, ce, x0)
    f = law.fit_
    print(f"\ndamping law {law.name}: {law.formula()}")
    print(_table(
        ["param", "lstsq", "std err", "normal eq. (Eq. 23)"],
        [[n, p, s, pn] for n, p, s, pn in zip(law.param_names, f.params, f.stderr, f.params_normal)],
        ["", ".6g", ".4g", ".6g"],
    ))
    print(f"cond(X) = {f.cond_X:.4g}, cond(G = X'X) = {f.cond_G:.4g}, RMSE = {f.rmse:.4g} N.s/mm, "
          f"LOO RMSE = {f.loo_rmse:.4g} N.s/mm, dof = {f.dof}")
    print("residuals [N.s/mm]: " + ", ".join(f"{r.test}: {v:.4g}" for r, v in zip(results, f.residuals)))
    out["law"] = law.to_dict()
    ranking = rank_laws(omega, A, ce, x0, model=model)
    print("\nlaws ranked by leave-one-out RMSE:")
    print(_table(
        ["law", "params", "RMSE N.s/mm", "LOO RMSE N.s/mm"],
        [[r["law"], r.get("n_params"), r.get("rmse", float("nan")), r["loo_rmse"]] for r in ranking],
        ["", "", ".4g", ".4g"],
    ))
    out["ranking"] = [{k: v for k, v in r.items() if k != "fitted"} for r in ranking]
    return 0, law


# --- simulate ---------------------------------------------------------------
def _parse_floats(s: str | None) -> list[float] | None:
    if s is None:
        return None
    try:
        return [float(v) for v in s.split(",") if v.strip()]
    except ValueError:
        raise ValueError(f"--params {s!r}: expected comma-separated numbers") from None


def cmd_simulate(args: argparse.Namespace) -> int:
    """``chainid simulate``: test plan + chain + damping law + noise → records CSV."""
    from chainid.records.files import write_records
    from chainid.records.simulate import paper_plan, read_plan, simulate

    _check_out(args.out, args.force, "output")
    _check_simulate_options(args)
    plan = paper_plan() if args.plan in (None, "paper") else read_plan(args.plan)
    if args.model not in ("chain", "linear"):
        from chainid.cli.model import simulate_model_file

        return simulate_model_file(args, plan)
    if args.model == "linear" and args.k is None:
        raise ValueError("--model linear needs --k [N/mm] (and --x-ref [mm]) for simulation")
    model = _model(args)
    params = _parse_floats(args.params)
    bad = [v for v in (params or []) if not math.isfinite(v)]
    if bad:
        raise ValueError(f"--params {args.params!r}: value {bad[0]!r} is invalid: valid range finite numbers")
    if params is None:
        defaults = {"viscous": [2834.4], "polynomial": [28.02, -651.57, -8386.50, 7394.84, 4378.89]}
        if args.law not in defaults:
            raise ValueError(f"--law {args.law} needs --params")
        params = defaults[args.law]
    law = _law(args.law, params, model)
    ramp = None if args.ramp_rate <= 0 else args.ramp_rate
    force_fn = None
    if args.effect:
        from chainid.model.effects import parse_effect

        force_fn = parse_effect(args.effect, model)
    recs = simulate(plan, model, law, seed=args.seed, n_cycles=args.cycles, samples_per_cycle=args.samples_per_cycle,
                    ramp_rate=ramp, taper_cycles=args.taper_cycles, noise_x=args.noise_x, noise_F=args.noise_F,
                    force_fn=force_fn, mass_kg=args.mass, max_memory=args.max_memory * 1024**3)
    write_records(args.out, recs, overwrite=args.force)
    print(_table(["test", "omega rad/s", "x0 mm", "A mm", "c_e N.s/mm", "samples", "duration s"],
                 [[s.test, s.omega, s.x0, s.A, float(law.predict(s.omega, s.A, s.x0)[0]), r.t.size, r.t[-1]]
                  for s, r in zip(plan, recs)],
                 ["", ".5g", ".4g", ".4g", ".5g", "d", ".4g"]))
    effect = f", effect {args.effect}" if args.effect else ""
    print(f"wrote {len(recs)} test(s) to {args.out} (law {law.name} {params}{effect}, noise x {args.noise_x} mm, "
          f"F {args.noise_F} N, seed {args.seed})")
    return 0


def _check_model_numbers(args: argparse.Namespace) -> None:
    """``--mass`` [kg], ``--k`` [N/mm], ``--x-ref`` [mm] of ``identify``: finite, mass >= 0, k > 0."""
    for name, v, ok, rng in (("--mass", args.mass, args.mass is None or args.mass >= 0, ">= 0 kg"),
                             ("--k", args.k, args.k is None or args.k > 0, "> 0 N/mm"),
                             ("--x-ref", args.x_ref, True, "finite mm")):
        if v is not None and not (math.isfinite(v) and ok):
            raise ValueError(f"{name} = {v!r} is invalid: valid range {rng} (finite)")


def _check_simulate_options(args: argparse.Namespace) -> None:
    """Range checks of ``simulate``'s numeric options, before anything is computed."""
    checks = (
        ("--noise-x", args.noise_x, args.noise_x is None or args.noise_x >= 0, ">= 0 mm"),
        ("--noise-F", args.noise_F, args.noise_F is None or args.noise_F >= 0, ">= 0 N"),
        ("--mass", args.mass, args.mass is None or args.mass >= 0, ">= 0 kg"),
        ("--k", args.k, args.k is None or args.k > 0, "> 0 N/mm"),
        ("--x-ref", args.x_ref, True, "finite mm"),
        ("--cycles", args.cycles, args.cycles > 0, "> 0"),
        ("--ramp-rate", args.ramp_rate, args.ramp_rate >= 0, ">= 0 mm/s (0 = no ramp)"),
        ("--taper-cycles", args.taper_cycles, 0 <= args.taper_cycles <= args.cycles / 2, "0 to --cycles/2"),
        ("--max-memory", args.max_memory, args.max_memory > 0, "> 0 GiB"),
    )
    for name, v, ok, rng in checks:
        if v is not None and not (math.isfinite(v) and ok):
            raise ValueError(f"{name} = {v!r} is invalid: valid range {rng} (finite)")
    if args.samples_per_cycle < 16:
        raise ValueError(f"--samples-per-cycle = {args.samples_per_cycle!r} is invalid: valid range >= 16")


# --- audit ------------------------------------------------------------------
def cmd_audit(args: argparse.Namespace) -> int:
    """``chainid audit``: Eq. 28 from Table 1 and findings (a)–(e); with ``--data RECORDS``: c_e(ω, A) identified
    per test from the records (as ``identify``) and the same Eq. 28 audit on them instead of Table 1."""
    from chainid.damping.audit import audit, format_audit

    _check_out(args.json, args.force)
    if args.data:  # the records' c_e instead of Table 1 (chainid.cli.audit_data)
        from chainid.cli.audit_data import audit_data

        _check_model_numbers(args)
        rep, text = audit_data(args, _model, _steady_tol(args.steady_tol))
    else:
        try:
            model = _model(args)
        except ImportError:
            model = None
            from chainid.infra.runlog import warn

            warn("stiffness model unavailable; finding (c) without k_e")
        rep = audit(model)
        text = format_audit(rep)
    print(text)
    if args.json:
        _write_json(args.json, rep, args.force)
        if args.json != "-":
            print(f"wrote {args.json}")
    return 0


# --- registration -----------------------------------------------------------
def _wrap(fn: Any) -> Any:
    def run(args: argparse.Namespace) -> int:
        try:
            return fn(args)
        except ValueError as exc:
            print(f"chainid {getattr(args, 'command', None) or 'identify'}: error: {exc}", file=sys.stderr)
            return 2

    run.__doc__ = fn.__doc__
    return run


def _model_options(p: argparse.ArgumentParser, model_file: bool = False) -> None:
    p.add_argument("--chain", metavar="FILE.toml", help="chain TOML file or preset name, e.g. din22252:26x92 (default: the paper's 14x50 chain)")
    p.add_argument("--variant", default="paper", help="stiffness model variant (default: paper)")
    if model_file:
        p.add_argument("--model", default="chain", metavar="chain|linear|M.toml",
                       help="stiffness model: the chain (default), linear F = k (x - x_ref), or an augmented model "
                            "file written by diagnose --save-model (then --law/--params/--effect/--k do not apply)")
    else:
        p.add_argument("--model", choices=("chain", "linear"), default="chain",
                       help="stiffness model: the chain (default) or linear F = k (x - x_ref) (allows compressive force)")
    p.add_argument("--k", type=float, help="linear model stiffness [N/mm] (identify: fitted from the data if omitted)")
    p.add_argument("--x-ref", dest="x_ref", type=float, default=0.0, help="linear model unloaded length offset [mm]")
    p.add_argument("--mass", type=float, default=None, help="mass m [kg] (default: the chain's / 0 for linear)")


def add_subparsers(subparsers: Any) -> None:
    """Register ``identify``, ``simulate`` and ``audit`` on an argparse subparsers object."""
    p = subparsers.add_parser("identify", help="identify damping from force-displacement records (Eq. 17-28)",
                              description=cmd_identify.__doc__)
    p.add_argument("data", help="records: CSV test,t,x,F (s, mm, N), or a file/directory/glob in the rig's layout "
                                "(see the reading options)")
    _model_options(p)
    p.add_argument("--law", choices=LAW_NAMES, default="polynomial", help="damping law to report (default Eq. 21)")
    p.add_argument("--side", metavar="FILE.csv", help="side file test,omega,x0,A (rad/s, mm, mm) to use instead of estimates")
    p.add_argument("--write-side", dest="write_side", metavar="FILE.csv", help="write the estimated omega,x0,A per test")
    p.add_argument("--allow-compression", action="store_true", help="accept F < 0 (implied by --model linear)")
    p.add_argument("--steady-tol", dest="steady_tol", metavar="TOL",
                   help="steady-cycle tolerance on amplitude/mean/drift, a fraction (0.05) or per cent (5%%); "
                        "default: adaptive, from each record's cycle-to-cycle scatter (3-15 %%)")
    p.add_argument("--strict", action="store_true",
                   help="fail (rc 2) if any test cannot be identified instead of leaving it out, or on a "
                        "plausibility warning (unit slip)")
    p.add_argument("--json", metavar="FILE", help="write results as JSON")
    p.add_argument("--plots", metavar="DIR", help="write loop and damping-surface PNGs")
    p.add_argument("--force", action="store_true", help="overwrite existing output files")
    p.add_argument("--quiet", action="store_true", help="no progress messages")
    from chainid.cli.readopts import add_reader_options

    add_reader_options(p)
    p.set_defaults(func=_wrap(cmd_identify))

    s = subparsers.add_parser("simulate", help="simulate a test series into a records CSV",
                              description=cmd_simulate.__doc__)
    s.add_argument("out", help="output records CSV")
    _model_options(s, model_file=True)
    s.add_argument("--plan", default="paper", help="plan CSV test,omega,x0,A (rad/s, mm, mm) or 'paper' (Table 1)")
    s.add_argument("--law", choices=LAW_NAMES, default="viscous", help="damping law (default viscous)")
    s.add_argument("--params", help="law parameters, comma separated (viscous default 2834.4 N.s/mm, Eq. 27)")
    s.add_argument("--noise-x", dest="noise_x", type=float, default=0.0, help="displacement noise std [mm]")
    s.add_argument("--noise-F", dest="noise_F", type=float, default=0.0, help="force noise std [N]")
    s.add_argument("--seed", type=int, default=0, help="noise seed")
    s.add_argument("--cycles", type=float, default=6, help="oscillation cycles per test")
    s.add_argument("--samples-per-cycle", dest="samples_per_cycle", type=int, default=200)
    s.add_argument("--ramp-rate", dest="ramp_rate", type=float, default=0.08973,
                   help="ramp rate to x0 [mm/s] (paper Eq. 25: 0.08973; 0 = no ramp)")
    s.add_argument("--taper-cycles", dest="taper_cycles", type=float, default=0.0, help="amplitude taper in/out [cycles]")
    s.add_argument("--effect", metavar="NAME[:p=v,...]",
                   help="add an unmodelled effect from the gap library, e.g. friction:F_c=150 (N), "
                        "hysteresis:F_h=300,x_h=0.05, backlash:b=0.02 (mm), slack:s=0.1 (mm), "
                        "machine_compliance:c=2e-5 (mm/N), contact_law:scale=1.2,beta=0.6, "
                        "sensor_delay:tau=0.01 (s), damping_law:eta=0.3,F_f=100")
    s.add_argument("--max-memory", dest="max_memory", type=float, default=2.0, metavar="GIB",
                   help="refuse a simulation whose estimated memory exceeds this many GiB (default 2)")
    s.add_argument("--force", action="store_true", help="overwrite the output file")
    s.set_defaults(func=_wrap(cmd_simulate))

    a = subparsers.add_parser("audit", help="reproduce Eq. 28 and audit the paper's damping numbers",
                              description=cmd_audit.__doc__)
    a.add_argument("--data", metavar="RECORDS", help="audit c_e identified from these records instead of Table 1")
    _model_options(a)
    a.add_argument("--allow-compression", action="store_true", help="--data: accept F < 0 (implied by --model linear)")
    a.add_argument("--steady-tol", dest="steady_tol", metavar="TOL", help="--data: steady-cycle tolerance (as identify)")
    a.add_argument("--strict", action="store_true", help="--data: fail on a test left out or a plausibility warning")
    a.add_argument("--json", metavar="FILE", help="write the report as JSON (includes eq28_alpha)")
    a.add_argument("--force", action="store_true", help="overwrite an existing JSON file")
    a.add_argument("--quiet", action="store_true", help="no progress bar")
    add_reader_options(a)
    a.set_defaults(func=_wrap(cmd_audit))


def main(argv: Sequence[str] | None = None) -> int:
    """Stand-alone entry point (for testing without chainid.cli)."""
    parser = argparse.ArgumentParser(prog="chainid")
    sub = parser.add_subparsers(dest="command", required=True)
    add_subparsers(sub)
    args = parser.parse_args(argv)
    from chainid.infra.runlog import collecting

    with collecting(args.command):  # warnings as in chainid.cli.main: once on stderr and in the JSON
        return int(args.func(args))


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
