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
* the damping's slopes over record features, (ω_r − w_ref)·ẋ and (A_r − A_ref)·ẋ: part of the base when its
  ``law`` is on (:class:`Base`), else the effect ``damping_law``;
* a covariate term ``effect.param@cov``: the column of that amplitude times (cov_r − cov_ref); ``effect@cov``: the
  effect with every amplitude following the covariate (its columns, and each times (cov_r − cov_ref)).

``sensor_delay`` evaluates the whole model on the motion at t − τ (the force lags the displacement by τ); the
samples whose t − τ falls outside the record (the motion there is unknown) carry no residual.  The memory
operators run over the samples of the view in order (the whole record, or its fit subset).  The sign of
sliding friction is its expectation given the estimated velocity and its spread over the sample
(:meth:`chainid.gap.core.kinematics.Kinematics.v_spread`, :func:`chainid.model.effects.forms.sliding_sign`).
Where a record's force is compared below a cut (``f_res``, :mod:`chainid.gap.timedomain.bandlimit`), the target
and every column pass the same zero-phase low-pass (each once, then kept in the cache).

Units: t s, x mm, ẋ mm/s, ẍ mm/s², F N, m kg, ω rad/s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np

from chainid.gap.timedomain.bandlimit import band_limited
from chainid.model.effects import (SPECS, STIFFNESS_SIDE, columns, identifiable, make_effect, modify_model,
                                   play_operator)

__all__ = ["Base", "ColumnCache", "MIN_FEATURE_SPAN", "split_name", "effect_of", "law_features", "amplitude_names",
           "amplitude_bounds", "shape_names", "build"]


@dataclass
class Base:
    """The base model of a time-domain problem.

    ``model``: the chain model (``kind == "chain"``) or None (a linear device fitted here); ``mass_kg``: a given
    moving mass [kg] of a linear base (None: fitted, >= 0); ``refs``: the reference values of the data the
    fixed parameters take (``x_mid`` [mm], ``w_ref`` [rad/s], ``A_ref`` [mm], ``cov:NAME``); ``law``: the
    dashpot follows the records' features, c_r = c + b_w·(ω_r − w_ref) + b_A·(A_r − A_ref) (the paper's
    c_e(ω, A) carried to any excitation, part of the base), instead of one c for every record;
    ``law_features``: the features that law (or the effect ``damping_law``) follows, ``"w"`` and/or ``"A"``
    (:func:`law_features`: a feature the records do not spread has no slope).
    """

    kind: str
    model: Any = None
    mass_kg: float | None = None
    refs: dict[str, float] = field(default_factory=dict)
    law: bool = False
    law_features: tuple[str, ...] = ("w", "A")

    @property
    def offsets(self) -> bool:
        """Per-record force offsets (nuisance) are projected out: a linear device has no absolute zero of force."""
        return self.kind == "linear"


def split_name(term: str) -> tuple[str, str | None, str | None]:
    """``effect`` → (effect, None, None); ``effect@cov`` (every amplitude of the effect following a covariate) →
    (effect, None, cov); ``effect.param@cov`` (one amplitude following it) → (effect, param, cov)."""
    if "@" in term:
        head, cov = term.split("@", 1)
        eff, _, par = head.partition(".")
        return eff, (par or None), cov
    return term, None, None


def effect_of(term: str) -> str | None:
    """The library effect a term adds: itself, or the effect of ``effect@cov``; None for ``effect.param@cov``
    (a slope of an amplitude already in the model)."""
    eff, par, _ = split_name(term)
    return eff if par is None else None


def _effects(names: Sequence[str]) -> list[str]:
    out: list[str] = []
    for n in names:
        e = effect_of(n)
        if e is not None and e not in out:
            out.append(e)
    return out


#: a record feature carries a slope of the dashpot law only when it spans at least this share of its largest value
#: over the training records: across repeats of one test (a spread of 1e-4) a "law" would be one c per record
MIN_FEATURE_SPAN = 0.05


def law_features(omegas: Sequence[float], amplitudes: Sequence[float]) -> tuple[str, ...]:
    """The record features a dashpot law over the training records can follow: ``"w"`` (band centre [rad/s]) and
    ``"A"`` (half range [mm]), each when its span is at least ``MIN_FEATURE_SPAN`` of its largest value."""
    out = []
    for k, v in (("w", omegas), ("A", amplitudes)):
        v = np.abs(np.asarray(v, float))
        if v.size and float(np.max(v)) > 0 and float(np.ptp(v)) >= MIN_FEATURE_SPAN * float(np.max(v)):
            out.append(k)
    return tuple(out)


def amplitude_names(base: Base, names: Sequence[str]) -> list[str]:
    """The free amplitudes of an effect set, in column order (base first, then effects, then covariate terms)."""
    out = (["spring.k"] + (["mass.m"] if base.mass_kg is None else []) if base.kind == "linear" else [])
    out.append("damping.c")
    if base.law or "damping_law" in _effects(names):
        out += ["damping_law.b_w", "damping_law.b_A"]
    for n in _effects(names):
        if n == "damping_law":
            continue
        spec = SPECS[n]
        if spec.kind not in ("force", "mass"):
            continue
        out += [f"{n}.{p.name}" for p in spec.params if p.amplitude and p.fitted
                and identifiable(n, p.name, base.kind)]
    for t in names:
        eff, par, cov = split_name(t)
        if cov is None:
            continue
        if par is not None:
            out.append(t)
        else:  # every amplitude of the effect follows the covariate
            out += [f"{a}@{cov}" for a in list(out) if a.startswith(eff + ".") and "@" not in a]
    return out


def amplitude_bounds(names: Sequence[str]) -> tuple[np.ndarray, np.ndarray]:
    """Bounds of the amplitudes ``names``: >= 0 where the library says so (a dashpot, a mass, a friction force,
    a spring of a passive device), free otherwise (slopes, cubic terms, an asymmetry)."""
    from chainid.model.ranges import EFFECT_RANGES

    nonneg = {"spring.k", "mass.m", "damping.c"}
    for n, s in SPECS.items():
        for p in s.params:
            if p.amplitude and EFFECT_RANGES[n][p.name].lo >= 0.0:
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


class ColumnCache:
    """Memo of a problem's design pieces that do not change between evaluations: the motion of a view at a lag,
    the play output, the chain's spring force at its stiffness-side shapes, and each effect's columns at its own
    shapes (searching a new effect's shapes re-evaluates only that effect).  At most ``max_bytes`` of arrays
    (the oldest entries dropped first)."""

    def __init__(self, max_bytes: int = 400 * 2**20):
        self.max_bytes = max_bytes
        self.store: dict[tuple, Any] = {}
        self.sizes: dict[tuple, int] = {}
        self.nbytes = 0

    @staticmethod
    def _size(val: Any) -> int:
        if isinstance(val, np.ndarray):
            return val.nbytes
        if isinstance(val, dict):
            return sum(ColumnCache._size(v) for v in val.values())
        if isinstance(val, (tuple, list)):
            return sum(ColumnCache._size(v) for v in val)
        return 64

    def get(self, key: tuple, make: Any) -> Any:
        if key in self.store:
            return self.store[key]
        val = make()
        size = self._size(val)
        if size > self.max_bytes:
            return val
        while self.store and self.nbytes + size > self.max_bytes:
            old = next(iter(self.store))
            self.store.pop(old)
            self.nbytes -= self.sizes.pop(old)
        self.store[key] = val
        self.sizes[key] = size
        self.nbytes += size
        return val


def _view(d: Any, idx: np.ndarray | None, tau: float) -> tuple[np.ndarray, ...]:
    """x, ẋ, ẍ and the velocity's error spread at the view's samples, each lagged by ``tau`` (interpolated at
    the view's times only)."""
    sel = slice(None) if idx is None else idx
    ts = d.t[sel] - tau

    def at(y: np.ndarray) -> np.ndarray:
        return np.interp(ts, d.t, y) if tau else y[sel]

    v_err = at(d.kin.v_spread(d.t)) if getattr(d, "kin", None) is not None else np.zeros(0)
    return at(d.x), at(d.xd), at(d.xdd), v_err


@dataclass
class _RecordView:
    """One record's samples as the model sees them: the view ``idx`` (None: all) at lag τ, its kinematics, the
    play output ``xp`` of a backlash of half-width ``play_b`` [mm], and the cache that keeps filtered columns."""

    d: Any
    idx: np.ndarray | None
    cache: ColumnCache
    tau: float
    play_b: float = 0.0

    def __post_init__(self) -> None:
        self.key = (self.d.test, "all" if self.idx is None else "sub", self.tau)
        self.x, self.xd, self.xdd, v_err = self.cache.get(self.key + ("view",), lambda: _view(self.d, self.idx,
                                                                                             self.tau))
        self.v_err = v_err if v_err.size else 0.0
        self.f_res = float(getattr(self.d, "f_res", math.nan))
        self.xp = self.x
        if self.play_b > 0:
            self.xp = self.cache.get(self.key + ("play", self.play_b),
                                     lambda: play_operator(self.x, self.play_b, periodic=False))
        self.Fk: np.ndarray | None = None

    def lp(self, tag: tuple, a: np.ndarray) -> np.ndarray:
        """A column as the comparison sees it: below the record's cut where its force is band-limited
        (:mod:`.bandlimit`; every column is filtered once, then kept), else as it is."""
        if not math.isfinite(self.f_res):
            return a
        return self.cache.get(self.key + ("lp",) + tag, lambda: band_limited(a, self.d.fs, self.f_res, self.idx))

    def effect_cols(self, base: Base, shapes: dict[str, float], n: str) -> dict[str, np.ndarray]:
        """The columns of effect ``n``'s amplitudes at its shape parameters (:func:`chainid.model.effects.columns`)."""
        p = _params_of(shapes, n)
        if n == "hardening":
            p["x_ref"] = base.refs.get("x_mid", 0.0)
        amp_names = {a.name for a in SPECS[n].params if a.amplitude}
        shape_key = tuple(sorted((k, v) for k, v in p.items() if k not in amp_names))
        ck = ("effect", n, self.play_b if n == "friction" else 0.0, shape_key)
        cols = self.cache.get(self.key + ck, lambda: columns(n, p, self.x, self.xd, self.xdd, self.Fk,
                                                             periodic=False, v_err=self.v_err))
        return {a: self.lp(ck + (a,), c) for a, c in cols.items()}


def _base_columns(base: Base, eff: Sequence[str], shapes: dict[str, float], v: _RecordView, Phi: np.ndarray,
                  col: dict[str, int], y: np.ndarray) -> np.ndarray:
    """The base's fixed force f [N] (a chain: F_k at the play output with the stiffness-side effects, plus m·ẍ;
    a linear device with a given mass: m·ẍ) and its columns in Φ: spring, mass, dashpot and the dashpot's
    slopes over record features; sets ``v.Fk`` (the chain's spring force) for the effects that read it."""
    if base.kind == "chain":
        side = tuple((n, tuple(sorted(_params_of(shapes, n).items()))) for n in eff if n in STIFFNESS_SIDE)

        def spring() -> np.ndarray:
            model = base.model
            for n, pp in side:
                model = modify_model(n, dict(pp), model)
            return np.asarray(model.force(v.xp), float)

        v.Fk = v.cache.get(v.key + ("spring", v.play_b, side), spring)
        f = v.lp(("spring", v.play_b, side), v.Fk) + float(base.model.mass_kg) * v.lp(("xdd",), v.xdd) * 1e-3
    else:
        f = np.zeros_like(y) if base.mass_kg is None else float(base.mass_kg) * v.lp(("xdd",), v.xdd) * 1e-3
        Phi[:, col["spring.k"]] = v.lp(("play", v.play_b), v.xp)
        if "mass.m" in col:
            Phi[:, col["mass.m"]] = v.lp(("xdd",), v.xdd) * 1e-3
    xd_c = v.lp(("xd",), v.xd)
    Phi[:, col["damping.c"]] = xd_c
    if "damping_law.b_w" in col:  # the dashpot following the record's features (the base's law, or the effect)
        if "w" in base.law_features:
            Phi[:, col["damping_law.b_w"]] = (v.d.omega_c - base.refs.get("w_ref", 0.0)) * xd_c
        if "A" in base.law_features:
            Phi[:, col["damping_law.b_A"]] = (v.d.A_c - base.refs.get("A_ref", 0.0)) * xd_c
    return f


def _covariate_columns(base: Base, shapes: dict[str, float], amps: Sequence[str], v: _RecordView, Phi: np.ndarray,
                       col: dict[str, int]) -> None:
    """The columns of the covariate terms ``effect.param@cov``: the amplitude's column times (cov_r − cov_ref)."""
    for t in amps:
        if "@" not in t:
            continue
        e, par, cov = split_name(t)
        src = Phi[:, col[f"{e}.{par}"]] if f"{e}.{par}" in col else v.effect_cols(base, shapes, e)[par]
        Phi[:, col[t]] = (v.d.covariates.get(cov, math.nan) - base.refs.get(f"cov:{cov}", 0.0)) * src


def _unfitted_rows(base: Base, v: _RecordView, lead: np.ndarray | None, f: np.ndarray, Phi: np.ndarray,
                   y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per-record offsets projected out (a linear base), and the rows that carry no residual: the lead-in and
    the samples whose lagged motion t − τ falls outside the record (Φ = 0 and y = f there)."""
    if base.offsets:
        w = np.ones(y.size) if lead is None else (~lead).astype(float)
        w /= w.sum()
        f = f - w @ f
        y = y - w @ y
        Phi -= w @ Phi  # the mean over the fitted rows, as a product (a row-wise mean of (n, p) is 10x slower)
    if lead is not None:
        Phi[lead] = 0.0
        y = np.where(lead, f, y)
    if v.tau:
        ts = np.asarray(v.d.t, float)[slice(None) if v.idx is None else v.idx] - v.tau
        out = (ts < v.d.t[0]) | (ts > v.d.t[-1])
        if out.any():
            Phi[out] = 0.0
            y = np.where(out, f, y)
    return f, Phi, y


def build(base: Base, names: Sequence[str], shapes: dict[str, float], d: Any, idx: np.ndarray | None = None,
          cache: ColumnCache | None = None, lead: np.ndarray | None = None
          ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Fixed force f [N], columns Φ (n, p) and target y = F [N] of an effect set on record ``d`` at ``shapes``.

    ``d`` is a :class:`chainid.gap.timedomain.data.TimeData` (its smooth kinematics, features, covariates);
    ``idx`` the samples of the view (None: all; the memory operators run over them in order); ``lead`` a boolean
    mask over the view of lead-in samples, which carry the operators' state but are not fitted (their rows of Φ
    are 0 and y = f there).  With per-record offsets (a linear base) f, Φ and y lose their mean over the view's
    fitted samples.  ``cache`` keeps pieces between calls.
    """
    eff = _effects(names)
    tau = float(shapes.get("sensor_delay.tau", 0.0)) if "sensor_delay" in names else 0.0
    play_b = 0.5 * shapes.get("backlash.b", 0.0) if "backlash" in eff else 0.0
    v = _RecordView(d, idx, cache if cache is not None else ColumnCache(0), tau, play_b)
    y = v.lp(("F",), np.asarray(d.F, float)[slice(None) if idx is None else idx])
    amps = amplitude_names(base, names)
    Phi = np.zeros((y.size, len(amps)))
    col = {k: j for j, k in enumerate(amps)}
    f = _base_columns(base, eff, shapes, v, Phi, col, y)
    for n in eff:
        if SPECS[n].kind not in ("force", "mass"):
            continue
        for a, c in v.effect_cols(base, shapes, n).items():
            if f"{n}.{a}" in col:
                Phi[:, col[f"{n}.{a}"]] = c
    _covariate_columns(base, shapes, amps, v, Phi, col)
    return _unfitted_rows(base, v, lead, f, Phi, y)
