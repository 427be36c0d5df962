"""Parameter sweeps of the chain line (pretension × drive speed × N) on :func:`chainid.infra.parallel.run_cases`.

Every case is an independent :func:`~chainid.dynamics.integrators.simulate` run; the cases go to the same
parallel back end as ``benchmark-gap`` (dask.distributed LocalCluster by default, an existing cluster by
address, a process pool or a serial loop) with a progress bar.  Units mm, N, s, kg.
"""
from __future__ import annotations

import dataclasses
import itertools
import math
from typing import Any, Sequence

import numpy as np

from chainid.infra.parallel import run_cases
from chainid.dynamics.drives import Drive
from chainid.dynamics.simulation import simulate
from chainid.dynamics.model import ChainLine

__all__ = ["sweep", "run_case", "sweep_cases", "as_table"]


def run_case(case: dict) -> dict:
    """Run one sweep case (a top-level, picklable function for the workers).

    ``case`` holds ``line`` (ChainLine), ``drive`` (Drive), ``t_end`` [s], ``sim`` (keyword arguments of
    simulate) and the swept values ``pretension_N``, ``v`` [mm/s], ``n_masses``.  Returns the simulate summary
    plus the swept values and the peak-to-peak drive-end tension ripple over the last quarter of the run [N].
    """
    res = simulate(case["line"], case["drive"], case["t_end"], **case.get("sim", {}))
    tail = res.tension[res.t >= 0.75 * res.t[-1], 0]
    out = {k: case[k] for k in ("pretension_N", "v", "n_masses")}
    out.update(res.summary())
    out["drive_tension_ripple_N"] = float(tail.max() - tail.min()) if tail.size else math.nan
    out["drive_tension_mean_N"] = float(tail.mean()) if tail.size else math.nan
    return out


def sweep_cases(line: ChainLine, drive: Drive, t_end: float, *, pretensions: Sequence[float] | None = None,
                speeds: Sequence[float] | None = None, n_masses: Sequence[int] | None = None,
                **sim_kw: Any) -> list[dict]:
    """The cases of :func:`sweep`: the full product of the given values (the line's/drive's own by default)."""
    P = [float(p) for p in pretensions] if pretensions is not None else [line.pretension_N]
    V = [float(v) for v in speeds] if speeds is not None else [drive.v]
    Ns = [int(n) for n in n_masses] if n_masses is not None else [line.n_masses]
    for name, vals in (("pretensions", P), ("speeds", V), ("n_masses", Ns)):
        if len(vals) == 0:
            raise ValueError(f"{name} = [] is invalid: valid values are a non-empty sequence (or None)")
    cases = []
    for p, v, n in itertools.product(P, V, Ns):
        ln = dataclasses.replace(line, pretension_N=p, n_masses=n)  # validated by ChainLine
        dr = dataclasses.replace(drive, v=v)
        cases.append({"line": ln, "drive": dr, "t_end": float(t_end), "sim": dict(sim_kw),
                      "pretension_N": p, "v": v, "n_masses": n})
    return cases


def sweep(
    line: ChainLine,
    drive: Drive,
    t_end: float,
    *,
    pretensions: Sequence[float] | None = None,
    speeds: Sequence[float] | None = None,
    n_masses: Sequence[int] | None = None,
    scheduler: str | None = None,
    n_workers: int | None = None,
    progress: bool = True,
    **sim_kw: Any,
) -> list[dict]:
    """Simulate every combination pretension [N] × drive speed [mm/s] × N and return one summary per case.

    Parameters
    ----------
    line, drive : ChainLine, Drive
        The base case; the swept fields replace ``pretension_N``, ``drive.v`` and ``n_masses``.
    t_end : float
        Simulated time per case [s].
    pretensions, speeds, n_masses : sequences, optional
        Values to sweep (None: the base case's value).
    scheduler, n_workers, progress
        Passed to :func:`chainid.infra.parallel.run_cases`.
    **sim_kw
        Further keyword arguments of :func:`simulate` (``scheme``, ``peak_force``, ``n_out``, ...).

    Returns
    -------
    list of dict
        In product order (pretension slowest, N fastest): the swept values, ``peak_tension_N``,
        ``dynamic_factor``, ``drive_tension_ripple_N``, ``energy_N_mm``, ... (see :func:`run_case`).
    """
    cases = sweep_cases(line, drive, t_end, pretensions=pretensions, speeds=speeds, n_masses=n_masses, **sim_kw)
    return run_cases(run_case, cases, scheduler=scheduler, n_workers=n_workers, progress=progress,
                     desc="dynamics sweep")


def as_table(rows: list[dict], keys: Sequence[str] = ("pretension_N", "v", "n_masses", "peak_tension_N",
                                                       "dynamic_factor", "drive_tension_ripple_N")) -> np.ndarray:
    """The sweep summaries as a float array (rows × keys) for plotting."""
    return np.array([[float(r[k]) for k in keys] for r in rows])
