"""Time integration of the lumped chain in numba: one step loop, two schemes (units mm, N, s, kg).

The loop (:func:`run`) advances the chain over steps of ``dt`` and stores every ``out_every``-th state; each
step is made of one or more sub-steps, taken by one of two schemes (accelerations a = 1e3·f/m mm/s² for f in
N and m in kg):

``"explicit"``  velocity Verlet (central difference, kick-drift-kick; the dampers see the half-step
                velocity; the moving resistance, stiff near standstill, is applied by a backward-Euler
                velocity update per node at the end of the (sub-)step, see ``_resist``: it does not limit the
                step, and its work is exactly the kinetic energy it removes).  Stable for a linear chain for
                dt <= dt_stable (see :func:`chainid.dynamics.simulation.stable_step`).
``"implicit"``  Newmark's average acceleration (trapezoidal rule: unconditionally stable for a linear chain,
                no numerical damping), solved by Newton's method on the tangent (chain kernel k_e + Jenkins
                springs, dampers) with a tridiagonal (Thomas) solve.  Convergence: the largest force residual
                below tol_abs + tol_rel·F_ref [N], F_ref fixed for the sub-step (the larger of the largest
                tension at its start and max(1, tensioner force) + Σ|loads| + Σ resistances; never the
                iterate's own forces), within ``max_it`` iterations; otherwise the sub-step is rejected and
                halved.  At the shortest sub-step, when that is no longer than ``dt_explicit`` (the explicit
                stable step: Newton cannot converge where a damper's force jumps as its segment goes taut),
                one Verlet sub-step is taken instead (``_fallback_step``); the resistance, which the implicit
                state's forces and accelerations include, is taken out of them for it and put back after.

Snap loads (slack ↔ taut).  A segment that starts or stops carrying load switches its stiffness between 0
and k_e within a step; Verlet is then only first-order accurate at that step and, near dt_stable, the
switching of two stable linear maps can pump energy into the chain (a slack polygon drive at 0.9·dt_stable
gained 0.9x its work input).  The remedy is in :func:`chainid.dynamics.simulation.simulate`: an adaptive
step with an error estimate, the estimate being the run's energy-balance residual (see there for why, with
the measurements that ruled out sub-stepping at the transitions).  Within a run the step is constant, so
Verlet keeps its time-reversible (symplectic) character.  The loop can still split a step into halves
(down to dt/2^levels): the implicit scheme does so when Newton's method fails.

Energy: work in (drive: trapezoidal T_1 work + the exact change of the drive node's kinetic energy; external
forces trapezoidal; resistance exact in a Verlet sub-step, trapezoidal in a Newmark one), dissipation
(:func:`.segments.tensions`), kinetic and stored energy, accumulated per sub-step (:mod:`.energy`).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from chainid.dynamics.drives import drive_state
from chainid.dynamics.segments import segment_energy, segment_tensions

__all__ = ["run", "explicit_core", "implicit_core"]

_FM = {"contract", "arcp", "nsz"}


@njit(cache=True, fastmath=_FM, error_model="numpy")
def _resistance(R, v, veps):
    """The moving resistance of a node [N]: −R·clip(v/ε, −1, 1) (Coulomb, regularised below |v| = ε)."""
    r = v / veps
    r = r if r < 1.0 else 1.0
    r = r if r > -1.0 else -1.0
    return -R * r


@njit(cache=True, fastmath=_FM, error_model="numpy")
def _accelerations(T, fe, inv, acc, last):
    """The free nodes' accelerations [mm/s²] into ``acc``: (T_{i−1} − T_i + f_e,i)·1e3/m_i for nodes 1..last, no
    segment beyond the last node."""
    N = T.shape[0]
    for i in range(1, last + 1):
        acc[i] = (T[i - 1] - (T[i] if i < N else 0.0) + fe[i]) * inv[i]


@njit(cache=True, fastmath=_FM, error_model="numpy")
def _external(t, u, v, res, veps, load_node, load_F, load_t, tens, Ft, kt, fe, with_res):
    """External forces on the nodes [N]: resistance (unless with_res is False), load steps, tensioner (into fe)."""
    nn = u.shape[0]
    for i in range(nn):
        fe[i] = _resistance(res[i], v[i], veps) if with_res else 0.0
    for k in range(load_node.shape[0]):
        if t >= load_t[k]:
            fe[load_node[k]] -= load_F[k]
    if tens:
        fe[nn - 1] -= Ft + kt * u[nn - 1]


@njit(cache=True, fastmath=_FM, error_model="numpy")
def _without_resistance(v, acc, fe, res, veps, inv, last):
    """Take the moving resistance −R·clip(v/ε, −1, 1) out of the external forces [N] and the accelerations
    [mm/s²] of nodes 1..last.

    The implicit state's forces and accelerations include it; the Verlet step applies it itself (``_resist``, with
    its exact work), so a fallback Verlet step from an implicit state must start from the state without it, or its
    first half-kick applies the resistance a second time (every step a fallback: 1.5 × the resistance's impulse)
    and its work is counted half again."""
    for i in range(1, last + 1):
        f = _resistance(res[i], v[i], veps)
        fe[i] -= f
        acc[i] -= f * inv[i]


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
def _drive_work(us, vs, Ts, u, v, T, m0):
    """Work of the drive on node 0 over a step [N·mm]: trapezoidal T_1·Δu_0 + exact Δ(½ m_0 v_0²)."""
    return 0.5 * (Ts[0] + T[0]) * (u[0] - us[0]) + 0.5e-3 * m0 * (v[0] * v[0] - vs[0] * vs[0])


@njit(cache=True, fastmath=_FM, error_model="numpy")
def _explicit_step(h, t1, c, S, X, inv, has_res, kind):
    """One Verlet step of length h [s] from state S into X; returns (dW, dD, peak, lowest tension)."""
    (m, cl, ch, cd, hf, hx, hd, hq, sp, tabs, ext, epre, res, veps, load_node, load_F, load_t, tens, Ft, kt, code, p,
     last) = c
    us, vs, accs, zs, dvs, fes, Ts = S
    u, v, acc, z, dv, fe, T, Fk, ks, cs = X
    for i in range(1, last + 1):
        vh = vs[i] + 0.5 * h * accs[i]
        v[i] = vh
        u[i] = us[i] + h * vh
    u[0], v[0], _ = drive_state(t1, code, p)
    dD, pk, low = segment_tensions(u, v, us, epre, cl, ch, cd, hf, hx, hd, hq, sp, tabs, ext, zs, dvs, z, dv, T, Fk,
                                   ks, cs, kind, np.bool_(False))
    dW = _drive_work(us, vs, Ts, u, v, T, m[0])
    if tens or load_node.shape[0] > 0:
        _external(t1, u, v, res, veps, load_node, load_F, load_t, tens, Ft, kt, fe, np.bool_(False))
        for i in range(1, last + 1):
            dW += 0.5 * (fes[i] + fe[i]) * (u[i] - us[i])
    _accelerations(T, fe, inv, acc, last)
    for i in range(1, last + 1):
        v[i] += 0.5 * h * acc[i]
    if has_res:
        dW += _resist(v, m, res, veps, h, last)
    return dW, dD, pk, low


@njit(cache=True, fastmath=_FM, error_model="numpy")
def _implicit_step(h, t1, c, S, X, lin, tol, max_it):
    """One Newmark (sub-)step by Newton's method; returns (converged, dW, dD, peak, lowest tension, iterations)."""
    (m, cl, ch, cd, hf, hx, hd, hq, sp, tabs, ext, epre, res, veps, load_node, load_F, load_t, tens, Ft, kt, code, p,
     nf) = c
    us, vs, accs, zs, dvs, fes, Ts = S
    u, v, acc, z, dv, fe, T, Fk, ks, cs = X
    lo, di, up, r, dx = lin
    N = T.shape[0]
    u[0], v[0], _ = drive_state(t1, code, p)
    u[N] = us[N]
    v[N] = vs[N]
    for i in range(1, nf + 1):
        acc[i] = accs[i]
    dD, pk, low = 0.0, 0.0, 0.0
    for it in range(max_it):
        for i in range(1, nf + 1):
            u[i] = us[i] + h * vs[i] + 0.25 * h * h * (accs[i] + acc[i])
            v[i] = vs[i] + 0.5 * h * (accs[i] + acc[i])
        dD, pk, low = segment_tensions(u, v, us, epre, cl, ch, cd, hf, hx, hd, hq, sp, tabs, ext, zs, dvs, z, dv, T,
                                       Fk, ks, cs, np.int64(0), np.bool_(True))
        _external(t1, u, v, res, veps, load_node, load_F, load_t, tens, Ft, kt, fe, np.bool_(True))
        rmax = 0.0
        for i in range(1, nf + 1):
            nxt = T[i] if i < N else 0.0
            kn = ks[i] if i < N else (kt if tens else 0.0)
            cn = cs[i] if i < N else 0.0
            cres = res[i] / veps if abs(v[i]) < veps else 0.0  # -d(resistance)/dv
            k = i - 1
            r[k] = (T[i - 1] - nxt + fe[i]) - 1e-3 * m[i] * acc[i]
            di[k] = 1e-3 * m[i] + 0.5 * h * (cs[i - 1] + cn + cres) + 0.25 * h * h * (ks[i - 1] + kn)
            lo[k] = -(0.5 * h * cs[i - 1] + 0.25 * h * h * ks[i - 1])
            up[k] = -(0.5 * h * cn + 0.25 * h * h * (ks[i] if i < N else 0.0))
            rmax = max(rmax, abs(r[k]))
        if not math.isfinite(rmax):
            return False, 0.0, 0.0, 0.0, 0.0, it + 1
        if rmax <= tol or nf == 0:
            dW = _drive_work(us, vs, Ts, u, v, T, m[0])
            for i in range(1, nf + 1):
                dW += 0.5 * (fes[i] + fe[i]) * (u[i] - us[i])
            return True, dW, dD, pk, low, it + 1
        _thomas(lo[:nf], di[:nf], up[:nf], r[:nf], dx[:nf])
        for i in range(1, nf + 1):
            acc[i] += dx[i - 1]
    return False, 0.0, 0.0, 0.0, 0.0, max_it


@njit(cache=True)
def _record(k, t, S, m, epre, cl, ch, hf, hx, hd, sp, ext, code, p, W, D, t_out, T_out, Fd_out, u_out, v_out,
            en_out):
    us, vs, accs, zs, dvs, fes, Ts = S
    t_out[k] = t
    T_out[k, :] = Ts
    Fd_out[k] = 1e-3 * m[0] * drive_state(t, code, p)[2] + Ts[0]
    u_out[k, :] = us
    v_out[k, :] = vs
    ek = 0.0
    for i in range(us.shape[0]):
        ek += 0.5e-3 * m[i] * vs[i] * vs[i]
    en_out[k, 0] = W
    en_out[k, 1] = ek
    en_out[k, 2] = segment_energy(us, epre, cl, ch, hf, hx, hd, sp, ext, zs)
    en_out[k, 3] = D


@njit(cache=True, fastmath=_FM, error_model="numpy")
def _initial_state(u, v, c, kind, implicit):
    """The state at t = 0 from the node displacements ``u`` [mm] and speeds ``v`` [mm/s]: the drive node at its
    law, the hysteretic elements unstressed, the tensions, external forces and accelerations of the free nodes
    (with the resistance for the implicit scheme, whose state includes it); returns (S, X, the Thomas solve's
    work arrays, 1e3/m per node, the largest tension [N])."""
    (m, cl, ch, cd, hf, hx, hd, hq, sp, tabs, ext, epre, res, veps, load_node, load_F, load_t, tens, Ft, kt, code, p,
     last) = c
    nn = u.shape[0]
    N = nn - 1
    S = (u.copy(), v.copy(), np.zeros(nn), np.zeros(hf.shape), np.zeros(N), np.zeros(nn), np.zeros(N))
    X = (u.copy(), v.copy(), np.zeros(nn), np.zeros(hf.shape), np.zeros(N), np.zeros(nn), np.zeros(N),
         np.zeros(N), np.zeros(N), np.zeros(N))
    nb = max(last, 1)
    lin = (np.zeros(nb), np.zeros(nb), np.zeros(nb), np.zeros(nb), np.zeros(nb))
    inv = np.zeros(nn)
    for i in range(1, last + 1):
        inv[i] = 1e3 / m[i]
    us, vs, accs, zs, dvs, fes, Ts = S
    us[0], vs[0], _ = drive_state(0.0, code, p)
    X[0][0] = us[0]
    X[1][0] = vs[0]
    for j in range(N):  # elements unstressed at t = 0 (sliders and play output at e, Dahl and Bouc–Wen at 0)
        for q in range(hf.shape[1]):
            zs[j, q] = epre[j] + us[j] - us[j + 1] if (hd[j, q] == 0 or hd[j, q] == 2 or hd[j, q] == 4) else 0.0
    _, peak, _ = segment_tensions(us, vs, us, epre, cl, ch, cd, hf, hx, hd, hq, sp, tabs, ext, zs, dvs, X[3], dvs, Ts,
                                  X[7], X[8], X[9], kind, np.bool_(False))
    _external(0.0, us, vs, res, veps, load_node, load_F, load_t, tens, Ft, kt, fes, implicit)
    if not (tens or load_node.shape[0] > 0 or implicit):
        fes[:] = 0.0
    _accelerations(Ts, fes, inv, accs, last)
    return S, X, lin, inv, peak


@njit(cache=True, fastmath=_FM, error_model="numpy")
def _fallback_step(h, t1, c, S, X, inv, has_res):
    """One Verlet sub-step of length h [s] in place of an implicit one whose Newton iteration failed; returns
    (dW, dD, peak, lowest tension) as :func:`_explicit_step`.  The implicit state's accelerations include the moving
    resistance, which the Verlet step applies itself: it is taken out before the step, and put into the new
    state's forces and accelerations after it, for the implicit step that follows.  Without a tensioner or a load
    step the Verlet step leaves the new external forces as they are, so they are cleared first (the failed Newton
    attempt left its own there)."""
    (m, cl, ch, cd, hf, hx, hd, hq, sp, tabs, ext, epre, res, veps, load_node, load_F, load_t, tens, Ft, kt, code, p,
     last) = c
    if has_res:
        _without_resistance(S[1], S[2], S[5], res, veps, inv, last)
    if not (tens or load_node.shape[0] > 0):
        X[5][:] = 0.0
    out = _explicit_step(h, t1, c, S, X, inv, has_res, np.int64(0))
    if has_res:
        _external(t1, X[0], X[1], res, veps, load_node, load_F, load_t, tens, Ft, kt, X[5], np.bool_(True))
        _accelerations(X[6], X[5], inv, X[2], last)
    return out


@njit(cache=True, fastmath=_FM, error_model="numpy")
def _try_step(implicit, h, t1, c, S, X, lin, inv, has_res, kind, tol, max_it):
    """One sub-step of length h [s] by the run's scheme; returns (converged, dW, dD, peak, lowest tension,
    iterations): Newton's for the implicit scheme (force tolerance ``tol`` [N]), 1 for a Verlet step."""
    if implicit:
        return _implicit_step(h, t1, c, S, X, lin, tol, max_it)
    dW, dD, pk, low = _explicit_step(h, t1, c, S, X, inv, has_res, kind)
    return True, dW, dD, pk, low, 1


@njit(cache=True)
def _store_stats(stats, n_acc, n_rej, it_max, hu_min, n_fb, n_slack, work, n_done):
    """The run's counts into ``stats`` (see :func:`run`; the last two only when it has room for 8)."""
    stats[0] = n_acc
    stats[1] = n_rej
    stats[2] = it_max
    stats[3] = hu_min
    stats[4] = n_fb
    stats[5] = n_slack
    if stats.shape[0] > 7:
        stats[6] = work
        stats[7] = n_done


@njit(cache=True, fastmath=_FM, error_model="numpy")
def run(implicit, u, v, m, cl, ch, cd, hf, hx, hd, hq, sp, tabs, ext, epre, res, veps, load_node, load_F, load_t, tens,
        Ft, kt, code, p, dt, n_steps, out_every, levels, tol_abs, tol_rel, max_it, dt_explicit, t_out, T_out, Fd_out,
        u_out, v_out, en_out, stats, kind=0, budget=0.0):
    """Integrate ``n_steps`` steps of ``dt`` [s] (see the module docstring); returns (status, peak [N]).

    status 0: done; 1: non-finite state (stopped at the last good output); 2: Newton did not converge at the
    shortest sub-step dt/2^levels, which is above ``dt_explicit`` (the explicit stable step; below it, such a
    sub-step is taken by the explicit scheme: Newton cannot converge where a segment's damper force jumps
    as it goes taut); 3: the work done exceeded ``budget`` [node-steps: free nodes × (Newton iterations of
    every implicit sub-step tried, or 1 per explicit sub-step)], when ``budget`` > 0.  ``stats`` (>= 8 entries)
    receives [accepted sub-steps, rejected sub-steps, largest Newton iteration count, shortest sub-step / dt,
    explicit fallback sub-steps, sub-steps ending with a segment that carries nothing (slack or clipped),
    work done [node-steps], whole steps done].
    """
    N = u.shape[0] - 1
    last = N if tens else N - 1  # last free node
    c = (m, cl, ch, cd, hf, hx, hd, hq, sp, tabs, ext, epre, res, veps, load_node, load_F, load_t, tens, Ft, kt, code,
         p, last)
    S, X, lin, inv, peak = _initial_state(u, v, c, kind, implicit)
    has_res = np.any(res > 0.0)
    Fbase = max(1.0, Ft) + np.sum(np.abs(load_F)) + np.sum(res)  # the step's reference force [N] (with the tensions)
    W = 0.0
    D = 0.0
    _record(np.int64(0), 0.0, S, m, epre, cl, ch, hf, hx, hd, sp, ext, code, p, W, D, t_out, T_out, Fd_out, u_out,
            v_out, en_out)
    status = 0
    unit = 1 << levels
    hu = unit
    n_acc, n_rej, it_max, hu_min, n_fb, n_slack = 0, 0, 0, unit, 0, 0
    work = 0.0
    n_done = 0
    for n in range(n_steps):
        done = 0
        while done < unit:
            hu = min(hu, unit - done)
            h = hu * dt / unit
            t1 = (n + (done + hu) / unit) * dt
            tol = tol_abs + tol_rel * max(Fbase, np.max(S[6])) if implicit else 0.0  # F_ref: never the iterate's
            ok, dW, dD, pk, low, its = _try_step(implicit, h, t1, c, S, X, lin, inv, has_res, kind, tol, max_it)
            it_max = max(it_max, its) if implicit else 0
            work += its * max(last, 1)
            if budget > 0.0 and work > budget:
                status = 3
                break
            if not ok and hu > 1:
                hu //= 2
                n_rej += 1
                continue
            if not ok and h <= dt_explicit:  # Newton stuck at a non-smooth point: one Verlet sub-step instead
                dW, dD, pk, low = _fallback_step(h, t1, c, S, X, inv, has_res)
                ok = True
                n_fb += 1
            if not ok:
                status = 2
                break
            S, X = (X[0], X[1], X[2], X[3], X[4], X[5], X[6]), (S[0], S[1], S[2], S[3], S[4], S[5], S[6],
                                                                 X[7], X[8], X[9])
            W += dW
            D += dD
            peak = max(peak, pk)
            if low <= 0.0:
                n_slack += 1
            done += hu
            n_acc += 1
            hu_min = min(hu_min, hu)
            if hu < unit:
                hu *= 2
        if status:
            break
        n_done = n + 1
        if (n + 1) % out_every == 0:
            if not math.isfinite(peak + W + D + S[0][last] + S[1][last]):
                status = 1
                break
            _record((n + 1) // out_every, (n + 1) * dt, S, m, epre, cl, ch, hf, hx, hd, sp, ext, code, p, W, D,
                    t_out, T_out, Fd_out, u_out, v_out, en_out)
    _store_stats(stats, n_acc, n_rej, it_max, hu_min / unit, n_fb, n_slack, work, n_done)
    return status, peak


def explicit_core(*args, kind: int = 0, budget: float = 0.0):
    """The explicit scheme through :func:`run` (arguments as :func:`run` without ``implicit``)."""
    return run(False, *args, kind=kind, budget=budget)


def implicit_core(*args, budget: float = 0.0):
    """The implicit scheme through :func:`run` (arguments as :func:`run` without ``implicit``)."""
    return run(True, *args, kind=0, budget=budget)
