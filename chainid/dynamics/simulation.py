"""Simulation API of the lumped chain: stable step, :func:`simulate` and its :class:`SimResult`.

Units mm, N, s, kg; energies N·mm.  The numba cores and the two schemes are described in
:mod:`chainid.dynamics.integrators`.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from chainid.dynamics.drives import Drive
from chainid.dynamics.energy import balance
from chainid.dynamics.integrators import explicit_core, implicit_core
from chainid.dynamics.model import ChainLine

__all__ = ["SCHEMES", "SimResult", "simulate", "stable_step", "core_arguments"]

SCHEMES: tuple[str, ...] = ("explicit", "implicit")


def _bad(name: str, value: object, valid: str) -> ValueError:
    return ValueError(f"{name} = {value!r} is invalid: valid range {valid}")


def stable_step(line: ChainLine, peak_force: float | None = None) -> float:
    """Largest stable explicit step [s]: (2/ω_max)(√(1+ζ²) − ζ) from the tangent k_e at ``peak_force``.

    Parameters
    ----------
    line : ChainLine
    peak_force : float, optional
        The largest segment tension expected [N], > 0.  ``None``: the load-independent bound k_e <= 1/c_lin
        (k_e grows with the load towards the link stiffness 1/c_lin; the Hertz contact only softens it).

    Returns
    -------
    float
        dt_stable [s]; ``inf`` when no node is free.
    """
    c_lin, c_h = line.segment_coefficients()
    if peak_force is None:
        k = 1.0 / c_lin
    else:
        if not (math.isfinite(peak_force) and peak_force > 0):
            raise _bad("peak_force", peak_force, "> 0 N")
        uu = np.cbrt(peak_force)
        k = 3.0 * uu / (2.0 * c_h + 3.0 * c_lin * uu)
    c = line.segment_damping()
    m = line.node_masses()
    N = line.n_masses
    last = N if line.far_end == "tensioner" else N - 1
    w2 = 0.0
    lam_c = 0.0
    for i in range(1, last + 1):
        k_next = k[i] if i < N else line.tensioner_stiffness / 2.0
        c_next = c[i] if i < N else 0.0
        w2 = max(w2, 2e3 * (k[i - 1] + k_next) / m[i])
        lam_c = max(lam_c, 2e3 * (c[i - 1] + c_next) / m[i])
    if w2 <= 0:
        return math.inf
    w = math.sqrt(w2)
    zeta = lam_c / (2.0 * w)
    return (2.0 / w) * (math.sqrt(1.0 + zeta * zeta) - zeta)


def core_arguments(line: ChainLine, drive: Drive, dt: float, n_steps: int, out_every: int,
                   initial_u: np.ndarray | None = None, initial_v: np.ndarray | None = None) -> tuple[tuple, tuple]:
    """(arguments, output arrays) of the numba cores for a line, drive and step (used by simulate, benchmarks).

    Output arrays: t [s], tension [N], drive force [N], u [mm], v [mm/s], energies (W, E_kin, E_el, D) [N·mm]
    at every ``out_every``-th of ``n_steps`` steps of ``dt`` [s].
    """
    n_rec = n_steps // out_every + 1
    nn, N = line.n_nodes, line.n_masses
    c_lin, c_h = line.segment_coefficients()
    code, p = drive.params(line.chain.pitch)
    loads = line.loads
    u_init, v_init = np.zeros(nn), np.zeros(nn)
    for name, arr, tgt in (("initial_u", initial_u, u_init), ("initial_v", initial_v, v_init)):
        if arr is not None:
            a = np.asarray(arr, dtype=float)
            if a.shape != (nn,) or not np.all(np.isfinite(a)):
                raise _bad(name, f"array of shape {a.shape}", f"finite values, shape ({nn},) (one per node)")
            tgt[:] = a
    if line.far_end == "fixed":
        u_init[-1] = v_init[-1] = 0.0
    args = (u_init, v_init, line.node_masses(), c_lin, c_h, line.segment_damping(),
            line.pretension_elongation(), line.resistance_per_node(), float(line.resistance_v_eps),
            np.array([ld.node for ld in loads], dtype=np.int64), np.array([ld.force_N for ld in loads], dtype=float),
            np.array([ld.t_on for ld in loads], dtype=float), line.far_end == "tensioner",
            float(line.pretension_N), float(line.tensioner_stiffness), code, p, float(dt), n_steps, out_every)
    t_out, Fd_out = np.zeros(n_rec), np.zeros(n_rec)
    T_out, u_out, v_out, en_out = np.zeros((n_rec, N)), np.zeros((n_rec, nn)), np.zeros((n_rec, nn)), np.zeros((n_rec, 4))
    return args, (t_out, T_out, Fd_out, u_out, v_out, en_out)


@dataclass
class SimResult:
    """Result of :func:`simulate` (arrays over the n_out output times; units mm, N, s, N·mm).

    Attributes
    ----------
    t : (n_out,) s
    tension : (n_out, N) segment tensions T_j [N] (segment 1 at the drive first)
    drive_force : (n_out,) force the drive applies to node 0, m_0·a_0 + T_1 [N]
    u, v : (n_out, N+1) node displacements [mm] from the pre-tensioned state and speeds [mm/s]
    work_in, kinetic, elastic, dissipated : (n_out,) energies [N·mm]; work_in = drive + external work
    peak_tension : largest segment tension over all steps [N]
    static_tension : the steady (static) drive-end tension the dynamic factor refers to [N]
    dynamic_factor : peak_tension / static_tension (nan when static_tension = 0)
    dt, dt_stable : step used and the explicit stable step [s]
    scheme : "explicit" or "implicit"
    """

    t: np.ndarray
    tension: np.ndarray
    drive_force: np.ndarray
    u: np.ndarray
    v: np.ndarray
    work_in: np.ndarray
    kinetic: np.ndarray
    elastic: np.ndarray
    dissipated: np.ndarray
    peak_tension: float
    static_tension: float
    dynamic_factor: float
    dt: float
    dt_stable: float
    scheme: str
    n_steps: int
    positions: np.ndarray = field(default_factory=lambda: np.zeros(0))

    def energy_balance(self) -> dict:
        """The energy balance (see :func:`chainid.dynamics.energy.balance`)."""
        return balance(self.work_in, self.kinetic, self.elastic, self.dissipated)

    def summary(self) -> dict:
        """JSON-ready summary: peak, static, dynamic factor, steps, energy balance."""
        return {"peak_tension_N": self.peak_tension, "static_tension_N": self.static_tension,
                "dynamic_factor": self.dynamic_factor, "dt_s": self.dt, "dt_stable_s": self.dt_stable,
                "scheme": self.scheme, "n_steps": self.n_steps, "t_end_s": float(self.t[-1]),
                "energy_N_mm": self.energy_balance()}


def simulate(
    line: ChainLine,
    drive: Drive,
    t_end: float,
    *,
    dt: float | None = None,
    scheme: str = "explicit",
    peak_force: float | None = None,
    safety: float = 0.9,
    n_out: int = 500,
    initial_u: np.ndarray | None = None,
    initial_v: np.ndarray | None = None,
) -> SimResult:
    """Integrate the chain line under a drive law from the pre-tensioned static state.

    Parameters
    ----------
    line : ChainLine
    drive : Drive
    t_end : float
        Simulated time [s], > 0.
    dt : float, optional
        Step [s], > 0; with ``scheme="explicit"`` at most the stable step.  Default: ``safety·dt_stable``
        (explicit) or dt_stable·10 capped at t_end/1000 (implicit).
    scheme : str
        ``"explicit"`` or ``"implicit"``.
    peak_force : float, optional
        Expected peak tension [N] for the stable step (see :func:`stable_step`).
    safety : float
        Fraction of the stable step used by default, 0 < safety <= 1.
    n_out : int
        Output samples (>= 2) besides t = 0, at most; every ``ceil(n_steps / n_out)``-th step is stored and the
        step is shortened slightly so that the last sample is at ``t_end``.
    initial_u, initial_v : ndarray, optional
        Node displacements [mm] and speeds [mm/s] at t = 0 (length N+1; default 0, the static state).  The
        drive node follows its law and a fixed far end stays at 0 whatever is given for them.

    Returns
    -------
    SimResult

    Raises
    ------
    ValueError
        Bad input (naming the field, value and valid range), or an explicit ``dt`` above the stable step.
    FloatingPointError
        If the integration produced non-finite numbers (should not happen within the stable step).
    """
    if not isinstance(line, ChainLine):
        raise _bad("line", type(line).__name__, "a ChainLine")
    if not isinstance(drive, Drive):
        raise _bad("drive", type(drive).__name__, "a Drive")
    if scheme not in SCHEMES:
        raise _bad("scheme", scheme, f"one of {list(SCHEMES)}")
    if not (isinstance(t_end, (int, float)) and math.isfinite(t_end) and t_end > 0):
        raise _bad("t_end", t_end, "> 0 s")
    if not (0 < safety <= 1):
        raise _bad("safety", safety, "0 < safety <= 1")
    if isinstance(n_out, bool) or not isinstance(n_out, (int, np.integer)) or n_out < 2:
        raise _bad("n_out", n_out, "an int >= 2")
    dts = stable_step(line, peak_force)
    if dt is None:
        dt = safety * dts if scheme == "explicit" else min(10.0 * dts, t_end / 1000.0)
        dt = min(dt, t_end / n_out)
    else:
        if not (isinstance(dt, (int, float)) and math.isfinite(dt) and dt > 0):
            raise _bad("dt", dt, "> 0 s")
        if scheme == "explicit" and dt > dts:
            raise _bad("dt", dt, f"0 < dt <= {dts:.6g} s (the explicit stable step at "
                       f"{'peak_force = %g N' % peak_force if peak_force else 'any load'}); "
                       "use a smaller dt or scheme='implicit'")
    n_steps = int(math.ceil(t_end / dt - 1e-9))
    out_every = max(1, int(math.ceil(n_steps / n_out)))
    n_steps = int(math.ceil(n_steps / out_every)) * out_every
    dt = t_end / n_steps  # <= the requested step; the last output is at t_end
    args, outs = core_arguments(line, drive, dt, n_steps, out_every, initial_u, initial_v)
    t_out, T_out, Fd_out, u_out, v_out, en_out = outs
    core = explicit_core if scheme == "explicit" else implicit_core
    status, peak = core(*args, t_out, T_out, Fd_out, u_out, v_out, en_out)
    if status == 1:
        raise FloatingPointError(f"the {scheme} integration produced non-finite values (dt = {dt:.3g} s, "
                                 f"dt_stable = {dts:.3g} s)")
    if status == 2:
        raise FloatingPointError(f"the implicit step did not converge (dt = {dt:.3g} s); use a smaller dt")
    if scheme == "explicit" and peak_force is not None and peak > peak_force:
        dts_peak = stable_step(line, float(peak))
        if dt > dts_peak:
            warnings.warn(f"peak tension {peak:.4g} N exceeded peak_force = {peak_force:.4g} N and dt = {dt:.3g} s "
                          f"is above the stable step {dts_peak:.3g} s there: rerun with peak_force >= {peak:.4g} N",
                          RuntimeWarning, stacklevel=2)
    static = line.static_tension_at_speed() if drive.law in ("ramp", "polygon") else float(line.pretension_N)
    return SimResult(
        t=t_out, tension=T_out, drive_force=Fd_out, u=u_out, v=v_out, work_in=en_out[:, 0], kinetic=en_out[:, 1],
        elastic=en_out[:, 2], dissipated=en_out[:, 3], peak_tension=float(peak), static_tension=static,
        dynamic_factor=float(peak / static) if static > 0 else math.nan, dt=float(dt), dt_stable=float(dts),
        scheme=scheme, n_steps=n_steps,
        positions=np.concatenate([[0.0], np.cumsum(line.segment_lengths())]),
    )
