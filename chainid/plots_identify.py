"""Figures of the damping identification (matplotlib, Agg backend).

* :func:`plot_loop`: measured vs model hysteresis loop F(x) of one test (paper Fig. 10, 12).
* :func:`plot_damping_surface`: c_e(omega, A) of a fitted law with the identified
  test points (paper Fig. 11).
* :func:`plot_all`: both, for a whole identification, into a directory.
"""
from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any, Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .identify import DampingLaw, TestResult, predict_force  # noqa: E402
from .records import Record  # noqa: E402

__all__ = ["plot_loop", "plot_damping_surface", "plot_all"]


def _safe(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", name)


def plot_loop(
    rec: Record,
    res: TestResult,
    model: Any,
    path: str | Path,
    *,
    law: DampingLaw | None = None,
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
    ps = res.omega * tt + res.theta
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
    p = Path(path)
    fig.savefig(p)
    plt.close(fig)
    return p


def plot_damping_surface(
    results: Sequence[TestResult],
    law: DampingLaw,
    path: str | Path,
    *,
    x0: float | None = None,
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
    p = Path(path)
    with np.errstate(over="ignore", invalid="ignore"):  # mplot3d projection of far corners
        fig.savefig(p)
    plt.close(fig)
    return p


def plot_all(
    records: Sequence[Record],
    results: Sequence[TestResult],
    model: Any,
    outdir: str | Path,
    *,
    law: DampingLaw | None = None,
) -> list[Path]:
    """Write ``loop_<test>.png`` for every test and ``damping_surface.png`` (if a law) into outdir."""
    d = Path(outdir)
    d.mkdir(parents=True, exist_ok=True)
    byname = {r.test: r for r in records}
    out = [plot_loop(byname[res.test], res, model, d / f"loop_{_safe(res.test)}.png", law=law) for res in results]
    if law is not None and law.params is not None:
        out.append(plot_damping_surface(results, law, d / "damping_surface.png"))
    return out
