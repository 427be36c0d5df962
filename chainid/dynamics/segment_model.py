"""A diagnosed model file as the segments of a chain line: ``chainid dynamics --segment-model M.toml``.

The file is read by the one loader, :func:`chainid.model.modelfile.load_model` (an
:class:`~chainid.model.augmented.AugmentedModel`).  It describes one *specimen* (the tested piece of chain of
n_ref = ``base.chain.n`` links): its chain kernel, effects of the library (:mod:`chainid.model.effects`) and a
time-domain damping.  Every segment of the chain line carries the same physics, scaled in series (springs and
dampers in series: a segment of n_s links carries the specimen's force at r = n_s/n_ref times its elongation, so
every travel-like parameter — x_s, x_h, x_y, b, g, x_c, s, and the Stribeck speed v_s — and every compliance
scales by r, every stiffness by 1/r, a dead band's k_d [N/mm^p] by r^−p, and every force is unchanged; see
:mod:`chainid.dynamics.line_tables`):

=====================================  ===============================================================
model                                  segment (specimen values; scaled by ChainLine)
=====================================  ===============================================================
chain base (spec, variant)             the line's chain and kernel variant; n_ref = base.chain.n
base kernel modifiers and the          the modified kernel, composed as the library does
stiffness-side effects                 (:func:`chainid.model.effects.modify_model`): ``ea_scale``
(``stiffness_level`` scale,            (c_lin/scale), ``hertz_scale`` and ``contact_exponent`` (the
``contact_law`` scale, beta,           free-exponent kernel), ``compliance`` (+c_lin), ``slack`` (the
``slack`` s, ``machine_compliance`` c) spring carries load from e = s)
effect ``friction`` F_c, x_s, mu      a Jenkins element, slip force F_c + mu·pretension; a stick stiffer
                                       than the link (x_s = 0 included): Coulomb with the link stiffness
                                       as stick (``coulomb_N``)
effect ``hysteresis`` F_h, x_h        a Dahl element (``dahl``)
effect ``stribeck`` F_c, dF_s, v_s,   a Stribeck element on the segment's ė (``stribeck``): a Jenkins
dF                                     slider whose slip force F_c + dF_s·exp(−(ė/v_s)²) ± dF follows ė,
                                       its stick spring (the link stiffness) the regularised sign near rest
effect ``bouc_wen`` F_y, x_y, n, r    a Bouc–Wen element (``bouc_wen``; :func:`~chainid.model.operators.
                                       bouc_wen_step` on its travel table)
effect ``backlash`` b                 a play of width b in series with the spring (``backlash_mm``; the
                                       spring acts on the play output, :func:`~chainid.model.operators.
                                       play_step`)
effect ``deadband`` k_d, g, p, x_c    a memoryless force k_d·sgn(u)·max(|u| − g, 0)^p, u = e − x_c
                                       (``deadband``)
effect ``fixture_mass`` m_f           added to the driven node 0 (``drive_mass_kg``): the fixture moved
                                       with the specimen's driven end, so it adds m_f·a_0 to the drive
                                       force, not to the chain's motion under a prescribed drive (a note)
effect ``hardening``                  refused: a chain base has no linear spring to harden
delay ``delay_s`` (``sensor_delay``)  not simulated: a measurement lag of the rig (a note)
damping ``viscous`` c                 viscous c [N·s/mm] (``damping``)
damping ``hysteretic`` η·k, x_max, n   Iwan elements of :func:`chainid.model.operators.iwan_for_loss`,
                                       (F_c,i, x_s,i) → Jenkins (k = F_c/x_s, f = F_c) (``hysteresis``)
damping ``coulomb`` F_c, x_s           as effect ``friction`` (without mu)
damping ``law`` (identified c_e),      resolved by the model's own rule (:meth:`Damping.resolve`) at a
``feature`` (c over record features)   stated operating point ω [rad/s], A [mm] (``omega``, ``amplitude``)
damping ``dahl`` F_h, x_h              a Dahl element (``dahl``)
covariate terms ``effect.param@cov``   resolved at the operating conditions given (``covariates``)
=====================================  ===============================================================

Refused with a message naming the part: a linear base (a device, not a chain), ``hardening``, a second
``backlash`` or ``deadband``, a parameter outside its physical range (after the covariate terms).  The rule
``hysteretic``'s compensating spring k_comp (it cancels the Iwan elements' in-phase stiffness on one harmonic
cycle) is not carried: reported in the returned notes.  The model's mass is not used (the segment masses come
from the chain; a fixture is ``fixture_mass``).
"""
from __future__ import annotations

import math
import numbers
from pathlib import Path
from typing import Any

import numpy as np

from chainid.model.effects import check_params, modify_model
from chainid.model.effects.library import STIFFNESS_SIDE
from chainid.model.modelfile import load_model
from chainid.model.timedamping import iwan_elements

__all__ = ["segment_kwargs"]

#: kernel modifiers of a chain base (chainid.model.base.ChainModel), carried by ChainLine fields of the same name
_MODIFIERS = ("ea_scale", "hertz_scale", "contact_exponent", "contact_ref_force", "compliance", "slack")


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


def _real_number(v: Any) -> float | None:
    """``v`` as a float when it is a real number (a Python or numpy int or float, or a 0-d numeric array), else
    None (a bool, a string, a sequence)."""
    if isinstance(v, (bool, np.bool_)):
        return None
    if isinstance(v, numbers.Real):
        return float(v)
    if isinstance(v, np.ndarray) and v.ndim == 0 and np.issubdtype(v.dtype, np.number) \
            and not np.issubdtype(v.dtype, np.complexfloating):
        return float(v)
    return None


def _at_conditions(m: Any, covariates: dict[str, float] | None, src: str, notes: list[str]) -> Any:
    """The model with its covariate terms resolved at the given operating conditions (a note lists them)."""
    cov = {}
    for k, v in dict(covariates or {}).items():
        x = _real_number(v)
        if x is None or not math.isfinite(x):
            raise ValueError(f"{src}: covariate {k} = {v!r} is invalid: valid range a finite number")
        cov[k] = x
    need = sorted({t.partition("@")[2] for t in m.covariate_terms})
    extra = sorted(set(cov) - set(need))
    if extra:
        notes.append(f"covariate(s) {', '.join(extra)} given but the model has no term over them: not used")
    if not need:
        return m
    spring = [t for t in m.covariate_terms if t.startswith("spring.")]
    if spring:
        raise ValueError(f"{src}: covariate term(s) {', '.join(spring)} act on a linear spring; a chain base has none "
                         "(valid: effect.param@cov, damping.c@cov)")
    missing = [c for c in need if c not in cov]
    if missing:
        terms = ", ".join(t for t in m.covariate_terms if t.partition("@")[2] in missing)
        raise ValueError(f"{src}: the model depends on covariate(s) {', '.join(map(repr, missing))} ({terms}); give "
                         "the operating condition: --segment-covariate NAME=VALUE")
    out = m.at_conditions(cov)
    notes.append("covariate terms resolved at " + ", ".join(f"{c} = {cov[c]:g} (ref {m.covariate_refs[c]:g})"
                                                            for c in need)
                 + ": " + ", ".join(f"{t} (slope {s:g})" for t, s in m.covariate_terms.items()))
    return out


def _composed_base(m: Any, src: str) -> Any:
    """The chain base with the stiffness-side effects applied (the library's composition), checked."""
    base = m.base
    for name, p in m.effects:
        if name in STIFFNESS_SIDE:
            check_params(name, p, f"{src}: effect")
            base = modify_model(name, p, base)
    return base


def _effect(name: str, p: dict[str, float], out: dict[str, Any], els: list, where: str, k_link: float,
            pretension_N: float, notes: list[str]) -> None:
    """One force-, play- or mass-kind effect into the line's fields (see the module docstring)."""
    if name == "friction":
        F_c = p.get("F_c", 0.0)
        if p.get("mu", 0.0):
            F_c += p["mu"] * pretension_N
            notes.append(f"{where}: the load-dependent part mu·|F_k| (mu = {p['mu']:.4g}) is taken at the "
                         f"pretension: slip force {F_c:.6g} N")
        _add_jenkins(out, els, F_c, p.get("x_s", 0.0), where, k_link, notes)
    elif name == "hysteresis":  # Dahl
        out["dahl"] += ((p.get("F_h", 0.0), p.get("x_h", 0.05)),) if p.get("F_h", 0.0) > 0 else ()
    elif name == "stribeck":
        F_c, dF_s, v_s, dF = (p.get(k, 0.0) for k in ("F_c", "dF_s", "v_s", "dF"))
        if abs(dF) > F_c:
            raise ValueError(f"{where}: dF = {dF:g} N is out of range: valid range |dF| <= F_c = {F_c:g} N (a slip "
                             "force that pushes the way it slides has no stick state)")
        if F_c > 0 or dF_s > 0:
            out["stribeck"] += ((F_c, dF_s, v_s, dF),)
            out["stribeck_stiffness"] = k_link
    elif name == "bouc_wen":
        if p.get("F_y", 0.0) > 0:
            out["bouc_wen"] += ((p["F_y"], p.get("x_y", 0.05), p.get("n", 1.0), p.get("r", 1.0)),)
    elif name in ("backlash", "deadband"):
        key = "backlash_mm" if name == "backlash" else "deadband"
        if out[key]:
            raise ValueError(f"{where}: a second {name} effect; valid: one (one play or dead band per segment)")
        if name == "backlash":
            out[key] = p.get("b", 0.0)
            if out[key] > 0:
                notes.append(f"{where}: the library's backlash (the spring on the play output, b = {out[key]:.6g} mm) "
                             "is not passive: it returns b·(F at the upper reversal − F at the lower) per cycle, "
                             "booked as negative dissipation, and can make the line's own oscillations grow")
        elif p.get("k_d", 0.0) > 0:
            out[key] = (p["k_d"], p.get("g", 0.0), p.get("p", 1.0), p.get("x_c", 0.0))
    elif name == "fixture_mass":
        out["drive_mass_kg"] += p.get("m_f", 0.0)
        if p.get("m_f", 0.0) > 0:
            notes.append(f"{where}: the fixture mass m_f = {p['m_f']:.6g} kg is added to the driven node 0 (the "
                         "fixture moved with the specimen's driven end): it adds m_f·a_0 to the drive force, not to "
                         "the chain's motion under a prescribed drive")
    elif name == "hardening":
        raise ValueError(f"{where} is not supported by dynamics segments: a chain base has no linear spring to "
                         "harden (hardening applies to a linear base; the chain's own stiffening is its kernel)")
    else:  # pragma: no cover - the library's names are all handled above
        raise ValueError(f"{where} is not supported by dynamics segments")


def _x0_ke(base: Any, pretension_N: float) -> tuple[float, float]:
    """The specimen's elongation x0 [mm] at the pretension and its tangent k_e [N/mm] there (the modified kernel)."""
    if pretension_N <= 0:
        x0 = float(base.slack)
    else:  # Eq. 15 with the modifiers' coefficients (the unmodified chain's are the kernel's, to rounding)
        c = base.coefficients
        beta = c[2] if len(c) == 3 else 2.0 / 3.0
        x0 = float(base.slack + c[0] * pretension_N + c[1] * pretension_N ** beta)
    return x0, float(base.stiffness(max(x0, base.slack + 1e-6)))


def _operating_point(d: Any, base: Any, src: str, pretension_N: float, omega: float | None,
                     amplitude: float | None, notes: list[str]) -> Any:
    """A ``law`` or ``feature`` damping resolved at the stated operating point (other forms as they are)."""
    if d.form not in ("law", "feature"):
        return d
    what = "an identified law c_e(ω, A)" if d.form == "law" else "a law over record features c(ω, A)"
    for name, v in (("omega", omega), ("amplitude", amplitude)):
        if v is None or not (math.isfinite(v) and v > 0):
            raise ValueError(f"{src}: the damping is {what}; give its operating point: {name} = {v!r} is invalid: "
                             "valid range > 0 (--segment-omega rad/s, --segment-amplitude mm)")
    x0, ke = _x0_ke(base, pretension_N)
    ke = d.k_e if d.k_e is not None else ke
    r = d.resolve(float(omega), float(amplitude), ke, x0=x0)
    how = f"resolved by rule {d.rule!r}" if d.form == "law" else "resolved"
    notes.append(f"damping {'law ' + repr(d.law) if d.form == 'law' else 'feature law'} {how} at omega = "
                 f"{omega:g} rad/s, A = {amplitude:g} mm, k_e = {ke:.6g} N/mm: {r.form} {r.params}")
    return r


def _damping(d: Any, out: dict[str, Any], els: list, src: str, k_link: float, at: str, notes: list[str]) -> None:
    """A resolved time-domain damping form into the line's fields."""
    p = d.params
    where = f"{src}: damping ({d.form})"
    if d.form == "viscous":
        out["damping"] = float(p.get("c", 0.0))
    elif d.form == "hysteretic":
        F_c, x_s = iwan_elements(p)
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
                         "viscous, hysteretic, dahl, coulomb, law, feature")


def segment_kwargs(path: str | Path, *, pretension_N: float = 0.0, omega: float | None = None,
                   amplitude: float | None = None,
                   covariates: dict[str, float] | None = None) -> tuple[dict[str, Any], list[str]]:
    """ChainLine keyword arguments of a model file, and notes (see the module docstring).

    Parameters
    ----------
    path : str or Path
        The model file (TOML or JSON).
    pretension_N : float
        The line's pretension [N]: the specimen's mean elongation x0 and tangent k_e for a ``law``, the slip force
        of a friction's mu.
    omega, amplitude : float, optional
        Operating point of a ``law`` or ``feature`` damping: circular frequency [rad/s] (> 0) and the specimen's
        elongation amplitude [mm] (> 0); required for those (c_e(ω, A) has no meaning in a transient).
    covariates : dict, optional
        Operating conditions (name → value in the covariate's unit) of the model's covariate terms; required for
        every covariate the model depends on.

    Returns
    -------
    (dict, list of str)
        ChainLine fields (``chain``, ``variant``, ``damping_ref_links``, ``damping`` [N·s/mm], ``hysteresis``
        ((k [N/mm], f [N]), ...), ``dahl`` ((F_h [N], x_h [mm]), ...), ``coulomb_N`` [N], the kernel modifiers,
        ``backlash_mm``, ``deadband``, ``stribeck``, ``stribeck_stiffness``, ``bouc_wen``, ``drive_mass_kg``) and
        notes.
    """
    src = f"--segment-model {str(path)!r}"
    m = load_model(path)
    if not hasattr(m.base, "hertz_scale"):
        raise ValueError(f"{src}: base {getattr(m.base, 'name', m.base)!r}; dynamics segments need a chain base "
                         "(the generated kernel of a chain spec; a linear base is a device, not a chain)")
    notes: list[str] = []
    m = _at_conditions(m, covariates, src, notes)
    base = _composed_base(m, src)
    chain = base.chain
    out: dict[str, Any] = {"chain": chain, "variant": base.variant, "damping_ref_links": int(chain.n),
                           "damping": 0.0, "hysteresis": (), "dahl": (), "coulomb_N": 0.0, "backlash_mm": 0.0,
                           "deadband": (), "stribeck": (), "stribeck_stiffness": None, "bouc_wen": (),
                           "drive_mass_kg": 0.0}
    out |= {k: getattr(base, k) for k in _MODIFIERS}
    els: list[tuple[float, float]] = []
    k_link = 1.0 / float(base.coefficients[0])  # N/mm: the specimen's link stiffness (with the modifiers)
    for name, p in m.effects:
        if name in STIFFNESS_SIDE:
            continue
        where = f"{src}: effect {name!r}"
        check_params(name, p, f"{src}: effect")
        _effect(name, p, out, els, where, k_link, pretension_N, notes)
    if m.delay_s:
        notes.append(f"the model's delay tau = {m.delay_s:.6g} s is a measurement lag; the chain is simulated "
                     "without it")
    d = _operating_point(m.damping, base, src, pretension_N, omega, amplitude, notes)
    from chainid.model.passivity import OperatingPoint, check_passive

    # the one rule for a negative dashpot (chainid.model.passivity): refused at the operating point
    check_passive(m, [OperatingPoint("the operating point", omega, amplitude, _x0_ke(base, pretension_N)[0])],
                  what=src, hint="a law extrapolated beyond its tests can turn negative: choose an operating point "
                                 "inside them (--segment-omega, --segment-amplitude)")
    at = f" at omega = {omega:g} rad/s, A = {amplitude:g} mm" if m.damping.form in ("law", "feature") else ""
    _damping(d, out, els, src, k_link, at, notes)
    out["hysteresis"] = tuple(els)
    return out, notes
