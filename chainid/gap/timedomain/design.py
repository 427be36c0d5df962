"""The time-domain model of a device as a fixed force plus columns times amplitudes, on a record's samples.

For an effect set and its *shape* parameters (stick travel, Dahl travel, Bouc–Wen shape, a dead band, the lag,
the chain's stiffness-side changes) the model force on a record is

    F(t) = f(t) + Σ_j a_j·φ_j(t),

f the part with no free amplitude (the chain spring F_k(x) with its stiffness-side effects, the chain's mass
m·ẍ) and φ_j the columns of the free amplitudes a_j (:mod:`chainid.gap.timedomain.lsq` fits them):

* the base — a chain: the dashpot ``damping.c`` (ẋ); a linear device: ``spring.k`` (x, or the play output of
  ``backlash``), ``mass.m`` (ẍ·1e-3, unless the mass is given) and ``damping.c`` (ẋ), with a force offset per
  record projected out (per-test preloads are nuisance parameters: every column and the target lose their mean
  over the record's samples);
* every force- and mass-kind effect's amplitudes (:func:`chainid.model.effects.columns`);
* ``damping_law``: the damping's slopes over record features, (ω_r − w_ref)·ẋ and (A_r − A_ref)·ẋ;
* a covariate term ``effect.param@cov``: the column of that amplitude times (cov_r − cov_ref).

``sensor_delay`` evaluates the whole model on the motion at t − τ (the force lags the displacement by τ).  The
memory operators run over the samples of the view in order (the whole record, or its fit subset).  The sign of
sliding friction is its expectation given the estimated velocity and its spread over the sample
(:meth:`chainid.gap.core.kinematics.Kinematics.v_spread`, :func:`chainid.model.effects.forms.sliding_sign`).

Units: t s, x mm, ẋ mm/s, ẍ mm/s², F N, m kg, ω rad/s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np

from chainid.model.effects import SPECS, STIFFNESS_SIDE, columns, make_effect, modify_model, play_operator

__all__ = ["Base", "split_name", "amplitude_names", "amplitude_bounds", "shape_names", "build"]


@dataclass
class Base:
    """The base model of a time-domain problem.

    ``model``: the chain model (``kind == "chain"``) or None (a linear device fitted here); ``mass_kg``: a given
    moving mass [kg] of a linear base (None: fitted, >= 0); ``refs``: the reference values of the data the
    fixed parameters take (``x_mid`` [mm], ``w_ref`` [rad/s], ``A_ref`` [mm], ``cov:NAME``).
    """

    kind: str
    model: Any = None
    mass_kg: float | None = None
    refs: dict[str, float] = field(default_factory=dict)

    @property
    def offsets(self) -> bool:
        """Per-record force offsets (nuisance) are projected out: a linear device has no absolute zero of force."""
        return self.kind == "linear"


def split_name(term: str) -> tuple[str, str | None, str | None]:
    """``effect`` → (effect, None, None); ``effect.param@cov`` (a covariate term) → (effect, param, cov)."""
    if "@" in term:
        head, cov = term.split("@", 1)
        eff, _, par = head.partition(".")
        return eff, par, cov
    return term, None, None


def _effects(names: Sequence[str]) -> list[str]:
    return [n for n in names if "@" not in n]


def amplitude_names(base: Base, names: Sequence[str]) -> list[str]:
    """The free amplitudes of an effect set, in column order (base first, then effects, then covariate terms)."""
    out = (["spring.k"] + (["mass.m"] if base.mass_kg is None else []) if base.kind == "linear" else [])
    out.append("damping.c")
    for n in _effects(names):
        if n == "damping_law":
            out += ["damping_law.b_w", "damping_law.b_A"]
            continue
        spec = SPECS[n]
        if spec.kind not in ("force", "mass"):
            continue
        out += [f"{n}.{p.name}" for p in spec.params if p.amplitude and p.fitted
                and not (n == "friction" and p.name == "mu" and base.kind != "chain")
                and not (n == "stribeck" and p.name == "dF" and base.offsets)]
    out += [t for t in names if "@" in t]
    return out


def amplitude_bounds(names: Sequence[str]) -> tuple[np.ndarray, np.ndarray]:
    """Bounds of the amplitudes ``names``: >= 0 where the library says so (a dashpot, a mass, a friction force,
    a spring of a passive device), free otherwise (slopes, cubic terms, an asymmetry)."""
    nonneg = {"spring.k", "mass.m", "damping.c"}
    for n, s in SPECS.items():
        for p in s.params:
            if p.amplitude and p.valid[0] >= 0.0:
                nonneg.add(f"{n}.{p.name}")
    lo = np.array([0.0 if k in nonneg else -np.inf for k in names])
    return lo, np.full(len(names), np.inf)


def shape_names(base: Base, names: Sequence[str], scales: dict[str, float]) -> list[tuple[str, float, float]]:
    """The shape parameters of an effect set with their fit bounds: (``effect.param``, low, high)."""
    out = []
    for n in _effects(names):
        if n == "damping_law":
            continue
        e = make_effect(n, scales["F"], scales["x"], scales["omega"], v_scale=scales["v"], x_mid=scales["x_mid"],
                        tau_max=scales["tau"])
        for k, (lo, hi), amp in zip(e.param_names, e.bounds, e.amplitude):
            if not amp:
                out.append((f"{n}.{k}", lo, hi))
    return out


def _params_of(p: dict[str, float], name: str) -> dict[str, float]:
    pre = name + "."
    return {k[len(pre):]: v for k, v in p.items() if k.startswith(pre)}


def _shift(t: np.ndarray, y: np.ndarray, tau: float) -> np.ndarray:
    return np.interp(t - tau, t, y) if tau else y


def build(base: Base, names: Sequence[str], shapes: dict[str, float], d: Any, idx: np.ndarray | None = None
          ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Fixed force f [N], columns Φ (n, p) and target y = F [N] of an effect set on record ``d`` at ``shapes``.

    ``d`` is a :class:`chainid.gap.timedomain.data.TimeData` (its smooth kinematics, features, covariates);
    ``idx`` the samples of the view (None: all; the memory operators run over them in order).  With per-record
    offsets (a linear base) f, Φ and y lose their mean over the view.
    """
    tau = float(shapes.get("sensor_delay.tau", 0.0)) if "sensor_delay" in names else 0.0
    sel = slice(None) if idx is None else idx
    x = _shift(d.t, d.x, tau)[sel]
    xd = _shift(d.t, d.xd, tau)[sel]
    xdd = _shift(d.t, d.xdd, tau)[sel]
    y = np.asarray(d.F, float)[sel]
    v_err = _shift(d.t, d.kin.v_spread(d.t), tau)[sel] if getattr(d, "kin", None) is not None else 0.0
    amps = amplitude_names(base, names)
    Phi = np.zeros((y.size, len(amps)))
    col = {k: j for j, k in enumerate(amps)}
    eff = _effects(names)
    play_b = 0.5 * shapes.get("backlash.b", 0.0) if "backlash" in eff else 0.0
    xp = play_operator(x, play_b, periodic=False) if play_b > 0 else x
    if base.kind == "chain":
        model = base.model
        for n in eff:
            if n in STIFFNESS_SIDE:
                model = modify_model(n, _params_of(shapes, n), model)
        Fk = np.asarray(model.force(xp), float)
        f = Fk + float(model.mass_kg) * xdd * 1e-3
    else:
        Fk = None
        f = np.zeros_like(y) if base.mass_kg is None else float(base.mass_kg) * xdd * 1e-3
        Phi[:, col["spring.k"]] = xp
        if "mass.m" in col:
            Phi[:, col["mass.m"]] = xdd * 1e-3
    Phi[:, col["damping.c"]] = xd
    for n in eff:
        spec = SPECS[n]
        if n == "damping_law":
            Phi[:, col["damping_law.b_w"]] = (d.omega_c - base.refs.get("w_ref", 0.0)) * xd
            Phi[:, col["damping_law.b_A"]] = (d.A - base.refs.get("A_ref", 0.0)) * xd
            continue
        if spec.kind not in ("force", "mass"):
            continue
        p = _params_of(shapes, n)
        if n == "hardening":
            p["x_ref"] = base.refs.get("x_mid", 0.0)
        for a, c in columns(n, p, x, xd, xdd, Fk, periodic=False, v_err=v_err).items():
            if f"{n}.{a}" in col:
                Phi[:, col[f"{n}.{a}"]] = c
    for t in names:
        if "@" not in t:
            continue
        e, par, cov = split_name(t)
        if f"{e}.{par}" in col:
            src = Phi[:, col[f"{e}.{par}"]]
        else:  # the effect itself is not in the set: its amplitude lives only through the covariate
            src = columns(e, _params_of(shapes, e), x, xd, xdd, Fk, periodic=False, v_err=v_err)[par]
        Phi[:, col[t]] = (d.covariates.get(cov, math.nan) - base.refs.get(f"cov:{cov}", 0.0)) * src
    if base.offsets:
        f = f - f.mean()
        y = y - y.mean()
        Phi = Phi - Phi.mean(axis=0)
    return f, Phi, y
