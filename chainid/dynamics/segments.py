"""Segment force law of the lumped chain in numba: spring, viscous damper and hysteretic (Jenkins) elements.

Units mm, N, s.  A segment j of elongation e_j [mm] and elongation rate ė_j [mm/s] carries

    T_j = F_k(e_j) + c_j·ė_j + Σ_q z_jq      if e_j > 0 and that sum is > 0, else 0,

with F_k the generated chain kernel (Eq. 15 inverted), c_j the viscous damper [N·s/mm] and z_jq the forces
[N] of Jenkins elements (a spring k_jq [N/mm] in series with a Coulomb slider of force f_jq [N]) in parallel
with the spring.  One Jenkins element with a stiff spring is Coulomb friction with stick (the stick phase
is elastic with k_stick); several elements of graded slip forces are an Iwan (parallel Masing) model of
rate-independent hysteresis.  Dahl elements (force z → ±F_h over a travel x_h after each reversal,
:func:`chainid.model.operators.dahl_step`, exact for a linear path) are the smooth alternative; their
state is z, their stored energy z²/(2F_h/x_h).  The Jenkins elements' state is the slider position y_jq [mm] on the segment's elongation
axis, z = k·(e − y); it is advanced by the ONE implementation of the operator,
:func:`chainid.model.operators.jenkins_step` (slip force F_c = f, stick travel x_s = f/k; exact
dissipation F_c·|Δy| for a monotone path over the step).  Initial state: unstressed (y = e at t = 0).

When the segment is slack (e <= 0) or its tension would be negative (the dampers cannot push), the segment
carries nothing and its Jenkins elements are released (y = e, z = 0; their stored energy k·(e − y)²/2 at
the start of the step counts as dissipated: the contacts open).  Energy bookkeeping: stored energy =
U(e) of the kernel + Σ k·(e − y)²/2 (:func:`stored_energy`); dissipation = trapezoidal work of the viscous
part over the step + slip work + released energy (:func:`tensions`).
"""
from __future__ import annotations

import numpy as np
from numba import njit

from chainid.generated.stiffness_paper import force as _force
from chainid.generated.stiffness_paper import stiffness as _stiffness
from chainid.dynamics.energy import elastic_energy_array
from chainid.model.operators import dahl_step, jenkins_step

__all__ = ["tensions", "stored_energy"]

_FM = {"contract", "arcp", "nsz"}


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
def tensions(u, v, us, epre, cl, ch, cd, hf, hx, hd, ys, dvs, y, dv, T, Fk, ks, cs, kind, tangent):
    """Segment tensions at the end of a step from its start state.

    Inputs: u, v node displacements [mm] and speeds [mm/s] at the end; us, ys, dvs displacements, element
    states and viscous forces [N] at the start.  Elements (N, n_el): ``hd`` 0 — a Jenkins element of slip
    force hf [N] and stick travel hx [mm], state its slider position [mm]; 1 — a Dahl element of force
    F_h = hf [N] and travel x_h = hx [mm], state its force z [N].  Outputs: y, dv, T (and, with ``tangent``, the tangent
    stiffness ks [N/mm] and damping cs [N·s/mm] of each segment for Newton's method).

    Returns
    -------
    (dD, peak, low)
        Dissipation over the step [N·mm] (trapezoidal viscous work + slip + released energy), the largest and
        the smallest tension [N] (0: a segment carries nothing, slack or clipped).
    """
    _springs(u, epre, cl, ch, Fk, kind)
    n_el = hf.shape[1]
    dD = 0.0
    peak = 0.0
    low = np.inf
    if n_el == 0 and not tangent:  # the explicit scheme's viscous-only path: one branch-free loop (vectorised)
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
        f = Fk[j]
        zsum = 0.0
        slip = 0.0
        kz = 0.0
        for q in range(n_el):
            if hd[j, q] == 0:
                yq, zq, dq = jenkins_step(ys[j, q], e, hf[j, q], hx[j, q])
                kz += hf[j, q] / hx[j, q] if yq == ys[j, q] else 0.0
            else:
                zq, dq = dahl_step(ys[j, q], e - de, e, hf[j, q], hx[j, q])
                yq = zq
                sg = 1.0 if de >= 0.0 else -1.0
                kz += hf[j, q] / hx[j, q] * (1.0 - sg * zq / hf[j, q])
            y[j, q] = yq
            zsum += zq
            slip += dq
        dvis = cd[j] * (v[j] - v[j + 1])
        t = f + dvis + zsum
        if e > 0.0 and t > 0.0:
            T[j] = t
            dv[j] = dvis
            dD += slip
            if tangent:
                ks[j] = _stiffness(e, cl[j], ch[j]) + kz
                cs[j] = cd[j]
        else:
            T[j] = 0.0
            dv[j] = -f
            es = e - de
            for q in range(n_el):  # released: the energy stored at the start is dissipated
                w = es - ys[j, q] if hd[j, q] == 0 else ys[j, q] * hx[j, q] / hf[j, q]
                dD += 0.5 * hf[j, q] / hx[j, q] * w * w
                y[j, q] = e if hd[j, q] == 0 else 0.0
            if tangent:
                ks[j] = 0.0
                cs[j] = 0.0
        dD += 0.5 * (dvs[j] + dv[j]) * de
        peak = peak if peak > T[j] else T[j]
        low = low if low < T[j] else T[j]
    return dD, peak, low


@njit(cache=True, fastmath=_FM, error_model="numpy")
def stored_energy(u, epre, cl, ch, hf, hx, hd, y):
    """Stored energy [N·mm]: Σ U(e_j) of the kernel + Σ k·(e_j − y_jq)²/2 of the Jenkins springs (k = f/x_s)
    + Σ z²/(2k₀) of the Dahl elements (k₀ = F_h/x_h)."""
    N = cl.shape[0]
    e = np.empty(N)
    for j in range(N):
        e[j] = epre[j] + u[j] - u[j + 1]
    s = elastic_energy_array(e, cl, ch)
    for j in range(N):
        for q in range(hf.shape[1]):
            w = e[j] - y[j, q] if hd[j, q] == 0 else y[j, q] * hx[j, q] / hf[j, q]
            s += 0.5 * hf[j, q] / hx[j, q] * w * w
    return s
