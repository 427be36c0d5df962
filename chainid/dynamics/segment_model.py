"""A diagnosed model file (issue 17) as the segments of a chain line: ``chainid dynamics --segment-model M.toml``.

The file is read by the one loader, :func:`chainid.model.modelfile.load_model` (an
:class:`~chainid.model.augmented.AugmentedModel`).  It describes one *specimen* (the tested piece of chain
of n_ref = ``base.chain.n`` links): its chain kernel, memory effects and a time-domain damping.  Every
segment of the chain line carries the same physics, scaled in series (springs and dampers in series: a
segment of n_s links carries the specimen's force at n_s/n_ref times its elongation, so every compliance
scales by n_s/n_ref and every force is unchanged; see :class:`chainid.dynamics.model.ChainLine`):

=====================================  ===============================================================
model                                  segment (specimen values; scaled by ChainLine)
=====================================  ===============================================================
chain base (spec, variant)             the line's chain and kernel variant; n_ref = base.chain.n
damping ``viscous`` c                  viscous c [N·s/mm] (``damping``)
damping ``hysteretic`` η·k, x_max, n   Iwan elements of :func:`chainid.model.operators.iwan_for_loss`,
                                       (F_c,i, x_s,i) → Jenkins (k = F_c/x_s, f = F_c) (``hysteresis``)
damping ``coulomb`` F_c, x_s           Jenkins element; a stick stiffer than the specimen's link (x_s = 0
                                       included): Coulomb with the link stiffness as stick (``coulomb_N``)
damping ``law`` (identified c_e)       resolved by the model's own rule (:meth:`Damping.resolve`) at a
                                       stated operating point ω [rad/s], A [mm] (``omega``, ``amplitude``)
damping ``dahl`` F_h, x_h              a Dahl element (``dahl``; x_h scales like a compliance)
effect ``friction`` F_c, x_s, mu      the same Jenkins element, slip force F_c + mu·pretension
effect ``hysteresis`` F_h, x_h        a Dahl element
=====================================  ===============================================================

Refused with a message naming the part: a linear base, kernel modifiers and stiffness-side effects (the
segments carry the generated chain kernel).  The rule
``hysteretic``'s compensating spring k_comp (it cancels the Iwan elements' in-phase stiffness on one
harmonic cycle) is not carried: reported in the returned notes.  The model's mass and delay are not used
(the segment masses come from the chain; a channel lag is a property of the rig, not of the chain).
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from chainid.model import kernels
from chainid.model.modelfile import load_model
from chainid.model.operators import iwan_for_loss

__all__ = ["segment_kwargs"]

#: kernel modifiers of a chain base and their neutral values (chainid.model.base.ChainModel)
_MODIFIERS = {"slack": 0.0, "compliance": 0.0, "hertz_scale": 1.0, "contact_exponent": None, "ea_scale": 1.0}


def _add_jenkins(out: dict[str, Any], els: list[tuple[float, float]], F_c: float, x_s: float, where: str,
                 k_link: float, notes: list[str]) -> None:
    """A Jenkins element, or the line's Coulomb element for a stick stiffer than the link (x_s = 0 included).

    A stick stiffness F_c/x_s above the specimen's link stiffness k_link = 1/c_lin is not resolved by a time
    step the chain itself allows (it would shrink dt_stable by √(k/k_link)): such a stick is the Coulomb
    element with stick stiffness k_link (a note says so).
    """
    if F_c <= 0:
        return
    if x_s > 0 and F_c / x_s <= k_link:
        els.append((F_c / x_s, F_c))
        return
    if out["coulomb_N"] > 0:
        raise ValueError(f"{where}: a second Coulomb element with a (near-)rigid stick; valid: one")
    out["coulomb_N"] = F_c
    notes.append(f"{where}: stick travel x_s = {x_s:.3g} mm is stiffer than the link ({k_link:.4g} N/mm): Coulomb "
                 f"friction {F_c:.6g} N with the link stiffness as stick stiffness")


def segment_kwargs(path: str | Path, *, pretension_N: float = 0.0, omega: float | None = None,
                   amplitude: float | None = None) -> tuple[dict[str, Any], list[str]]:
    """ChainLine keyword arguments of a model file, and notes (see the module docstring).

    Parameters
    ----------
    path : str or Path
        The model file (TOML or JSON).
    pretension_N : float
        The line's pretension [N]: the specimen's mean elongation x0 and tangent k_e for a ``law``.
    omega, amplitude : float, optional
        Operating point of a ``law`` damping: circular frequency [rad/s] (> 0) and the specimen's elongation
        amplitude [mm] (> 0); required for a law (c_e(ω, A) has no meaning in a transient).

    Returns
    -------
    (dict, list of str)
        ``chain``, ``variant``, ``damping_ref_links``, ``damping`` [N·s/mm], ``hysteresis``
        ((k [N/mm], f [N]), ...), ``dahl`` ((F_h [N], x_h [mm]), ...), ``coulomb_N`` [N]; and notes.
    """
    src = f"--segment-model {str(path)!r}"
    m = load_model(path)
    base = m.base
    if not hasattr(base, "hertz_scale"):
        raise ValueError(f"{src}: base {getattr(base, 'name', base)!r}; dynamics segments need a chain base "
                         "(the generated kernel of a chain spec)")
    mods = [k for k, neutral in _MODIFIERS.items() if getattr(base, k, neutral) != neutral]
    if mods:
        raise ValueError(f"{src}: base kernel modifiers {mods} are not supported by dynamics segments "
                         "(they carry the unmodified chain kernel)")
    chain = base.chain
    out: dict[str, Any] = {"chain": chain, "variant": base.variant, "damping_ref_links": int(chain.n),
                           "damping": 0.0, "hysteresis": (), "dahl": (), "coulomb_N": 0.0}
    notes: list[str] = []
    els: list[tuple[float, float]] = []
    k_link = 1.0 / float(kernels.coefficients(chain, base.variant)[0])  # N/mm: the specimen's link stiffness
    for name, p in m.effects:
        where = f"{src}: effect {name!r}"
        if name == "hysteresis":  # Dahl
            out["dahl"] += ((p.get("F_h", 0.0), p.get("x_h", 0.05)),) if p.get("F_h", 0.0) > 0 else ()
            continue
        if name != "friction":
            raise ValueError(f"{where} is not supported by dynamics segments; valid: friction, hysteresis")
        F_c = p.get("F_c", 0.0)
        if p.get("mu", 0.0):
            F_c += p["mu"] * pretension_N
            notes.append(f"{where}: the load-dependent part mu·|F_k| (mu = {p['mu']:.4g}) is taken at the "
                         f"pretension: slip force {F_c:.6g} N")
        _add_jenkins(out, els, F_c, p.get("x_s", 0.0), where, k_link, notes)
    d = m.damping
    from chainid.model.passivity import OperatingPoint, check_passive

    x0 = float(kernels.displacement(pretension_N, chain, base.variant)) if pretension_N > 0 else 0.0
    if d.form == "law":
        for name, v in (("omega", omega), ("amplitude", amplitude)):
            if v is None or not (math.isfinite(v) and v > 0):
                raise ValueError(f"{src}: the damping is an identified law c_e(ω, A); give its operating point: "
                                 f"{name} = {v!r} is invalid: valid range > 0 (--segment-omega rad/s, "
                                 "--segment-amplitude mm)")
        ke = d.k_e if d.k_e is not None else float(kernels.stiffness(max(x0, 1e-6), chain, base.variant))
        d = d.resolve(float(omega), float(amplitude), ke, x0=x0)
        notes.append(f"damping law {m.damping.law!r} resolved by rule {m.damping.rule!r} at omega = {omega:g} rad/s, "
                     f"A = {amplitude:g} mm, k_e = {ke:.6g} N/mm: {d.form} {d.params}")
    # the one rule for a negative dashpot (chainid.model.passivity): refused at the operating point
    check_passive(m, [OperatingPoint("the operating point", omega, amplitude, x0)],
                  what=src, hint="a law extrapolated beyond its tests can turn negative: choose an operating point "
                                 "inside them (--segment-omega, --segment-amplitude)")
    p = d.params
    where = f"{src}: damping ({d.form})"
    if d.form == "viscous":
        out["damping"] = float(p.get("c", 0.0))
    elif d.form == "hysteretic":
        F_c, x_s = iwan_for_loss(p.get("eta_k", 0.0), p.get("x_max", 1.0), int(p.get("n", 32)))
        els += [(float(f) / float(x), float(f)) for f, x in zip(F_c, x_s) if f > 0]
        if p.get("k_comp", 0.0):
            notes.append(f"the hysteretic rule's compensating spring k_comp = {p['k_comp']:.6g} N/mm is not carried "
                         "by dynamics segments: the Iwan elements keep their in-phase stiffness")
    elif d.form == "coulomb":
        _add_jenkins(out, els, p.get("F_c", 0.0), p.get("x_s", 0.0), where, k_link, notes)
    elif d.form == "dahl":
        out["dahl"] += ((p.get("F_h", 0.0), p.get("x_h", 1.0)),) if p.get("F_h", 0.0) > 0 else ()
    elif d.form != "none":
        raise ValueError(f"{where}: damping form {d.form!r} is not supported by dynamics segments; valid: none, "
                         "viscous, hysteretic, dahl, coulomb, law")
    out["hysteresis"] = tuple(els)
    return out, notes
