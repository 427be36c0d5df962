"""Segment force law of the lumped chain in numba: spring, viscous damper and memory elements.

Units mm, N, s.  A segment j of elongation e_j [mm] and elongation rate ė_j [mm/s] carries

    T_j = F_s(a_j) + F_d(e_j) + c_j·ė_j + Σ_q z_jq      if the segment is taut and that sum is > 0, else 0,

with F_s the segment's spring (:mod:`.springs`: the generated chain kernel, or the free-exponent contact kernel)
at the argument a_j = (play output or e_j) − s_j (s_j the slack), F_d a dead band with hardening stops, c_j the
viscous damper [N·s/mm] and z_jq the forces [N] of the memory elements in parallel with the spring.  The segment
is taut when a_j > 0 or F_d > 0 (a chain cannot push).  Elements (``hd`` kind; force ``hf``, travel or stiffness
``hx``, extra parameters ``hq``; each advanced by the ONE implementation of its operator in
:mod:`chainid.model.operators`):

====  ================  ====================================  =========================  ==================
kind  element           hf, hx, hq                            state                      stored energy
====  ================  ====================================  =========================  ==================
0     Jenkins           slip force f, stick travel x_s         slider position y [mm]     f/x_s·(e − y)²/2
1     Dahl              F_h, x_h                               force z [N]                z²·x_h/(2F_h)
2     Stribeck          F_c, stick stiffness k, (dF_s, v_s,    slider position y [mm]     k·(e − y)²/2
                        dF)
3     Bouc–Wen          F_y, x_y, (table index, n, r)          z ∈ [−1, 1]                F_y·x_y·z²/2
4     play (backlash)   0, half-width h                        play output [mm]           (the spring's)
====  ================  ====================================  =========================  ==================

A play element comes first in its segment's row: the spring acts on its output.  One Jenkins element with a stiff
spring is Coulomb friction with stick; several of graded slip forces are an Iwan model.  Stribeck friction is
rate dependent: its slip force follows the segment's ė at the end of the step, and its stick spring regularises
the sign of ė near rest (:func:`chainid.model.operators.stribeck_step`).  Initial state: unstressed (sliders and
play output at e, Dahl and Bouc–Wen at 0).

When the segment is slack or its tension would be negative (the dampers cannot push), it carries nothing and its
elements are released (sliders at e, z = 0; the play keeps its output; the energy the elements stored at the
start of the step counts as dissipated: the contacts open).  Energy bookkeeping: stored energy = U(a) of the
spring + the dead band's potential + the elements' stored energies (:func:`segment_energy`); dissipation =
trapezoidal work of the viscous part over the step + the elements' losses + released energy + the play's loss
F_s(a)·(Δe − Δoutput) (the spring's force moves with e while the play holds its argument: the library's play
operator is not passive, this term is < 0 where it returns energy) (:func:`segment_tensions`).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from chainid.dynamics.energy import elastic_energy_array
from chainid.dynamics.springs import deadband, deadband_energy, spring_energy, spring_force, spring_stiffness
from chainid.generated.stiffness_paper import force as _force
from chainid.generated.stiffness_paper import stiffness as _stiffness
from chainid.model.operators import bouc_wen_step, dahl_step, jenkins_step, play_step, stribeck_step

__all__ = ["tensions", "segment_tensions", "segment_energy", "PLAY", "ELEMENT_KINDS"]

_FM = {"contract", "arcp", "nsz"}
#: element kinds (``hd``)
ELEMENT_KINDS = ("jenkins", "dahl", "stribeck", "bouc_wen", "play")
PLAY = 4


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
def _element(kd, s, e, de, ev, f, x, q, tabs):
    """One element over a step from state s: (state, force [N], loss [N·mm], dT/de [N/mm], dT/dė [N·s/mm])."""
    if kd == 0:
        yq, zq, dq = jenkins_step(s, e, f, x)
        return yq, zq, dq, (f / x if yq == s else 0.0), 0.0
    if kd == 1:
        zq, dq = dahl_step(s, e - de, e, f, x)
        sg = 1.0 if de >= 0.0 else -1.0
        return zq, zq, dq, f / x * (1.0 - sg * zq / f), 0.0
    if kd == 2:
        yq, zq, dq = stribeck_step(s, e, ev, x, f, q[0], q[1], q[2])
        if yq == s:
            return yq, zq, dq, x, 0.0
        w = math.exp(-(ev / q[1]) * (ev / q[1]))
        sl = 1.0 if yq > s else -1.0  # sliding: z = ±(band edge at ė), its slope over ė
        return yq, zq, dq, 0.0, sl * q[0] * w * (-2.0 * ev / (q[1] * q[1]))
    if kd == 3:
        i = int(q[0])
        zq, dq = bouc_wen_step(s, e - de, e, f, x, tabs[i, 0], tabs[i, 1])
        sg = 1.0 if de >= 0.0 else -1.0
        szz = 0.0 if zq == 0.0 else (1.0 if sg * zq > 0.0 else -1.0)
        h = 1.0 - (q[2] * szz + 1.0 - q[2]) * abs(zq) ** q[1]
        return zq, f * zq, dq, f / x * h, 0.0
    return play_step(s, e, x), 0.0, 0.0, 0.0, 0.0


@njit(cache=True, fastmath=_FM, error_model="numpy")
def _element_energy(kd, e, s, f, x):
    """Energy [N·mm] an element of state s stores at elongation e (the play: none of its own)."""
    if kd == 0:
        w = e - s
        return 0.5 * f / x * w * w
    if kd == 1:
        return 0.5 * s * s * x / f
    if kd == 2:
        w = e - s
        return 0.5 * x * w * w
    if kd == 3:
        return 0.5 * f * x * s * s
    return 0.0


@njit(cache=True, fastmath=_FM, error_model="numpy")
def _elastic(j, e, de, ys, y, cl, ch, hx, hd, sp, tangent):
    """(spring force at the argument a [N], a [mm], dead band force [N], spring tangent if its argument moved
    [N/mm] (with ``tangent``), dead band tangent [N/mm], play loss [N·mm], first element column after the play) of
    segment j."""
    beta, s = sp[j, 0], sp[j, 1]
    q0, a, loss = 0, e - s, 0.0
    fd, kdb = deadband(e - sp[j, 5], sp[j, 2], sp[j, 3], sp[j, 4])
    moved = True
    rest = 0.0
    if hd.shape[1] > 0 and hd[j, 0] == 4:
        yp = play_step(ys[j, 0], e, hx[j, 0])
        y[j, 0] = yp
        q0, a, moved = 1, yp - s, yp != ys[j, 0]
        rest = de - (yp - ys[j, 0])  # the travel over which the play held the spring's argument
    f = spring_force(a, cl[j], ch[j], beta)
    if not moved:
        loss = f * rest
    elif q0 == 1 and abs(rest) > 1e-12 * (abs(e) + hx[j, 0]):  # the step that engages (not round-off of it);
        # q0 == 1 first: without a play there is no column 0 to read
        loss = spring_force(ys[j, 0] - s, cl[j], ch[j], beta) * rest
    kf = spring_stiffness(a, cl[j], ch[j], beta) if (moved and tangent) else 0.0
    return f, a, fd, kf, kdb, loss, q0


@njit(cache=True, fastmath=_FM, error_model="numpy")
def segment_tensions(u, v, us, epre, cl, ch, cd, hf, hx, hd, hq, sp, tabs, ext, ys, dvs, y, dv, T, Fk, ks, cs,
                     kind, tangent):
    """Segment tensions at the end of a step from its start state.

    Inputs: u, v node displacements [mm] and speeds [mm/s] at the end; us, ys, dvs displacements, element states
    and viscous forces [N] at the start.  Elements (N, n_el) ``hd``, ``hf``, ``hx`` and (N, n_el, 3) ``hq`` (see the
    module docstring), Bouc–Wen travel tables ``tabs`` (n_tables, 2, points); the spring table ``sp`` (N, 6) of
    :mod:`.springs`, used when ``ext`` (else the plain generated kernel, or a benchmark floor ``kind``).
    Outputs: y, dv, T, Fk (the elastic force [N]) and, with ``tangent``, the tangent stiffness ks [N/mm] and
    damping cs [N·s/mm] of each segment for Newton's method.

    Returns
    -------
    (dD, peak, low)
        Dissipation over the step [N·mm], the largest and the smallest tension [N] (0: a segment carries nothing).
    """
    n_el = hf.shape[1]
    dD = 0.0
    peak = 0.0
    low = np.inf
    if not ext:
        _springs(u, epre, cl, ch, Fk, kind)
    if n_el == 0 and not tangent and not ext:  # the explicit scheme's viscous-only path (vectorised)
        for j in range(T.shape[0]):
            e = epre[j] + u[j] - u[j + 1]
            f = Fk[j]
            t = f + cd[j] * (v[j] - v[j + 1])
            t = t if t > 0.0 else 0.0
            t = t if e > 0.0 else 0.0
            d = t - f
            dD += 0.5 * (dvs[j] + d) * ((u[j] - us[j]) - (u[j + 1] - us[j + 1]))
            dv[j] = d
            T[j] = t
            peak = peak if peak > t else t
            low = low if low < t else t
        return dD, peak, low
    for j in range(T.shape[0]):
        e = epre[j] + u[j] - u[j + 1]
        de = (u[j] - us[j]) - (u[j + 1] - us[j + 1])
        ev = v[j] - v[j + 1]
        if ext:
            f, a, fd, kf, kdb, loss, q0 = _elastic(j, e, de, ys, y, cl, ch, hx, hd, sp, tangent)
        else:
            f, a, fd, kf, kdb, loss, q0 = Fk[j], e, 0.0, 0.0, 0.0, 0.0, 0
        zsum, slip, kz, cz = 0.0, 0.0, 0.0, 0.0
        for q in range(q0, n_el):
            st, zq, dq, kq, cq = _element(hd[j, q], ys[j, q], e, de, ev, hf[j, q], hx[j, q], hq[j, q], tabs)
            y[j, q] = st
            zsum += zq
            slip += dq
            kz += kq
            cz += cq
        Fk[j] = f + fd
        dvis = cd[j] * ev
        t = f + fd + dvis + zsum
        dD += loss
        if (a > 0.0 or fd > 0.0) and t > 0.0:
            T[j] = t
            dv[j] = dvis
            dD += slip
            if tangent:
                ks[j] = (kf if ext else _stiffness(e, cl[j], ch[j])) + kdb + kz
                cs[j] = cd[j] + cz
        else:
            T[j] = 0.0
            dv[j] = -(f + fd)
            es = e - de
            for q in range(q0, n_el):  # released: the energy stored at the start is dissipated
                dD += _element_energy(hd[j, q], es, ys[j, q], hf[j, q], hx[j, q])
                y[j, q] = e if (hd[j, q] == 0 or hd[j, q] == 2) else 0.0
            if tangent:
                ks[j] = 0.0
                cs[j] = 0.0
        dD += 0.5 * (dvs[j] + dv[j]) * de
        peak = peak if peak > T[j] else T[j]
        low = low if low < T[j] else T[j]
    return dD, peak, low


@njit(cache=True, fastmath=_FM, error_model="numpy")
def tensions(u, v, us, epre, cl, ch, cd, hf, hx, hd, ys, dvs, y, dv, T, Fk, ks, cs, kind, tangent):
    """:func:`segment_tensions` for the plain generated kernel and Jenkins (kind 0) / Dahl (kind 1) elements only
    (hf: slip force or F_h [N], hx: stick travel or x_h [mm])."""
    N, n_el = hf.shape
    return segment_tensions(u, v, us, epre, cl, ch, cd, hf, hx, hd, np.zeros((N, n_el, 3)), np.zeros((N, 6)),
                            np.zeros((0, 2, 2)), np.bool_(False), ys, dvs, y, dv, T, Fk, ks, cs, kind, tangent)


@njit(cache=True, fastmath=_FM, error_model="numpy")
def segment_energy(u, epre, cl, ch, hf, hx, hd, sp, ext, y):
    """Stored energy [N·mm]: Σ U(a_j) of the springs + the dead bands' potentials + the elements' stored energies
    (see the module docstring)."""
    N = cl.shape[0]
    e = np.empty(N)
    for j in range(N):
        e[j] = epre[j] + u[j] - u[j + 1]
    if not ext:
        s = elastic_energy_array(e, cl, ch)
    else:
        s = 0.0
        for j in range(N):
            a = (y[j, 0] if hf.shape[1] > 0 and hd[j, 0] == 4 else e[j]) - sp[j, 1]
            s += spring_energy(a, cl[j], ch[j], sp[j, 0]) + deadband_energy(e[j] - sp[j, 5], sp[j, 2], sp[j, 3],
                                                                            sp[j, 4])
    for j in range(N):
        for q in range(hf.shape[1]):
            s += _element_energy(hd[j, q], e[j], y[j, q], hf[j, q], hx[j, q])
    return s
