"""CLI: ``chainid predict MODEL DATA``, the model-file outputs of ``diagnose`` (``--save-model``, ``--save-steps``)
and ``simulate --model M.toml`` (:func:`simulate_model_file`).

``chainid predict M.toml DATA.csv [--tests IDS] [--fitted-damping] [--json F] [--plots DIR]`` prints per-test
and pooled NRMSE of the model file's baseline and of the model, and the shrinkage (see
:mod:`chainid.gap.modelio` for how each record is evaluated).
"""

from __future__ import annotations

import argparse
import shlex
import sys
from pathlib import Path
from typing import Any, Sequence

#: figure names of ``predict --plots`` per test (overlay and residual over t and over x; the id made portable
#: and injective by :func:`plot_name`)
PLOT_NAME = "predict_{test}.png"


def step_paths(path: str | Path, n_steps: int) -> list[Path]:
    """``M.toml`` → ``M.step0.toml``, ``M.step1.toml`` … (one file per step of the explanation chain)."""
    p = Path(path)
    return [p.with_name(f"{p.stem}.step{i}{p.suffix}") for i in range(n_steps)]


def check_model_targets(path: str | None, save_steps: bool, force: bool, max_steps: int = 4) -> None:
    """Check the ``--save-model`` target (and the step files it may write) before the diagnosis runs."""
    if not path:
        if save_steps:
            raise ValueError("--save-steps needs --save-model M.toml (the step files are named after it)")
        return
    from chainid.infra.fileio import check_output_file

    if Path(path).suffix.lower() not in (".toml", ".json"):
        raise ValueError(f"--save-model {path!r}: the model file name must end in .toml or .json")
    check_output_file(path, force=force, what="--save-model")
    if save_steps:
        for p in step_paths(path, max_steps):
            check_output_file(p, force=force, what="--save-steps")


def save_models(res: dict[str, Any], path: str, save_steps: bool, data_file: str,
                argv: Sequence[str] | None, force: bool) -> list[Path]:
    """Write the chosen chain's model to ``path`` (and every step's model with ``save_steps``)."""
    from chainid.gap.modelio import provenance
    from chainid.model.modelfile import save_model

    cmd = "chainid " + " ".join(shlex.quote(a) for a in (argv if argv is not None else sys.argv[1:]))
    prov = provenance(data_file, cmd)
    models = res["_models"]
    for m in models:
        m.info["provenance"] = prov
    out = [save_model(res.get("_model", models[-1]), path, overwrite=force)]
    if save_steps:
        out += [save_model(m, p, overwrite=force) for m, p in zip(models, step_paths(path, len(models)))]
    return out


def simulate_model_file(args: argparse.Namespace, plan: Sequence[Any]) -> int:
    """``simulate --model M.toml``: records of the plan from an augmented model file."""
    from chainid.model.modelfile import load_model
    from chainid.records import write_records
    from chainid.records.simulate import simulate_model

    given = getattr(args, "given", None)  # the options on the command line (chainid.cli.main), else by value
    opts = (("--chain", "chain", args.chain is not None), ("--variant", "variant", args.variant != "paper"),
            ("--law", "law", False), ("--params", "params", args.params is not None),
            ("--effect", "effect", args.effect is not None), ("--k", "k", args.k is not None),
            ("--x-ref", "x_ref", args.x_ref != 0.0), ("--mass", "mass", args.mass is not None))
    clash = [o for o, dest, set_ in opts if (dest in given if given is not None else set_)]
    if clash:
        raise ValueError(f"--model {args.model!r} is a model file: {', '.join(clash)} cannot be given with it (the "
                         "file holds the chain, its kernel variant, the effects, the damping, the base and the mass)")
    model = load_model(args.model)
    ramp = None if args.ramp_rate <= 0 else args.ramp_rate
    recs = simulate_model(plan, model, seed=args.seed, n_cycles=args.cycles, samples_per_cycle=args.samples_per_cycle,
                          ramp_rate=ramp, taper_cycles=args.taper_cycles, noise_x=args.noise_x, noise_F=args.noise_F,
                          max_memory=args.max_memory * 1024**3)
    write_records(args.out, recs, overwrite=args.force)
    names = "+".join(n for n, _ in model.effects) or "no effects"
    print(f"wrote {len(recs)} test(s) to {args.out} (model {args.model}: {names}, damping {model.damping.form}, "
          f"delay {model.delay_s:g} s, noise x {args.noise_x} mm, F {args.noise_F} N, seed {args.seed})")
    return 0


def cmd_predict(args: argparse.Namespace) -> int:
    """``chainid predict``: a saved model on records → per-test and pooled NRMSE of baseline and model."""
    from chainid.infra.fileio import check_output_dir, check_output_file, write_json
    from chainid.infra.runlog import warn
    from chainid.gap.modelio import predict
    from chainid.model.modelfile import load_model

    try:
        if args.json:
            check_output_file(args.json, force=args.force, what="--json")
        if args.plots:
            check_output_dir(args.plots, "--plots", (), force=args.force)
        model = load_model(args.model)
        from chainid.cli.readopts import load_records
        from chainid.records.validate import check_channels

        read_doc: dict[str, Any] = {}
        recs = load_records(args, args.data, getattr(getattr(model, "base", None), "chain", None), doc=read_doc,
                            check=check_channels)
        if args.plots:  # the figures' names are known now (--tests applied by the reader): refuse before the work
            check_output_dir(args.plots, "--plots", [plot_name(r.test) for r in recs], force=args.force)
        res = predict(model, recs, None, fitted=args.fitted_damping, keep=bool(args.plots))
        for w in res["warnings"]:
            if getattr(args, "strict", False):
                raise ValueError(f"{w} (--strict)")
            warn(w)
        res["warnings"] = read_doc.get("warnings", []) + res["warnings"]  # reading's too (printed when read)
        print(_table(res))
        if args.json:
            write_json({k: v for k, v in res.items() if not k.startswith("_")}, args.json, force=args.force)
            if args.json != "-":
                print(f"wrote {args.json}")
        if args.plots:
            for p in plot_predictions(res["_series"], args.plots, force=args.force):
                print(f"wrote {p}")
    except ValueError as exc:
        print(f"chainid predict: error: {exc}", file=sys.stderr)
        return 2
    return 0


def _table(res: dict[str, Any]) -> str:
    def f(v: Any) -> str:
        return "-" if v is None else f"{v:.4g}"

    w = max([8, len("pooled")] + [len(str(r["test"])) for r in res["tests"]])  # the longest id sets the column
    rows = [f"{'test':<{w}}  {'mode':>12}  {'NRMSE base':>10}  {'NRMSE model':>11}  {'shrinkage':>9}"]
    for r in res["tests"]:
        rows.append(f"{r['test']:<{w}}  {r['mode']:>12}  {f(r['nrmse_baseline']):>10}  {f(r['nrmse_model']):>11}  "
                    f"{f(r['shrinkage']):>9}")
    p = res["pooled"]
    rows.append(f"{'pooled':<{w}}  {'':>12}  {f(p['nrmse_baseline']):>10}  {f(p['nrmse_model']):>11}  "
                f"{f(p['shrinkage']):>9}   (damping: {res['damping_used']})")
    return "\n".join(rows)


def plot_name(test: str) -> str:
    """File name of a test's figure: ``predict_<id>.png``, the id made portable by
    :func:`chainid.infra.fileio.safe_filename` (an id it changes gets a hash of itself: "T 1", "T_1" and "T/1"
    give three names, never one figure over another)."""
    from chainid.infra.fileio import safe_filename

    return safe_filename(str(test), prefix="predict_", suffix=".png")


def plot_predictions(series: dict[str, Any], outdir: str, force: bool = False) -> list[Path]:
    """Per test: measured and predicted force over t and over x, and the residual over t and over x (PNG)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from chainid.infra.fileio import save_figure

    out = []
    d = Path(outdir)
    d.mkdir(parents=True, exist_ok=True)
    for test, (t, x, F, Fm, Fb) in series.items():
        fig, ax = plt.subplots(2, 2, figsize=(10, 7))
        ax[0, 0].plot(t, F, ".", ms=2, color="0.6", label="measured")
        ax[0, 0].plot(t, Fb, "-", lw=1, label="baseline")
        ax[0, 0].plot(t, Fm, "-", lw=1, label="model")
        ax[0, 0].set(xlabel="t [s]", ylabel="F [N]", title=f"test {test}: force over time")
        ax[0, 0].legend(fontsize=8)
        ax[1, 0].plot(t, F - Fb, ".", ms=2, label="baseline")
        ax[1, 0].plot(t, F - Fm, ".", ms=2, label="model")
        ax[1, 0].set(xlabel="t [s]", ylabel="residual [N]", title="residual over time")
        ax[1, 0].legend(fontsize=8)
        ax[0, 1].plot(x, F, ".", ms=2, color="0.6", label="measured")
        ax[0, 1].plot(x, Fb, ".", ms=1, label="baseline")
        ax[0, 1].plot(x, Fm, ".", ms=1, label="model")
        ax[0, 1].set(xlabel="x [mm]", ylabel="F [N]", title="force over x")
        ax[1, 1].plot(x, F - Fb, ".", ms=2, label="baseline")
        ax[1, 1].plot(x, F - Fm, ".", ms=2, label="model")
        ax[1, 1].set(xlabel="x [mm]", ylabel="residual [N]", title="residual over x")
        fig.tight_layout()
        p = d / plot_name(test)
        save_figure(fig, p, force=force, dpi=90)
        plt.close(fig)
        out.append(p)
    return out


def add_subparsers(subparsers: Any) -> None:
    """Add ``predict`` to the chainid CLI."""
    p = subparsers.add_parser("predict", help="a saved model (diagnose --save-model) on records: NRMSE and shrinkage",
                              description=cmd_predict.__doc__)
    p.add_argument("model", help="model file (TOML or JSON) written by diagnose --save-model")
    p.add_argument("data", help="records: CSV test,t,x,F (s, mm, N), or a file/directory/glob in the rig's layout "
                                "(see the reading options)")
    p.add_argument("--fitted-damping", dest="fitted_damping", action="store_true",
                   help="use the per-test c_e the law was fitted on for those tests (default: the law for every test)")
    p.add_argument("--json", metavar="FILE", help="write the JSON result")
    p.add_argument("--plots", metavar="DIR", help="write overlay/residual figures (over t and over x) per test")
    p.add_argument("--force", action="store_true", help="overwrite existing --json / --plots files")
    from chainid.cli.readopts import add_reader_options

    add_reader_options(p, strict=True, quiet=True)
    p.set_defaults(func=cmd_predict)
