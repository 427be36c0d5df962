"""Time integration of the lumped chain in numba, directly on the generated kernels.

Two schemes (units mm, N, s, kg; accelerations a = 1e3·f/m mm/s² for f in N and m in kg):

``"explicit"``  velocity Verlet (central difference, kick-drift-kick; the damper and the moving resistance
                see the half-step velocity).  Stable for dt <= dt_stable = (2/ω_max)(√(1+ζ²) − ζ), with
                ω_max² the Gershgorin bound max_i 2·1e3·(k_{i−1} + k_i)/m_i of the tangent stiffnesses k_e at
                the peak load (``peak_force``; by default the bound k_e <= 1/c_lin, safe at any load) and
                ζ from the dampers the same way.  One F_k evaluation per segment and step.
``"implicit"``  Newmark's average acceleration (trapezoidal rule: unconditionally stable, no numerical
                damping), solved by Newton's method on the tangent k_e with a tridiagonal (Thomas) solve in
                numba.  For very short (stiff) segments where dt_stable is tiny.

Both use the generated kernels' scalar functions (``chainid.generated.stiffness_paper.force`` and
``stiffness``, inlined by numba).  The kernels of all variants share this math and differ only in their
coefficients (``coefficients()``), which the chain line computes for its variant.  Work, dissipation,
kinetic and elastic energy are accumulated by the trapezoidal rule on the same steps (:mod:`.energy`).
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import numpy as np
from numba import njit

from ..generated.stiffness_paper import force as _force
from ..generated.stiffness_paper import stiffness as _stiffness
from .drives import Drive, drive_state
from .energy import balance, elastic_energy_array
from .model import ChainLine

__all__ = ["SCHEMES", "SimResult", "simulate", "stable_step"]

SCHEMES: tuple[str, ...] = ("explicit", "implicit")
_FM = {"contract", "arcp", "nsz"}


# ---------------------------------------------------------------------------------------------- kernels
@njit(cache=True, fastmath=_FM, error_model="numpy")
def _segments(u, v, du, epre, cl, ch, cd, T, dprev):
    """Tensions T_j [N] and the trapezoidal damper work over the last step [N·mm]; peak tension."""
    N = T.shape[0]
    dw = 0.0
    peak = 0.0
    for j in range(N):
        e = epre[j] + u[j] - u[j + 1]
        f = _force(e, cl[j], ch[j])
        t = f + cd[j] * (v[j] - v[j + 1])
        t = t if t > 0.0 else 0.0
        t = t if e > 0.0 else 0.0
        d = t - f if e > 0.0 else 0.0
        dw += 0.5 * (dprev[j] + d) * (du[j] - du[j + 1])
        dprev[j] = d
        T[j] = t
        peak = max(peak, t)
    return dw, peak


@njit(cache=True, fastmath=_FM, error_model="numpy")
def _external(t, u, v, res, veps, load_node, load_F, load_t, tens, Ft, kt, fe):
    """External forces on the nodes [N]: resistance, load steps, tensioner (into fe)."""
    nn = u.shape[0]
    for i in range(nn):
        vi = v[i]
        fe[i] = -res[i] * vi / math.sqrt(vi * vi + veps * veps)
    for k in range(load_node.shape[0]):
        if t >= load_t[k]:
            fe[load_node[k]] -= load_F[k]
    if tens:
        fe[nn - 1] -= Ft + kt * u[nn - 1]


@njit(cache=True)
def _record(k, t, u, v, m, T, Fd, epre, cl, ch, W, D, t_out, T_out, Fd_out, u_out, v_out, en_out):
    t_out[k] = t
    T_out[k, :] = T
    Fd_out[k] = Fd
    u_out[k, :] = u
    v_out[k, :] = v
    ek = 0.0
    for i in range(u.shape[0]):
        ek += 0.5e-3 * m[i] * v[i] * v[i]
    N = T.shape[0]
    e = np.empty(N)
    for j in range(N):
        e[j] = epre[j] + u[j] - u[j + 1]
    en_out[k, 0] = W
    en_out[k, 1] = ek
    en_out[k, 2] = elastic_energy_array(e, cl, ch)
    en_out[k, 3] = D


@njit(cache=True, fastmath=_FM, error_model="numpy")
def _explicit(u, v, m, cl, ch, cd, epre, res, veps, load_node, load_F, load_t, tens, Ft, kt, code, p,
              dt, n_steps, out_every, t_out, T_out, Fd_out, u_out, v_out, en_out):
    nn = u.shape[0]
    N = nn - 1
    last = N if tens else N - 1  # last free node
    has_ext = tens or load_node.shape[0] > 0 or np.any(res > 0.0)
    T = np.zeros(N)
    dprev = np.zeros(N)
    du = np.zeros(nn)
    fe = np.zeros(nn)
    feprev = np.zeros(nn)
    acc = np.zeros(nn)
    inv = np.zeros(nn)
    for i in range(1, last + 1):
        inv[i] = 1e3 / m[i]
    u0, v0, a0 = drive_state(0.0, code, p)
    u[0] = u0
    v[0] = v0
    _, peak = _segments(u, v, du, epre, cl, ch, cd, T, dprev)
    if has_ext:
        _external(0.0, u, v, res, veps, load_node, load_F, load_t, tens, Ft, kt, feprev)
    for i in range(1, last + 1):
        nxt = T[i] if i < N else 0.0
        acc[i] = (T[i - 1] - nxt + feprev[i]) * inv[i]
    Fd = 1e-3 * m[0] * a0 + T[0]
    W = 0.0
    D = 0.0
    _record(0, 0.0, u, v, m, T, Fd, epre, cl, ch, W, D, t_out, T_out, Fd_out, u_out, v_out, en_out)
    status = 0
    for n in range(n_steps):
        t1 = (n + 1) * dt
        for i in range(1, last + 1):
            v[i] += 0.5 * dt * acc[i]
            du[i] = dt * v[i]
            u[i] += du[i]
        u0, v0, a0 = drive_state(t1, code, p)
        du[0] = u0 - u[0]
        u[0] = u0
        v[0] = v0
        dD, pk = _segments(u, v, du, epre, cl, ch, cd, T, dprev)
        D += dD
        peak = max(peak, pk)
        if has_ext:
            _external(t1, u, v, res, veps, load_node, load_F, load_t, tens, Ft, kt, fe)
            for i in range(1, last + 1):
                W += 0.5 * (feprev[i] + fe[i]) * du[i]
                feprev[i] = fe[i]
        for i in range(1, N):
            acc[i] = (T[i - 1] - T[i] + fe[i]) * inv[i]
        if tens:
            acc[N] = (T[N - 1] + fe[N]) * inv[N]
        for i in range(1, last + 1):
            v[i] += 0.5 * dt * acc[i]
        Fd1 = 1e-3 * m[0] * a0 + T[0]
        W += 0.5 * (Fd + Fd1) * du[0]
        Fd = Fd1
        if (n + 1) % out_every == 0:
            if not math.isfinite(peak + u[last]):
                status = 1
                break
            _record((n + 1) // out_every, t1, u, v, m, T, Fd, epre, cl, ch, W, D,
                    t_out, T_out, Fd_out, u_out, v_out, en_out)
    return status, peak


@njit(cache=True, fastmath=_FM, error_model="numpy")
def _thomas(lo, di, up, r, x):
    """Solve the tridiagonal system (lo: sub, di: diagonal, up: super diagonal) for x; r is overwritten."""
    n = di.shape[0]
    c = np.empty(n)
    b = di[0]
    x[0] = r[0] / b
    for i in range(1, n):
        c[i] = up[i - 1] / b
        b = di[i] - lo[i] * c[i]
        x[i] = (r[i] - lo[i] * x[i - 1]) / b
    for i in range(n - 2, -1, -1):
        x[i] -= c[i + 1] * x[i + 1]


@njit(cache=True, fastmath=_FM, error_model="numpy")
def _implicit(u, v, m, cl, ch, cd, epre, res, veps, load_node, load_F, load_t, tens, Ft, kt, code, p,
              dt, n_steps, out_every, t_out, T_out, Fd_out, u_out, v_out, en_out):
    nn = u.shape[0]
    N = nn - 1
    nf = N if tens else N - 1  # free nodes 1..nf
    T = np.zeros(N)
    dprev = np.zeros(N)
    du = np.zeros(nn)
    fe = np.zeros(nn)
    feprev = np.zeros(nn)
    acc = np.zeros(nn)
    un = np.zeros(nn)
    vn = np.zeros(nn)
    ks = np.zeros(N)
    cs = np.zeros(N)
    lo = np.zeros(max(nf, 1))
    di = np.zeros(max(nf, 1))
    up = np.zeros(max(nf, 1))
    r = np.zeros(max(nf, 1))
    dx = np.zeros(max(nf, 1))
    u0, v0, a0 = drive_state(0.0, code, p)
    u[0] = u0
    v[0] = v0
    _, peak = _segments(u, v, du, epre, cl, ch, cd, T, dprev)
    _external(0.0, u, v, res, veps, load_node, load_F, load_t, tens, Ft, kt, feprev)
    for i in range(1, nf + 1):
        nxt = T[i] if i < N else 0.0
        acc[i] = 1e3 * (T[i - 1] - nxt + feprev[i]) / m[i]
    Fd = 1e-3 * m[0] * a0 + T[0]
    W = 0.0
    D = 0.0
    _record(0, 0.0, u, v, m, T, Fd, epre, cl, ch, W, D, t_out, T_out, Fd_out, u_out, v_out, en_out)
    status = 0
    anew = acc.copy()
    for n in range(n_steps):
        t1 = (n + 1) * dt
        u0, v0, a0 = drive_state(t1, code, p)
        un[0] = u0
        vn[0] = v0
        if not tens:
            un[N] = u[N]
            vn[N] = v[N]
        converged = False
        for it in range(30):
            for i in range(1, nf + 1):
                un[i] = u[i] + dt * v[i] + 0.25 * dt * dt * (acc[i] + anew[i])
                vn[i] = v[i] + 0.5 * dt * (acc[i] + anew[i])
            fmax = 0.0
            for j in range(N):
                e = epre[j] + un[j] - un[j + 1]
                f = _force(e, cl[j], ch[j])
                t = f + cd[j] * (vn[j] - vn[j + 1])
                taut = e > 0.0 and t > 0.0
                T[j] = t if taut else 0.0
                ks[j] = _stiffness(e, cl[j], ch[j]) if taut else 0.0
                cs[j] = cd[j] if taut else 0.0
                fmax = max(fmax, abs(T[j]))
            _external(t1, un, vn, res, veps, load_node, load_F, load_t, tens, Ft, kt, fe)
            rmax = 0.0
            for i in range(1, nf + 1):
                nxt = T[i] if i < N else 0.0
                kn = ks[i] if i < N else (kt if tens else 0.0)
                cn = cs[i] if i < N else 0.0
                vi = vn[i]
                s2 = vi * vi + veps * veps
                cres = res[i] * veps * veps / (s2 * math.sqrt(s2))  # d(resistance)/dv
                k = i - 1
                r[k] = -(1e-3 * m[i] * anew[i] - (T[i - 1] - nxt + fe[i]))
                di[k] = 1e-3 * m[i] + 0.5 * dt * (cs[i - 1] + cn + cres) + 0.25 * dt * dt * (ks[i - 1] + kn)
                lo[k] = -(0.5 * dt * cs[i - 1] + 0.25 * dt * dt * ks[i - 1])
                up[k] = -(0.5 * dt * cn + 0.25 * dt * dt * (ks[i] if i < N else 0.0))
                rmax = max(rmax, abs(r[k]))
            if rmax <= 1e-10 * (1.0 + fmax) or nf == 0:
                converged = True
                break
            _thomas(lo[:nf], di[:nf], up[:nf], r[:nf], dx[:nf])
            for i in range(1, nf + 1):
                anew[i] += dx[i - 1]
        if not converged:
            status = 2
            break
        for i in range(nn):
            du[i] = un[i] - u[i]
        pk = 0.0
        dD = 0.0
        for j in range(N):
            e = epre[j] + un[j] - un[j + 1]
            d = T[j] - _force(e, cl[j], ch[j]) if T[j] > 0.0 else (0.0 if e <= 0.0 else -_force(e, cl[j], ch[j]))
            dD += 0.5 * (dprev[j] + d) * (du[j] - du[j + 1])
            dprev[j] = d
            pk = max(pk, T[j])
        D += dD
        peak = max(peak, pk)
        for i in range(1, nf + 1):
            W += 0.5 * (feprev[i] + fe[i]) * du[i]
            feprev[i] = fe[i]
        for i in range(nn):
            u[i] = un[i]
            v[i] = vn[i]
            acc[i] = anew[i]
        Fd1 = 1e-3 * m[0] * a0 + T[0]
        W += 0.5 * (Fd + Fd1) * du[0]
        Fd = Fd1
        if (n + 1) % out_every == 0:
            if not math.isfinite(peak + u[N]):
                status = 1
                break
            _record((n + 1) // out_every, t1, u, v, m, T, Fd, epre, cl, ch, W, D,
                    t_out, T_out, Fd_out, u_out, v_out, en_out)
    return status, peak


# ---------------------------------------------------------------------------------------------- python API
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
    core = _explicit if scheme == "explicit" else _implicit
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
