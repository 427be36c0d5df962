"""Time integration of the lumped chain in numba, directly on the generated kernels (the compiled cores).

Two schemes (units mm, N, s, kg; accelerations a = 1e3·f/m mm/s² for f in N and m in kg):

``"explicit"``  velocity Verlet (central difference, kick-drift-kick; the dampers see the half-step
                velocity; the moving resistance, stiff near standstill, is applied by a backward-Euler
                velocity update per node at the end of the step, see ``_resist``: it does not limit the
                step, and its work is exactly the kinetic energy it removes.  Near standstill (|v| ~ ε) the
                creep speeds are first-order accurate only; tensions are insensitive to that, see the
                benchmark notes).  Stable for dt <= dt_stable = (2/ω_max)(√(1+ζ²) − ζ), with
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

import numpy as np
from numba import njit

from chainid.generated.stiffness_paper import force as _force
from chainid.generated.stiffness_paper import stiffness as _stiffness
from chainid.dynamics.drives import drive_state
from chainid.dynamics.energy import elastic_energy_array

__all__ = ["explicit_core", "implicit_core"]

_FM = {"contract", "arcp", "nsz"}


# ---------------------------------------------------------------------------------------------- kernels
@njit(cache=True, fastmath=_FM, error_model="numpy")
def _springs(u, epre, cl, ch, Fk, kind):
    """F_k of every segment [N]: the generated kernel (kind 0); benchmark floors: cbrt (1), linear (2)."""
    if kind == 0:
        for j in range(Fk.shape[0]):
            Fk[j] = _force(epre[j] + u[j] - u[j + 1], cl[j], ch[j])
    elif kind == 1:  # benchmark floor: a spring that costs one cube root, cbrt(e)/c_lin (not a chain model)
        for j in range(Fk.shape[0]):
            e = epre[j] + u[j] - u[j + 1]
            Fk[j] = np.cbrt(e) / cl[j] if e > 0.0 else 0.0
    else:  # benchmark floor: a linear tension-only spring e/c_lin, the cheapest spring there is
        for j in range(Fk.shape[0]):
            e = epre[j] + u[j] - u[j + 1]
            Fk[j] = e / cl[j] if e > 0.0 else 0.0


@njit(cache=True, fastmath=_FM, error_model="numpy")
def _segments(u, v, du, epre, cl, ch, cd, T, Fk, dprev, kind):
    """Tensions T_j [N] and the trapezoidal damper work over the last step [N·mm]; peak tension.

    Two loops (the spring kernel first) so that numba vectorises both."""
    _springs(u, epre, cl, ch, Fk, kind)
    N = T.shape[0]
    dw = 0.0
    peak = 0.0
    for j in range(N):
        e = epre[j] + u[j] - u[j + 1]
        f = Fk[j]
        t = f + cd[j] * (v[j] - v[j + 1])
        t = t if t > 0.0 else 0.0
        t = t if e > 0.0 else 0.0
        d = t - f
        dw += 0.5 * (dprev[j] + d) * (du[j] - du[j + 1])
        dprev[j] = d
        T[j] = t
        peak = peak if peak > t else t
    return dw, peak


@njit(cache=True, fastmath=_FM, error_model="numpy")
def _external(t, u, v, res, veps, load_node, load_F, load_t, tens, Ft, kt, fe, with_res=True):
    """External forces on the nodes [N]: resistance (unless with_res is False), load steps, tensioner (into fe)."""
    nn = u.shape[0]
    for i in range(nn):
        vi = v[i]
        r = vi / veps
        r = r if r < 1.0 else 1.0
        r = r if r > -1.0 else -1.0
        fe[i] = -res[i] * r if with_res else 0.0
    for k in range(load_node.shape[0]):
        if t >= load_t[k]:
            fe[load_node[k]] -= load_F[k]
    if tens:
        fe[nn - 1] -= Ft + kt * u[nn - 1]


@njit(cache=True, fastmath=_FM, error_model="numpy")
def _resist(v, m, res, veps, dt, last):
    """Backward-Euler velocity update of the moving resistance f = -R·clip(v/ε, -1, 1) on nodes 1..last.

    The regularised Coulomb law is stiff near v = 0 (slope R/ε), so the explicit scheme treats it
    implicitly, node by node, in closed form: w = v*/(1 + α/ε) if that is within ±ε, else w = v* − α·sign(v*)
    (α = dt·1e3·R/m).  Returns the resistance work [N·mm], which is exactly the kinetic energy it removed,
    ½·m·(w² − v*²)·1e-3.
    """
    dW = 0.0
    for i in range(1, last + 1):
        vs = v[i]
        a = dt * 1e3 * res[i] / m[i]
        w_lin = vs / (1.0 + a / veps)
        w_sat = vs - a if vs > 0.0 else vs + a
        w = w_lin if abs(w_lin) <= veps else w_sat
        dW += 0.5e-3 * m[i] * (w * w - vs * vs)
        v[i] = w
    return dW


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
              dt, n_steps, out_every, t_out, T_out, Fd_out, u_out, v_out, en_out, kind=0):
    nn = u.shape[0]
    N = nn - 1
    last = N if tens else N - 1  # last free node
    has_ext = tens or load_node.shape[0] > 0
    has_res = np.any(res > 0.0)
    T = np.zeros(N)
    Fk = np.zeros(N)
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
    _, peak = _segments(u, v, du, epre, cl, ch, cd, T, Fk, dprev, kind)
    if has_ext:
        _external(0.0, u, v, res, veps, load_node, load_F, load_t, tens, Ft, kt, feprev, False)
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
        dD, pk = _segments(u, v, du, epre, cl, ch, cd, T, Fk, dprev, kind)
        D += dD
        peak = max(peak, pk)
        if has_ext:
            _external(t1, u, v, res, veps, load_node, load_F, load_t, tens, Ft, kt, fe, False)
            for i in range(1, last + 1):
                W += 0.5 * (feprev[i] + fe[i]) * du[i]
                feprev[i] = fe[i]
        for i in range(1, N):
            acc[i] = (T[i - 1] - T[i] + fe[i]) * inv[i]
        if tens:
            acc[N] = (T[N - 1] + fe[N]) * inv[N]
        for i in range(1, last + 1):
            v[i] += 0.5 * dt * acc[i]
        if has_res:
            W += _resist(v, m, res, veps, dt, last)
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
    _, peak = _segments(u, v, du, epre, cl, ch, cd, T, np.zeros(N), dprev, 0)
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
                cres = res[i] / veps if abs(vn[i]) < veps else 0.0  # -d(resistance)/dv
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


#: The compiled cores (public names for :mod:`.simulation` and the benchmarks).
explicit_core = _explicit
implicit_core = _implicit
