"""``chainid report``: the main job — every step on the built-in chain into one report folder.

Steps (each writes its figures and JSON into the folder and a section of
``report.md``):

1. verification: the paper checked equation by equation (SymPy);
2. stiffness: the paper's Fig. 8a/8b and the model variants;
3. damping: Table 1 audit, Eq. 28 reproduced, damping surface (Fig. 11), the
   validation case (Fig. 12) under both readings of ω — or, with ``--data``,
   the identification of the user's records;
4. gap: a diagnosis on a built-in simulated series with a hidden effect and on
   the paper's Eq. 26 record — or on the user's records.
"""
from __future__ import annotations

import json
import math
import shutil
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["run_report"]

from chainid.report.common import Progress, dump_json, md_table


def _say(msg: str) -> None:
    print(f"[chainid report] {msg}", file=sys.stderr, flush=True)


# -- step 1 ----------------------------------------------------------------------

def step_verification(folder: Path, say: Progress) -> str:
    """Equation-by-equation table, derived vs the paper (SymPy; ~4 s, or none when this process has run it already)."""
    from chainid.derive import verify

    checks = verify.run_checks(progress=lambda s: say(f"verification: {s}"))
    doc = verify.as_json(checks)
    j = dump_json(folder, "verify.json", doc)
    rows = [[c.equation, c.status, c.detail] for c in checks]
    s = doc["summary"]
    return (
        "## 1. Verification: the paper, equation by equation\n\n"
        f"SymPy re-derivation from internal forces to the chain displacement, compared with each printed closed "
        f"form: {s['agrees']} agree, {s['differs']} differ (findings, with the reason). JSON: `{j}`.\n\n"
        + md_table(["Eq.", "status", "detail"], rows) + "\n"
    )


# -- step 2 ----------------------------------------------------------------------

def step_stiffness(folder: Path, chain: Any, say: Progress) -> str:
    """Fig. 8a, 8b and the variants from the generated kernels."""
    from chainid.model import kernels
    from chainid.report import figures as plots

    say("stiffness figures")
    fig = folder / "figures"
    fig.mkdir(exist_ok=True)
    plots.plot_stiffness_vs_length(fig / "fig8a_stiffness_vs_length.png", chain)
    plots.plot_stiffness_vs_modulus(fig / "fig8b_stiffness_vs_modulus.png", chain)
    plots.plot_variants(fig / "stiffness_variants.png", chain)
    xs = [0.5, 1.0, 2.2, 3.0, 5.0]
    rows, doc = [], {"chain": chain.to_dict(), "points": []}
    for x in xs:
        r = {"x_mm": x}
        for v in kernels.VARIANTS:
            try:
                r[f"F_k_{v}_N"] = kernels.force(x, chain, v)
                r[f"k_e_{v}_N_per_mm"] = kernels.stiffness(x, chain, v)
            except ValueError:
                pass
        doc["points"].append(r)
        rows.append([x] + [f"{r.get(f'F_k_{v}_N', float('nan')):.0f} / {r.get(f'k_e_{v}_N_per_mm', float('nan')):.0f}"
                           for v in kernels.VARIANTS])
    c_lin, c_h = kernels.coefficients(chain)
    doc["c_lin_mm_per_N"], doc["c_hertz_mm_per_N23"] = c_lin, c_h
    doc["x_at_11117N_mm"] = kernels.displacement(11117.0, chain)
    j = dump_json(folder, "stiffness.json", doc)
    return (
        "## 2. Stiffness\n\n"
        f"Chain: d = {chain.d:g} mm, pitch = {chain.pitch:g} mm, width = {chain.width:g} mm, n = {chain.n}, "
        f"E = {chain.E:g} MPa, ν = {chain.nu:g}. x = {c_lin:.4e}·F + {c_h:.4e}·F^(2/3) [mm, N]; "
        f"x(11117 N) = {doc['x_at_11117N_mm']:.4f} mm (the paper's test: F₀ = 11117 N at x₀ = 2.2 mm). JSON: `{j}`.\n\n"
        "![Fig. 8a](figures/fig8a_stiffness_vs_length.png)\n\n![Fig. 8b](figures/fig8b_stiffness_vs_modulus.png)\n\n"
        "![variants](figures/stiffness_variants.png)\n\n"
        "F_k [N] / k_e [N/mm] by variant:\n\n" + md_table(["x [mm]"] + list(kernels.VARIANTS), rows) + "\n"
    )


def step_practice(folder: Path, chain: Any, say: Progress) -> str:
    """The model against practice: presets, catalogue EA, elastic-contact limit (table and figures)."""
    from chainid.report.practice import report_section

    return report_section(folder, chain, say)


# -- step 3 ----------------------------------------------------------------------

def _plot_table1_surface(path: Path, alpha: list[float], tb: dict) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    w = np.linspace(0.5, 20, 120)
    A = np.linspace(0.15, 0.45, 100)
    W, AA = np.meshgrid(w, A)
    C = alpha[0] * W**2 + alpha[1] * W + alpha[2] * AA**2 + alpha[3] * AA + alpha[4]
    fig, ax = plt.subplots(figsize=(7.2, 4.6))
    cs = ax.contourf(W, AA, C, levels=20, cmap="viridis")
    fig.colorbar(cs, ax=ax, label="$c_e$ (Eq. 21, 28) [N·s/mm]")
    ax.scatter(tb["omega_col"], tb["A"], c=tb["c_e"], cmap="viridis", edgecolors="k", s=60,
                    vmin=cs.get_clim()[0], vmax=cs.get_clim()[1], label="Table 1 tests")
    ax.set_xlabel("ω, Table 1 column (as used by Eq. 28) [paper: rad/s]")
    ax.set_ylabel("amplitude A [mm]")
    ax.set_title("Damping surface of Eq. 28 with the Table 1 tests (paper Fig. 11)")
    ax.legend(loc="upper right")
    fig.tight_layout()
    from chainid.infra.fileio import save_figure

    save_figure(fig, path, force=True, what="report figure", dpi=120)
    plt.close(fig)


def _plot_validation(path: Path, model: Any, alpha: list[float]) -> dict:
    """Paper Fig. 12: x = 2.25 + 0.32 sin(14πt) with c_e of Eq. 21 fed ω = 7 or ω = 14π."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from chainid.model.predict import predict_force

    x0, A, w = 2.25, 0.32, 14 * math.pi
    t = np.linspace(0, 2 * math.pi / w, 400)
    x = x0 + A * np.sin(w * t)

    def ce(om: float) -> float:
        return alpha[0] * om**2 + alpha[1] * om + alpha[2] * A**2 + alpha[3] * A + alpha[4]

    out = {}
    fig, ax = plt.subplots(figsize=(7.2, 4.6))
    for label, om in (("ω = 7 in Eq. 21 (as the paper)", 7.0), ("ω = 14π rad/s in Eq. 21", w)):
        c = ce(om)
        F = predict_force(t, x, model, c, omega=w, A=A, x0=x0)
        ax.plot(x, F / 1000, label=f"{label}: c_e = {c:.0f} N·s/mm")
        out[label] = {"omega_in_eq21": om, "c_e_N_s_per_mm": c, "F_min_N": float(F.min()), "F_max_N": float(F.max())}
    ax.plot(x, model.force(x) / 1000, "k--", label="elastic force F_k(x) alone")
    ax.set_xlabel("chain elongation x [mm]")
    ax.set_ylabel("force F [kN]")
    ax.set_title("Validation case x = 2.25 + 0.32 sin(14πt) mm (paper Fig. 12)")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    from chainid.infra.fileio import save_figure

    save_figure(fig, path, force=True, what="report figure", dpi=120)
    plt.close(fig)
    return out


def step_damping(folder: Path, model: Any, say: Progress) -> str:
    """Table 1 audit, Eq. 28, damping surface, validation case under both readings of ω."""
    from chainid.damping import audit

    say("damping: Table 1 audit")
    rep = audit.audit(model)
    j = dump_json(folder, "audit.json", rep)
    tb = audit.load_table1()
    _plot_table1_surface(folder / "figures" / "fig11_damping_surface.png", rep["eq28_alpha"], tb)
    say("damping: validation case")
    val = _plot_validation(folder / "figures" / "fig12_validation.png", model, rep["eq28_alpha"])
    j2 = dump_json(folder, "validation.json", val)
    return (
        "## 3. Damping: Table 1, Eq. 28 and the validation case\n\n"
        f"Eq. 28 reproduced from Table 1: α = {[round(a, 2) for a in rep['eq28_alpha']]} "
        f"(paper: [28.02, −651.57, −8386.50, 7394.84, 4378.89]). JSON: `{j}`, `{j2}`.\n\n"
        "```\n" + audit.format_audit(rep) + "\n```\n\n"
        "![Fig. 11](figures/fig11_damping_surface.png)\n\n![Fig. 12](figures/fig12_validation.png)\n"
    )


def step_identify_data(folder: Path, data: Path, model: Any, say: Progress, recs: list | None = None) -> str:
    """Identification of the user's records (``--data``; ``recs``: those records already read)."""
    from chainid.damping import identify, plots as plots_identify
    from chainid.model import laws
    from chainid.records import files as records

    note = ""
    if recs is None:
        recs = records.read_records(data, allow_compression=True)
    fmin = min(float(r.F.min()) for r in recs)
    if fmin < 0:
        # the force changes sign: not a chain under tension; identify with a fitted linear spring
        model = identify.linear_model_from_records(recs)
        note = (f"The force goes compressive (min F = {fmin:.6g} N); a chain carries none, so this step uses a linear "
                f"spring fitted on the steady cycles, k = {model.k:.4g} N/mm, x_ref = {model.x_ref:.4g} mm "
                "(as `chainid identify --model linear`).\n")
    say(f"identification of {len(recs)} tests from {data}")
    res = identify.identify_records(recs, model,
                                    progress=lambda i, n, t: say(f"identify {i}/{n}: {t}"))
    doc: dict[str, Any] = {"tests": [r.to_dict() for r in res], "model": getattr(model, "name", "?")}
    text = [f"## 3. Damping identification of `{data.name}`\n"] + ([note] if note else [])
    law = None
    if len(res) >= laws.MIN_TESTS:
        arr = {k: np.array([getattr(r, k) for r in res]) for k in ("omega", "A", "c_e", "x0")}
        ranking = laws.rank_laws(arr["omega"], arr["A"], arr["c_e"], arr["x0"], model=model)
        doc["laws"] = [{k: v for k, v in r.items() if k != "fitted"} for r in ranking]
        law = ranking[0].get("fitted")
        text.append("Damping laws ranked by leave-one-out error (best first):\n")
        text.append(md_table(["law", "parameters", "RMSE [N·s/mm]", "LOO RMSE [N·s/mm]"],
                              [[r["law"], r.get("n_params", ""), f"{r.get('rmse', float('nan')):.4g}",
                                f"{r.get('loo_rmse', float('nan')):.4g}"] for r in ranking]) + "\n")
    else:
        text.append(f"{len(res)} tests: fewer than {laws.MIN_TESTS}, no damping law fitted.\n")
    plots_identify.plot_all(recs, res, model, folder / "figures", law=law)
    j = dump_json(folder, "identify.json", doc)
    rows = [[r.test, f"{r.omega:.3f}", f"{r.x0:.3f}", f"{r.A:.3f}", f"{r.F0:.1f}", f"{r.FA:.1f}", f"{r.c_e:.2f}",
             f"{r.W:.1f}"] for r in res]
    text.append(md_table(["test", "ω [rad/s]", "x₀ [mm]", "A [mm]", "F₀ [N]", "F_A [N]", "c_e [N·s/mm]", "W [N·mm]"],
                          rows))
    text.append(f"\nJSON: `{j}`; loops in `figures/loop_*.png`.\n")
    return "\n".join(text)


# -- step 4 ----------------------------------------------------------------------

def step_gap(folder: Path, model: Any, data: Path | None, say: Progress, spec: Any = None) -> str:
    """Gap diagnosis (chainid.gap): built-in simulated series with a hidden effect and Eq. 26, or the user's data."""
    try:
        from chainid.report import gap as report_steps
    except ImportError:
        return "## 4. Gap diagnosis\n\nThe gap diagnosis module is not available in this build.\n"
    return report_steps.report_section(folder, model, data, say, spec)


# -- driver ----------------------------------------------------------------------

#: File in the report folder listing (relative paths) every file the last ``chainid report`` wrote there.
#: ``--force`` replaces and deletes only files listed in it; anything else in the folder is left alone.
MANIFEST = ".chainid-manifest.json"


def _files_under(root: Path) -> list[str]:
    return sorted(p.relative_to(root).as_posix() for p in root.rglob("*") if p.is_file() or p.is_symlink())


def _read_manifest(out: Path) -> list[str]:
    """Relative paths listed in ``out``'s manifest (unsafe entries dropped; none without a manifest)."""
    m = out / MANIFEST
    if not m.is_file():
        return []
    try:
        files = json.loads(m.read_text(encoding="utf-8")).get("files", [])
    except (OSError, ValueError, AttributeError):
        return []
    ok = []
    for rel in files:
        q = Path(str(rel))
        if isinstance(rel, str) and rel and not q.is_absolute() and ".." not in q.parts and rel != MANIFEST:
            ok.append(q.as_posix())
    return ok


def _check_not_ours(out: Path, new: list[str], ours: set[str]) -> None:
    """Refuse to replace a file in ``out`` that the previous report did not write (not in its manifest)."""
    from chainid.infra.fileio import OutputError

    for rel in new:
        dst = out / rel
        if (dst.exists() or dst.is_symlink()) and rel not in ours:
            why = "is not listed in its" if (out / MANIFEST).is_file() else "has no"
            raise OutputError(f"--out {str(out)!r}: {str(dst)!r} was not written by chainid report (the folder "
                              f"{why} manifest {MANIFEST}); refusing to replace it: move it away or choose "
                              "another folder")


def _check_swap(tmp: Path, out: Path, new: list[str]) -> None:
    """Every new file must be able to take its place in ``out`` (checked before anything is touched)."""
    from chainid.infra.fileio import OutputError

    _check_not_ours(out, new, set(_read_manifest(out)))
    for rel in new:
        dst = out / rel
        for anc in list(reversed(dst.relative_to(out).parents))[1:]:
            a = out / anc
            if a.exists() and not a.is_dir():
                raise OutputError(f"--out {str(out)!r}: {str(a)!r} is a file where the report needs a folder")
        if dst.is_dir() and not dst.is_symlink():
            raise OutputError(f"--out {str(out)!r}: {str(dst)!r} is a folder where the report writes a file")


def _swap_in(tmp: Path, out: Path, inputs: Any = ()) -> None:
    """Move the finished report from ``tmp`` into ``out``; SIGINT is held back while files move.

    ``inputs`` ((option, path) pairs): none of the files replaced or removed may be one of them.
    """
    import os

    from chainid.infra.fileio import (atomic_write_text, check_inputs_not_outputs, deferred_sigint, dumps_json,
                                      replace_file)

    new = _files_under(tmp)
    manifest = dumps_json({"written_by": "chainid report", "files": new}) + "\n"
    if not out.exists():  # a new folder: one rename
        atomic_write_text(tmp / MANIFEST, manifest, force=True, what="report manifest")
        os.chmod(tmp, 0o777 & ~_umask())
        with deferred_sigint():
            os.rename(tmp, out)
        return
    _check_swap(tmp, out, new)
    stale = [rel for rel in _read_manifest(out) if rel not in set(new)]
    check_inputs_not_outputs([("--out", out / rel) for rel in new + stale], inputs)
    with deferred_sigint():
        for rel in new:
            dst = out / rel
            dst.parent.mkdir(parents=True, exist_ok=True)
            replace_file(tmp / rel, dst, what="--out")
        for rel in stale:  # written by the previous report, not by this one
            f = out / rel
            if f.is_file() or f.is_symlink():
                f.unlink()
            for d in f.parents:  # its folders, if now empty (never out itself)
                if d == out or not d.is_dir() or any(d.iterdir()):
                    break
                d.rmdir()
        atomic_write_text(out / MANIFEST, manifest, force=True, what="report manifest")


def _umask() -> int:
    import os

    m = os.umask(0)
    os.umask(m)
    return m


def run_report(out: Path, chain_path: str | None = None, data: str | None = None, force: bool = False,
               say: Progress = _say, reader: Any = None) -> Path:
    """Run every step and write ``out/report.md`` with figures/ and json/.

    Inputs and the target are checked first; the report is built in a temporary
    folder beside ``out`` and moved in at the end, so a failure or SIGINT on the
    way leaves an existing report untouched.  With ``force`` the files of the
    previous report (listed in :data:`MANIFEST`) are replaced or removed; files
    the report did not write stay, and one that has the name of a report file
    (e.g. the user's own ``report.md`` in a folder without a manifest) is an
    error: it is never replaced.  No file replaced or removed may be ``data``
    or the chain file.

    Raises
    ------
    ValueError
        If ``out`` is a file, or exists and is not empty and ``force`` is not set,
        or cannot be written; a bad chain file or ``data`` (before any step runs).
    """
    import tempfile

    from chainid.infra.fileio import OutputError, atomic_write_text, check_output_dir
    from chainid.model.base import ChainModel
    from chainid.chain.spec import load_chain

    out = Path(out)
    if out.exists() and not out.is_dir():
        raise OutputError(f"--out {str(out)!r} is a file; give a folder")
    if out.is_dir() and any(out.iterdir()) and not force:
        raise OutputError(f"report folder {str(out)!r} exists and is not empty; pass --force to overwrite "
                          "the files of the previous report (other files are kept)")
    check_output_dir(out, "--out")
    chain = load_chain(chain_path)
    model = ChainModel(chain)
    datap = Path(data) if data else None
    recs = None
    if datap is not None:
        from chainid.records.files import read_records

        if not datap.exists() and not any(ch in str(datap) for ch in "*?["):  # a directory/glob: one file per test
            raise ValueError(f"--data {str(datap)!r} does not exist")
        # every cell checked before the first step; ``reader``: a ReaderSpec (columns, units, ... of the rig)
        recs = read_records(datap, allow_compression=True, spec=reader)
    if out.is_dir():  # a folder without our manifest: its report.md is the user's (the rest is checked at the end)
        _check_not_ours(out, ["report.md"], set(_read_manifest(out)))
    base = out.resolve()
    try:  # beside the target (same file system: the final moves are renames)
        base.parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=f".{base.name}.building-", dir=base.parent))
    except OSError:  # e.g. --out . in a folder whose parent is read-only: build inside the target
        base.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=".chainid-report.building-", dir=base))
    try:
        t0 = time.time()
        (tmp / "figures").mkdir()
        parts = ["# chainid report\n",
                 f"Chain: {'built-in 14x50 (paper)' if chain_path is None else chain_path}. "
                 f"Data: {datap.name if datap else 'built-in (paper Table 1, Eq. 26, simulated series)'}. "
                 "Units: mm, N, s, MPa, kg.\n"]
        parts.append(step_verification(tmp, say))
        parts.append(step_stiffness(tmp, chain, say))
        parts.append(step_practice(tmp, chain, say))
        parts.append(step_identify_data(tmp, datap, model, say, recs) if datap else step_damping(tmp, model, say))
        parts.append(step_gap(tmp, model, datap, say, **({"spec": reader} if reader is not None else {})))
        parts.append(f"\n_Generated by `chainid report` in {time.time() - t0:.0f} s._\n")
        atomic_write_text(tmp / "report.md", "\n".join(parts), force=True, what="report")
        _swap_in(tmp, out, [("--data", data), ("--chain", chain_path)])
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return out / "report.md"
