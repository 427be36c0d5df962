"""Simulation API of the lumped chain: stable step, :func:`simulate` and its :class:`SimResult`.

Units mm, N, s, kg; energies N·mm.  The numba loop and the two schemes are described in
:mod:`chainid.dynamics.integrators`.

Checks on every run: the work and memory are estimated before integrating and refused beyond
``max_work`` (node-steps) and ``max_memory`` (bytes); after the run, every energy must be finite and the
energy balance (at its worst output time, :func:`chainid.dynamics.energy.balance`) within
:data:`BALANCE_TOL`: otherwise a RuntimeWarning, or with ``strict=True`` a :class:`SimulationError`.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from chainid.dynamics.drives import Drive
from chainid.dynamics.energy import balance
from chainid.dynamics.integrators import run
from chainid.dynamics.resolution import MIN_STEPS_PER_PERIOD, resolution_warnings  # noqa: F401 (re-export)
from chainid.dynamics import line_tables
from chainid.dynamics.model import ChainLine

__all__ = ["SCHEMES", "SimResult", "SimulationError", "simulate", "stable_step", "core_arguments", "estimate",
           "BALANCE_TOL", "PEAK_TOL", "DEFAULT_MAX_MEMORY", "DEFAULT_MAX_WORK"]

SCHEMES: tuple[str, ...] = ("explicit", "implicit")
#: Largest relative energy-balance error of a trusted run (worst output time).
BALANCE_TOL = 1e-3
#: Largest relative change of the peak tension between a run and its half-step rerun (``refine`` > 0).
PEAK_TOL = 0.02
#: Default ceiling of the memory estimate [bytes] (2 GiB, as ``chainid simulate --max-memory``).
DEFAULT_MAX_MEMORY = 2 * 1024**3
#: Default ceiling of the work estimate [node-steps; an implicit node-step counts IMPLICIT_COST]: about
#: 10 min at the explicit loop's measured 3e7 node-steps/s.
DEFAULT_MAX_WORK = 2e10
#: Cost of an implicit node-step in explicit node-steps (Newton: 2-4 iterations of kernel + tangent + solve).
IMPLICIT_COST = 8.0
#: Node-steps one Newton iteration of the implicit scheme costs per node (measured: 2e7 iterations·nodes/s
#: against 3.8e7 explicit node-steps/s); the work actually done counts in these units against ``max_work``
ITERATION_COST = 2.0
#: Nominal speed of the explicit loop [node-steps/s] for the time estimate (benchmarks/dynamics_bench.py).
NODE_STEPS_PER_S = 3e7


class SimulationError(ValueError, FloatingPointError):
    """A run whose result cannot be trusted: non-finite values, a Newton failure at the shortest sub-step,
    or (with ``strict``) an energy-balance error above :data:`BALANCE_TOL`."""


def _number(name: str, value: object, valid: str, positive: bool = True) -> float:
    """``value`` as a finite float (Python or numpy int/float, never bool), > 0 if ``positive``."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise _bad(name, value, valid)
    v = float(value)
    if not math.isfinite(v) or (positive and v <= 0):
        raise _bad(name, value, valid)
    return v


def _bad(name: str, value: object, valid: str) -> ValueError:
    """The error for an invalid input: its name, its value and the valid range."""
    return ValueError(f"{name} = {value!r} is invalid: valid range {valid}")


def stable_step(line: ChainLine, peak_force: float | None = None) -> float:
    """Largest stable explicit step [s]: (2/ω_max)(√(1+ζ²) − ζ) from the tangent k_e at ``peak_force``.

    Parameters
    ----------
    line : ChainLine
    peak_force : float, optional
        The largest segment tension expected [N], > 0.  ``None``: the load-independent bound k_e <= 1/c_lin
        (k_e grows with the load towards the link stiffness 1/c_lin; the Hertz contact only softens it).
        The memory elements add their stiffest tangent (:func:`.line_tables.element_stiffness`).  A dead band
        with p > 1 stiffens without bound: its tangent is taken where its force is ``peak_force``, or without it
        twice the static load (pretension + resistance + load steps: a suddenly applied load doubles it); a run
        that still exceeds its stable step fails its checks and is refined (``refine``) or refused.

    Returns
    -------
    float
        dt_stable [s]; ``inf`` when no node is free.
    """
    c_lin, c_h = line.segment_coefficients()
    if peak_force is None:
        k = 1.0 / c_lin
    else:
        peak_force = _number("peak_force", peak_force, "> 0 N")
        uu = np.cbrt(peak_force)
        if line.contact_exponent is None:
            k = 3.0 * uu / (2.0 * c_h + 3.0 * c_lin * uu)
        else:  # x = c_lin·F + c_h·F^β: k = 1/(c_lin + β·c_h·F^(β−1))
            beta = float(line.contact_exponent)
            k = 1.0 / (c_lin + beta * c_h * peak_force ** (beta - 1.0))
    k = k + line_tables.element_stiffness(line)  # elements in parallel at their stiffest
    if line.deadband:  # no load-independent bound: the tangent at the peak force (default: twice the static load)
        F_ref = peak_force if peak_force is not None else 2.0 * max(
            line.static_tension_at_speed() + sum(abs(ld.force_N) for ld in line.loads), 1.0)
        k = k + line_tables.deadband_stiffness(line, float(F_ref))
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
    return (2.0 / w) / (math.sqrt(1.0 + zeta * zeta) + zeta)  # = (2/ω)(√(1+ζ²) − ζ), no cancellation


def core_arguments(line: ChainLine, drive: Drive, dt: float, n_steps: int, out_every: int,
                   initial_u: np.ndarray | None = None, initial_v: np.ndarray | None = None, *,
                   levels: int = 6, tol_abs: float = 1e-6, tol_rel: float = 1e-9,
                   max_it: int = 25, dt_explicit: float = 0.0) -> tuple[tuple, tuple]:
    """(arguments, output arrays) of :func:`chainid.dynamics.integrators.run` after its ``implicit`` flag.

    Output arrays: t [s], tension [N], drive force [N], u [mm], v [mm/s], energies (W, E_kin, E_stored, D)
    [N·mm] at every ``out_every``-th of ``n_steps`` steps of ``dt`` [s], and the loop statistics (4,).
    ``levels``: sub-steps down to dt/2^levels at slack/taut changes; ``tol_abs`` [N], ``tol_rel``, ``max_it``:
    Newton's tolerance and iteration limit (implicit scheme); ``dt_explicit`` [s]: sub-steps of at most this
    length that Newton cannot solve are taken by the explicit scheme (0: never).
    """
    n_rec = n_steps // out_every + 1
    nn, N = line.n_nodes, line.n_masses
    c_lin, c_h = line.segment_coefficients()
    hf, hx, hd, hq, tabs = line.segment_element_arrays()
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
    args = (u_init, v_init, line.node_masses(), c_lin, c_h, line.segment_damping(), hf, hx, hd, hq,
            line.spring_table(), tabs, line.extended_spring(), line.pretension_elongation(),
            line.resistance_per_node(), float(line.resistance_v_eps),
            np.array([ld.node for ld in loads], dtype=np.int64), np.array([ld.force_N for ld in loads], dtype=float),
            np.array([ld.t_on for ld in loads], dtype=float), line.far_end == "tensioner",
            float(line.pretension_N), float(line.tensioner_stiffness), code, p, float(dt), int(n_steps),
            int(out_every), int(levels), float(tol_abs), float(tol_rel), int(max_it), float(dt_explicit))
    t_out, Fd_out = np.zeros(n_rec), np.zeros(n_rec)
    T_out, u_out, v_out, en_out = np.zeros((n_rec, N)), np.zeros((n_rec, nn)), np.zeros((n_rec, nn)), np.zeros((n_rec, 4))
    return args, (t_out, T_out, Fd_out, u_out, v_out, en_out, np.zeros(8))


def estimate(line: ChainLine, n_steps: float, n_rec: float, scheme: str = "explicit") -> dict:
    """Work and memory of a run before it starts.

    Parameters
    ----------
    line : ChainLine
    n_steps, n_rec : float
        Steps and stored output samples.
    scheme : str

    Returns
    -------
    dict
        ``node_steps`` (steps × nodes, × IMPLICIT_COST for the implicit scheme; sub-steps at slack/taut
        changes come on top), ``seconds`` (at the nominal NODE_STEPS_PER_S) and ``bytes`` (outputs and work
        arrays).
    """
    nn, N = line.n_nodes, line.n_masses
    n_el = (len(line.specimen_elements()) + len(line.dahl) + len(line.stribeck) + len(line.bouc_wen)
            + (line.backlash_mm > 0))
    work = float(n_steps) * nn * (IMPLICIT_COST if scheme == "implicit" else 1.0)
    # per element and segment: the tables hf, hx, hd and hq's 3 columns, and the state's two copies in the loop
    mem = 8.0 * (float(n_rec) * (3 * nn + N + 5) + 40 * nn + 8 * N * n_el)
    return {"node_steps": work, "seconds": work / NODE_STEPS_PER_S, "bytes": mem}


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
    refinements : step halvings done by ``refine``; peak_change : relative change of the peak at the last one
    static_tension : the steady (static) drive-end tension the dynamic factor refers to [N]
    dynamic_factor : peak_tension / static_tension (nan when static_tension = 0)
    dt, dt_stable : step used and the explicit stable step [s]
    scheme : "explicit" or "implicit"
    n_steps : steps of dt
    substeps, rejected : accepted and rejected sub-steps (sub-steps at slack/taut changes, Newton halving)
    shortest_substep_s : the shortest sub-step taken [s]
    explicit_fallbacks : implicit sub-steps taken by the explicit scheme (Newton stuck at a damper jump)
    slack_substeps : sub-steps that ended with a segment carrying nothing (snap loads possible)
    work : work done by the run [node-steps: free nodes × sub-steps (explicit) or × Newton iterations ×
        ITERATION_COST (implicit)]
    warnings : messages of the checks (energy balance)
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
    substeps: int = 0
    rejected: int = 0
    shortest_substep_s: float = math.nan
    warnings: list = field(default_factory=list)
    refinements: int = 0
    peak_change: float = math.nan
    explicit_fallbacks: int = 0
    slack_substeps: int = 0
    work: float = 0.0

    def energy_balance(self) -> dict:
        """The energy balance at its worst output time (see :func:`chainid.dynamics.energy.balance`)."""
        return balance(self.work_in, self.kinetic, self.elastic, self.dissipated, self.t)

    def summary(self) -> dict:
        """JSON-ready summary: peak, static, dynamic factor, steps, energy balance."""
        return {"peak_tension_N": self.peak_tension, "static_tension_N": self.static_tension,
                "dynamic_factor": self.dynamic_factor, "dt_s": self.dt, "dt_stable_s": self.dt_stable,
                "scheme": self.scheme, "n_steps": self.n_steps, "t_end_s": float(self.t[-1]),
                "refinements": self.refinements, "peak_change_last_halving": self.peak_change,
                "explicit_fallback_substeps": self.explicit_fallbacks,
                "slack_substeps": self.slack_substeps, "substeps": self.substeps, "rejected_substeps": self.rejected,
                "shortest_substep_s": self.shortest_substep_s,
                "energy_N_mm": self.energy_balance(), "warnings": list(self.warnings)}


def simulate(line: ChainLine, drive: Drive, t_end: float, *, dt: float | None = None, scheme: str = "explicit",
             peak_force: float | None = None, safety: float = 0.9, n_out: int = 500,
             initial_u: np.ndarray | None = None, initial_v: np.ndarray | None = None, substep_levels: int = 6,
             strict: bool = False, max_work: float | None = DEFAULT_MAX_WORK,
             max_memory: float | None = DEFAULT_MAX_MEMORY, refine: int = 0) -> SimResult:
    """Integrate the chain line under a drive law from the pre-tensioned static state.

    Parameters
    ----------
    line : ChainLine
    drive : Drive
    t_end : float
        Simulated time [s], > 0 (Python or numpy number).
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
    substep_levels : int
        0 .. 20: the implicit scheme halves a step whose Newton iteration fails down to dt/2^levels (0: no
        halving, the run fails at once).
    strict : bool
        Raise :class:`SimulationError` when the energy balance error exceeds :data:`BALANCE_TOL` (default:
        a RuntimeWarning, and the message in ``SimResult.warnings``).
    max_work, max_memory : float or None
        Refuse runs whose estimate (:func:`estimate`) exceeds this many node-steps / bytes (None: no limit).
        ``max_work`` also bounds the work actually done, over every refinement: the sub-steps and Newton
        iterations of a stiff implicit run (a stiff hysteretic element halving its steps) are counted as they are
        taken, and a run that reaches the limit stops with a ValueError naming it.
    refine : int
        0 .. 10: adaptive step on an error estimate.  While the energy-balance error exceeds
        :data:`BALANCE_TOL`, or (when a segment went slack: snap loads) the peak tension changed by more
        than :data:`PEAK_TOL` from the previous run (the error estimate of the peak), the run is repeated with dt halved, at most ``refine`` times (the
        cost is at most twice that of the last run).  If it does not converge: a warning (``strict``: an
        error).  0: one run, balance check only.  Why this and not sub-stepping at each slack/taut change: a
        variable step breaks Verlet's time reversibility; bisecting the transitions (tried, to dt/64) left a
        balance drift of 1e-2 and scattered the peak of the slack polygon drive by ±5 %, while constant-step
        runs converge as dt² (balance 0.89, 3.4e-3, 1.7e-4 at dt = 250, 62.5, 15.6 µs) with peaks within
        1.1 % (see docs/dynamics_convergence.md).

    Returns
    -------
    SimResult

    Raises
    ------
    ValueError
        Bad input (naming the field, value and valid range), an explicit ``dt`` above the stable step, or an
        estimate beyond ``max_work`` / ``max_memory``.
    SimulationError
        (a ValueError and FloatingPointError) non-finite values, a Newton failure at the shortest sub-step,
        or with ``strict`` an energy-balance error above :data:`BALANCE_TOL`.
    """
    t_end, safety = _checked_inputs(line, drive, t_end, scheme, safety, n_out, substep_levels, refine, max_work,
                                    max_memory)
    dts = stable_step(line, peak_force)
    dt = _first_step(dt, dts, scheme, safety, t_end, n_out, peak_force)
    res, prev, eb = _refined_runs(line, drive, t_end, dt, dts, scheme, n_out, initial_u, initial_v, substep_levels,
                                  max_work, max_memory, refine, peak_force)
    msgs = _run_messages(line, drive, t_end, scheme, peak_force, refine, strict, res, prev, eb, dt)
    for m in msgs:
        warnings.warn(m, RuntimeWarning, stacklevel=2)
    res.warnings = msgs
    return res


def _first_step(dt: float | None, dts: float, scheme: str, safety: float, t_end: float, n_out: int,
                peak_force: float | None) -> float:
    """The first run's step [s]: the given ``dt`` checked (> 0; explicit: at most the stable step ``dts`` [s]), or
    the default (``safety·dts`` explicit, ``10·dts`` up to t_end/1000 implicit; at most t_end/n_out)."""
    if dt is None:
        dt = safety * dts if scheme == "explicit" else min(10.0 * dts, t_end / 1000.0)
        dt = min(dt, t_end / n_out)
    else:
        dt = _number("dt", dt, "> 0 s (a finite number)")
        if scheme == "explicit" and dt > dts:
            raise _bad("dt", dt, f"0 < dt <= {dts:.6g} s (the explicit stable step at "
                       f"{'peak_force = %g N' % peak_force if peak_force else 'any load'}); "
                       "use a smaller dt or scheme='implicit'")
    return dt


def _refined_runs(line: ChainLine, drive: Drive, t_end: float, dt: float, dts: float, scheme: str, n_out: int,
                  initial_u: np.ndarray | None, initial_v: np.ndarray | None, substep_levels: int,
                  max_work: float | None, max_memory: float | None, refine: int,
                  peak_force: float | None) -> tuple[SimResult, SimResult | None, dict]:
    """Runs from step ``dt`` [s], halved while a run fails or its energy balance or (slack) peak [N] is not
    converged, at most ``refine`` times: (the last run with its ``refinements``, the run before it or None, the
    last run's energy balance); SimulationError when the last attempt fails."""
    prev: SimResult | None = None
    spent = [0.0]  # work done by the runs so far [node-steps] (max_work bounds them all)
    for attempt in range(refine + 1):
        try:
            res = _run_once(line, drive, t_end, dt, dts, scheme, n_out, initial_u, initial_v, substep_levels,
                            max_work, max_memory, spent)
        except SimulationError as exc:  # non-finite or Newton failure: the strongest error estimate there is
            if attempt == refine:
                hint = (f"; peak_force = {peak_force:g} N sets the stable step: give the expected peak"
                        if peak_force is not None and scheme == "explicit" else "")
                raise SimulationError(f"{exc}{hint}") from None
            dt = dt / 2.0
            continue
        eb = res.energy_balance()
        if prev is not None:
            res.peak_change = abs(res.peak_tension - prev.peak_tension) / max(res.peak_tension, 1e-300)
        snaps = res.slack_substeps > 0  # the peak is checked under halving only where snap loads can occur
        if eb["relative_error"] <= BALANCE_TOL and (refine == 0 or not snaps or res.peak_change <= PEAK_TOL) \
                or attempt == refine:
            break
        prev = res
        dt = res.dt / 2.0
    res.refinements = attempt
    return res, prev, eb


def _checked_inputs(line: ChainLine, drive: Drive, t_end: float, scheme: str, safety: float, n_out: int,
                    substep_levels: int, refine: int, max_work: float | None,
                    max_memory: float | None) -> tuple[float, float]:
    """Check :func:`simulate`'s inputs (ValueError naming the first bad one): (t_end [s], safety) as floats."""
    if not isinstance(line, ChainLine):
        raise _bad("line", type(line).__name__, "a ChainLine")
    if not isinstance(drive, Drive):
        raise _bad("drive", type(drive).__name__, "a Drive")
    if scheme not in SCHEMES:
        raise _bad("scheme", scheme, f"one of {list(SCHEMES)}")
    t_end = _number("t_end", t_end, "> 0 s (a finite number)")
    safety = _number("safety", safety, "0 < safety <= 1")
    if safety > 1:
        raise _bad("safety", safety, "0 < safety <= 1")
    if isinstance(n_out, (bool, np.bool_)) or not isinstance(n_out, (int, np.integer)) or n_out < 2:
        raise _bad("n_out", n_out, "an int >= 2")
    if isinstance(substep_levels, (bool, np.bool_)) or not isinstance(substep_levels, (int, np.integer)) \
            or not 0 <= substep_levels <= 20:
        raise _bad("substep_levels", substep_levels, "an int 0 .. 20")
    if isinstance(refine, (bool, np.bool_)) or not isinstance(refine, (int, np.integer)) or not 0 <= refine <= 10:
        raise _bad("refine", refine, "an int 0 .. 10")
    for name, lim in (("max_work", max_work), ("max_memory", max_memory)):
        if lim is not None:
            _number(name, lim, "> 0 (or None)")
    return t_end, safety


def _run_messages(line: ChainLine, drive: Drive, t_end: float, scheme: str, peak_force: float | None, refine: int,
                  strict: bool, res: SimResult, prev: SimResult | None, eb: dict, dt0: float) -> list[str]:
    """Warnings on the final run (refinement, peak [N], step [s], drive resolution, energy balance); strict raises."""
    msgs: list[str] = []
    if res.refinements:
        msgs.append(f"step refined {res.refinements} time(s) (energy balance and peak under halving): "
                    f"dt {dt0:.3g} s -> {res.dt:.3g} s")
    if refine and res.slack_substeps > 0 and not res.peak_change <= PEAK_TOL:
        msgs.append(f"peak tension not converged under step refinement: {res.peak_tension:.6g} N at dt = "
                    f"{res.dt:.3g} s vs {prev.peak_tension if prev else math.nan:.6g} N at twice that step "
                    f"({100 * res.peak_change:.3g} % > {100 * PEAK_TOL:g} %): snap loads make the peak sensitive; "
                    "raise --refine or give a smaller --dt")
        if strict:
            raise SimulationError(f"strict: {msgs[-1]}")
    if scheme == "explicit" and peak_force is not None and res.peak_tension > peak_force:
        peak = res.peak_tension
        dts_peak = stable_step(line, float(peak))
        if res.dt > dts_peak:
            msgs.append(f"peak tension {peak:.4g} N exceeded peak_force = {peak_force:.4g} N and dt = {res.dt:.3g} s "
                        f"is above the stable step {dts_peak:.3g} s there: rerun with peak_force >= {peak:.4g} N")
    msgs += resolution_warnings(drive, line.chain.pitch, res.dt,
                                float(res.t[1] - res.t[0]) if res.t.size > 1 else t_end)
    if eb["relative_error"] > BALANCE_TOL:
        msgs.append(f"energy balance error {eb['relative_error']:.3g} at t = {eb['worst_t_s']:.6g} s exceeds "
                    f"{BALANCE_TOL:g} ({scheme}, dt = {res.dt:.3g} s): the result is not converged; use a smaller dt "
                    "or more refinements (and compare the peak under step refinement)")
        if strict:
            raise SimulationError(f"strict: {msgs[-1]}")
    return msgs


def _run_once(line: ChainLine, drive: Drive, t_end: float, dt: float, dts: float, scheme: str, n_out: int,
              initial_u: np.ndarray | None, initial_v: np.ndarray | None, levels: int,
              max_work: float | None, max_memory: float | None, spent: list[float] | None = None) -> SimResult:
    """One run at step ``dt`` (checked against the limits first); raises SimulationError on a failed run.

    ``spent``: a one-item list with the work of the earlier runs [node-steps], updated with this run's; the
    kernel stops when the total reaches ``max_work`` (ValueError naming the limit and --max-work)."""
    spent = [0.0] if spent is None else spent
    steps = t_end / dt if dt > 0 else math.inf
    n_rec = min(float(n_out), steps) + 1
    est = estimate(line, steps, n_rec, scheme)
    if max_work is not None and not est["node_steps"] <= max_work:
        raise ValueError(f"the run would take about {est['node_steps']:.3g} node-steps ({steps:.3g} steps of "
                         f"dt = {dt:.3g} s for t_end = {t_end:g} s, {line.n_nodes} nodes; about "
                         f"{est['seconds']:.3g} s), over max_work = {max_work:.3g} node-steps: valid range <= the "
                         "limit; use a shorter t_end, a larger dt, fewer masses, or raise --max-work")
    if max_memory is not None and not est["bytes"] <= max_memory:
        raise ValueError(f"the run would need about {est['bytes'] / 1024**3:.3g} GiB ({n_rec:.4g} output samples x "
                         f"{line.n_nodes} nodes), over max_memory = {max_memory / 1024**3:.3g} GiB: valid range <= "
                         "the limit; use a smaller n_out, fewer masses, or raise --max-memory")
    n_steps = int(math.ceil(steps - 1e-9))
    out_every = max(1, int(math.ceil(n_steps / n_out)))
    n_steps = int(math.ceil(n_steps / out_every)) * out_every
    dt = t_end / n_steps  # <= the requested step; the last output is at t_end
    levels = int(levels)
    args, outs = core_arguments(line, drive, dt, n_steps, out_every, initial_u, initial_v, levels=levels,
                                dt_explicit=0.9 * dts)
    t_out, T_out, Fd_out, u_out, v_out, en_out, stats = outs
    cost = ITERATION_COST if scheme == "implicit" else 1.0  # node-steps per counted unit of the kernel
    budget = 0.0 if max_work is None else max(float(max_work) - spent[0], 1.0) / cost
    status, peak = run(scheme == "implicit", *args, *outs, kind=0, budget=budget)
    spent[0] += float(stats[6]) * cost
    if status == 3:
        raise ValueError(f"the run stopped at t = {stats[7] * dt:.4g} s of t_end = {t_end:g} s after about "
                         f"{spent[0]:.3g} node-steps of work ({int(stats[0])} sub-steps taken, {int(stats[1])} rejected, "
                         f"Newton iterations up to {int(stats[2])} per sub-step; the estimate was "
                         f"{est['node_steps']:.3g}): over max_work = {max_work:.3g} node-steps: valid range <= the "
                         "limit; raise --max-work (max_work), or use the explicit scheme, a smaller dt or softer "
                         "elements (a stiff hysteretic element makes the implicit scheme halve its sub-steps)")
    if status == 1:
        raise SimulationError(f"the {scheme} integration produced non-finite values (dt = {dt:.3g} s, "
                              f"dt_stable = {dts:.3g} s): no result")
    if status == 2:
        raise SimulationError(f"the implicit step did not converge even at dt/{2 ** levels} = "
                              f"{dt / 2 ** levels:.3g} s (dt = {dt:.3g} s); use a smaller dt")
    static = line.static_tension_at_speed() if drive.law in ("ramp", "polygon") else float(line.pretension_N)
    res = SimResult(
        t=t_out, tension=T_out, drive_force=Fd_out, u=u_out, v=v_out, work_in=en_out[:, 0], kinetic=en_out[:, 1],
        elastic=en_out[:, 2], dissipated=en_out[:, 3], peak_tension=float(peak), static_tension=static,
        dynamic_factor=float(peak / static) if static > 0 else math.nan, dt=float(dt), dt_stable=float(dts),
        scheme=scheme, n_steps=n_steps,
        positions=np.concatenate([[0.0], np.cumsum(line.segment_lengths())]),
        substeps=int(stats[0]), rejected=int(stats[1]), shortest_substep_s=float(stats[3] * dt),
        explicit_fallbacks=int(stats[4]), slack_substeps=int(stats[5]), work=float(stats[6]) * cost,
    )
    if not res.energy_balance()["finite"]:
        raise SimulationError(f"the {scheme} integration produced non-finite energies (dt = {dt:.3g} s): no result")
    return res
