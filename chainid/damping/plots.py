"""Figures of the damping identification (matplotlib, Agg backend).

* :func:`plot_loop`: measured vs model hysteresis loop F(x) of one test (paper Fig. 10, 12).
* :func:`plot_damping_surface`: c_e(omega, A) of a fitted law with the identified
  test points (paper Fig. 11).
* :func:`plot_all`: both, for a whole identification, into a directory.
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from chainid.model.laws import DampingLaw

from chainid.model.predict import predict_force

from chainid.damping.identify import TestResult  # noqa: E402
from chainid.records.files import Record  # noqa: E402

__all__ = ["plot_loop", "plot_damping_surface", "plot_all", "plot_names"]


def _safe(name: str) -> str:
    """Injective file-name part for a test id ("T 1", "T_1", "T/1" differ); see :func:`chainid.infra.fileio.safe_filename`."""
    from chainid.infra.fileio import safe_filename

    return safe_filename(name)


def plot_names(tests: Sequence[str], surface: bool = True) -> list[str]:
    """File names :func:`plot_all` writes for these test ids (``loop_<id>.png`` …, ``damping_surface.png``)."""
    return [f"loop_{_safe(t)}.png" for t in tests] + (["damping_surface.png"] if surface else [])


def plot_loop(
    rec: Record,
    res: TestResult,
    model: Any,
    path: str | Path,
    *,
    law: DampingLaw | None = None,
    force: bool = True,
) -> Path:
    """Measured vs model hysteresis loop of one test (Fig. 10 / 12).

    The model loops use Eq. 1 on the measured steady window with the test's own
    c_e and, if given, the law's c_e(omega, A, x0); velocity and acceleration are
    those of the fitted harmonic.

    Parameters
    ----------
    rec : Record
        t [s], x [mm], F [N].
    res : TestResult
        Its identification.
    model : StiffnessModel
    path : str or Path
        PNG to write.
    law : DampingLaw, optional
        Fitted law to overlay.
    force : bool
        Replace an existing file (default True); written atomically either way.

    Returns
    -------
    Path
    """
    m = (rec.t >= res.t_start) & (rec.t < res.t_end)
    x, F = rec.x[m], rec.F[m]
    fig, ax = plt.subplots(figsize=(6.4, 4.8), dpi=110)
    ax.plot(x, F * 1e-3, ".", ms=2, color="0.45", label="measured (steady cycles)")
    # one cycle of the model on a smooth harmonic x for clarity
    tt = np.linspace(res.t_start, res.t_start + 2 * math.pi / res.omega, 400)
    ps = res.omega * (tt - res.t_origin) + res.theta
    xh = res.x0 + res.A * np.sin(ps)
    xdh = res.omega * res.A * np.cos(ps)
    xddh = -res.omega**2 * res.A * np.sin(ps)
    Fm = predict_force(tt, xh, model, res.c_e, xdot=xdh, xddot=xddh, mass_kg=res.mass_kg)
    ax.plot(xh, Fm * 1e-3, "-", color="C0", lw=1.8, label=f"model, test c_e = {res.c_e:.4g} N·s/mm")
    if law is not None and law.params is not None:
        c = float(law.predict(res.omega, res.A, res.x0)[0])
        Fl = predict_force(tt, xh, model, c, xdot=xdh, xddot=xddh, mass_kg=res.mass_kg)
        ax.plot(xh, Fl * 1e-3, "--", color="C3", lw=1.5, label=f"model, {law.name} law c_e = {c:.4g} N·s/mm")
    Fk = np.asarray(model.force(xh), dtype=float)
    ax.plot(xh, Fk * 1e-3, ":", color="k", lw=1.0, label="elastic force F_k(x)")
    ax.set_xlabel("elongation x [mm]")
    ax.set_ylabel("force F [kN]")
    ax.set_title(
        f"test {res.test}: ω = {res.omega:.4g} rad/s, x0 = {res.x0:.3g} mm, A = {res.A:.3g} mm\n"
        f"W = {res.W:.4g} N·mm, W/(π c_e ω A²) = {res.W_ratio:.3f}",
        fontsize=9,
    )
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    return _save(fig, path, force)


def plot_damping_surface(
    results: Sequence[TestResult],
    law: DampingLaw,
    path: str | Path,
    *,
    x0: float | None = None,
    force: bool = True,
) -> Path:
    """Damping surface c_e(omega, A) of a fitted law with the identified test points (Fig. 11).

    Parameters
    ----------
    results : sequence of TestResult
        Identified tests (omega rad/s, A mm, c_e N·s/mm).
    law : DampingLaw
        Fitted law.
    path : str or Path
        PNG to write.
    x0 : float, optional
        Mean elongation [mm] for laws that need it (default: mean of the tests).
    force : bool
        Replace an existing file (default True); written atomically either way.

    Returns
    -------
    Path
    """
    w = np.array([r.omega for r in results])
    a = np.array([r.A for r in results])
    c = np.array([r.c_e for r in results])
    x0v = float(np.mean([r.x0 for r in results])) if x0 is None else float(x0)
    wpad = 0.1 * (w.max() - w.min() or w.max())
    apad = 0.1 * (a.max() - a.min() or a.max())
    W, Aa = np.meshgrid(
        np.linspace(max(w.min() - wpad, 1e-3), w.max() + wpad, 80),
        np.linspace(max(a.min() - apad, 1e-4), a.max() + apad, 80),
    )
    C = law.predict(W.ravel(), Aa.ravel(), np.full(W.size, x0v)).reshape(W.shape)
    fig = plt.figure(figsize=(10.5, 4.6), dpi=110)
    ax3 = fig.add_subplot(1, 2, 1, projection="3d")
    ax3.plot_surface(W, Aa, C, cmap="viridis", alpha=0.45, linewidth=0, zorder=1)
    ax3.scatter(w, a, c, color="red", edgecolors="k", s=30, depthshade=False, zorder=10, label="identified tests")
    ax3.set_xlabel("ω [rad/s]")
    ax3.set_ylabel("A [mm]")
    ax3.set_zlabel("c_e [N·s/mm]")
    ax3.set_title(f"{law.name} law", fontsize=9)
    ax3.legend(fontsize=8, loc="upper left")
    ax = fig.add_subplot(1, 2, 2)
    cs = ax.contourf(W, Aa, C, levels=20, cmap="viridis")
    fig.colorbar(cs, ax=ax, label="c_e [N·s/mm]")
    ax.scatter(w, a, c=c, cmap="viridis", norm=cs.norm, edgecolors="r", s=50, label="identified tests")
    for r in results:
        ax.annotate(str(r.test), (r.omega, r.A), textcoords="offset points", xytext=(4, 4), fontsize=7, color="w")
    ax.set_xlabel("ω [rad/s]")
    ax.set_ylabel("A [mm]")
    ax.set_title("c_e(ω, A); points coloured by identified c_e", fontsize=9)
    ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    with np.errstate(over="ignore", invalid="ignore"):  # mplot3d projection of far corners
        return _save(fig, path, force)


def _save(fig: plt.Figure, path: str | Path, force: bool) -> Path:
    from chainid.infra.fileio import save_figure

    try:
        return save_figure(fig, path, force=force, what="--plots")
    finally:
        plt.close(fig)


def plot_all(
    records: Sequence[Record],
    results: Sequence[TestResult],
    model: Any,
    outdir: str | Path,
    *,
    law: DampingLaw | None = None,
    force: bool = True,
) -> list[Path]:
    """Write ``loop_<test>.png`` for every test and ``damping_surface.png`` (if a law) into outdir.

    ``<test>`` is the test id made file-safe and injective (:func:`chainid.infra.fileio.safe_filename`),
    so every test gets its own file.  Each file is written atomically; with ``force`` False an
    existing file is an error (checked for all files before the first is drawn).

    Returns
    -------
    list of Path
        The files written (one per test, plus the surface).
    """
    from chainid.infra.fileio import check_output_dir

    d = Path(outdir)
    surface = law is not None and law.params is not None
    names = plot_names([res.test for res in results], surface)
    check_output_dir(d, "--plots", names, force=force)
    d.mkdir(parents=True, exist_ok=True)
    byname = {r.test: r for r in records}
    out = [plot_loop(byname[res.test], res, model, d / n, law=law, force=force) for res, n in zip(results, names)]
    if surface:
        out.append(plot_damping_surface(results, law, d / names[-1], force=force))
    return out
