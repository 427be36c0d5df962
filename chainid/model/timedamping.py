"""Damping in time-domain form, and the rule that converts an identified c_e(ω, A) law into one.

The paper identifies an equivalent viscous coefficient c_e per harmonic test (Eq. 17–27); c_e(ω, A) has
no meaning in a transient.  A model carries one of these time-domain forms (units N, mm, s):

* ``viscous`` — F_d = c·ẋ, c [N·s/mm];
* ``hysteretic`` — rate-independent Masing/Iwan distribution of Jenkins elements
  (:func:`chainid.operators.iwan_for_loss`) with loop area π·η·k·A² for A ≤ x_max: params ``eta_k`` [N/mm],
  ``x_max`` [mm], ``n`` (elements);
* ``dahl`` — Dahl hysteresis, params ``F_h`` [N], ``x_h`` [mm];
* ``coulomb`` — Coulomb friction with elastic stick (Jenkins element), ``F_c`` [N], ``x_s`` [mm]
  (x_s = 0: Coulomb with rigid stick, sgn(ẋ) with 0 at reversals);
* ``law`` — an identified law c_e = X(ω, A, k_e)·p (:data:`LAWS`), converted for each record by the rule
  below; with ``per_test`` c_e of the tests it was fitted on;
* ``feature`` — a viscous c that follows the record's features (the time-domain form of the paper's c_e(ω, A)):
  c_r = c + b_w·(ω_r − w_ref) + b_A·(A_r − A_ref), ω_r the band centre [rad/s] and A_r the half range of x [mm]
  of the record (:func:`record_features`; a harmonic test's frequency and amplitude), params ``c`` [N·s/mm],
  ``b_w`` [N·s²/mm], ``b_A`` [N·s/mm²], ``w_ref`` [rad/s], ``A_ref`` [mm]; optionally the box of features the
  law was identified on, ``w_lo``, ``w_hi`` [rad/s], ``A_lo``, ``A_hi`` [mm]: a record outside it takes the law
  at the nearest point of the box (the law is not extrapolated, and a law >= 0 on its box is >= 0 everywhere).

**Conversion rule** (:meth:`Damping.resolve`).  For a record, its dominant angular frequency ω and
amplitude A (:func:`dominant`: the largest spectral line of x and its least-squares amplitude) give
c = c_e(ω, A, k_e(x0)).  ``rule = "viscous"`` (default) uses F_d = c·ẋ — exact for a harmonic test (it *is*
the identification's model); ``rule = "hysteretic"`` uses the Iwan distribution with the same energy per
cycle, π·c·ω·A² = π·η·k·A², i.e. η·k = c·ω and x_max = A, with a compensating linear spring −k_comp·(x − x0)
that removes the distribution's in-phase first harmonic on that cycle (k_comp ≈ 1.39·η·k), so only higher
harmonics differ from c·ẋ on a harmonic test; rate independent in a transient (its error is measured in
``tests/model/test_time_damping.py`` and stated in the README's model-file section).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from chainid.model import operators as ops

#: law name -> number of coefficients (c_e = X(ω, A, k_e)·p)
LAWS: dict[str, int] = {
    "polynomial": 5,
    "viscous": 1,
    "coulomb": 1,
    "hysteretic": 1,
    "viscous+coulomb": 2,
    "viscous+hysteretic": 2,
    "viscous+coulomb+hysteretic": 3,
}
#: time-domain forms and their parameters
FORMS: dict[str, tuple[str, ...]] = {
    "none": (),
    "viscous": ("c",),
    "hysteretic": ("eta_k", "x_max", "n", "k_comp", "x_c"),
    "dahl": ("F_h", "x_h"),
    "coulomb": ("F_c", "x_s"),
    "law": (),
    "feature": ("c", "b_w", "b_A", "w_ref", "A_ref", "w_lo", "w_hi", "A_lo", "A_hi"),
}
#: the optional box of a ``feature`` law's features (its identification range; see the module docstring)
BOX_KEYS = ("w_lo", "w_hi", "A_lo", "A_hi")
#: parameters that may be negative (a fitted slope; an identified c read as a lag)
SIGNED = ("c", "b_w", "b_A")
RULES = ("viscous", "hysteretic")
#: elements of the Iwan distribution of the ``hysteretic`` rule
IWAN_N = 32


def iwan_elements(params: dict[str, float]) -> tuple[np.ndarray, np.ndarray]:
    """The Iwan elements (slip forces F_c,i [N], stick travels x_s,i [mm]) of a ``hysteretic`` damping's params:
    :func:`chainid.model.operators.iwan_for_loss` with ``eta_k`` [N/mm] (default 0), ``x_max`` [mm] (default 1 mm)
    and ``n`` (default :data:`IWAN_N`); the model's own force and the dynamics segments both read them here."""
    return ops.iwan_for_loss(params.get("eta_k", 0.0), params.get("x_max", 1.0), int(params.get("n", IWAN_N)))


def _iwan_in_phase() -> float:
    """In-phase first-harmonic stiffness of :func:`chainid.operators.iwan_for_loss` (η·k = 1, x_max = A = 1) on its
    steady cycle, [N/mm per N/mm]: the rule's compensating spring removes it (computed once, 4000 steps)."""
    global _IN_PHASE
    if _IN_PHASE is None:
        psi = np.linspace(0, 4 * math.pi, 4001)
        Fc, xs = ops.iwan_for_loss(1.0, 1.0, IWAN_N)
        F = ops.iwan(np.sin(psi), Fc, xs)[0][2000:-1]
        _IN_PHASE = 2 * float(np.mean(F * np.sin(psi[2000:-1])))
    return _IN_PHASE


_IN_PHASE: float | None = None


def design(kind: str, w: np.ndarray, A: np.ndarray, ke: np.ndarray) -> np.ndarray:
    """Design matrix of law ``kind`` at ω [rad/s], A [mm], k_e [N/mm] (one row per test).

    ``polynomial`` is the paper's Eq. 21 (α₁ω² + α₂ω + α₃A² + α₄A + α₅); ``viscous`` 1; ``coulomb``
    4/(πωA) (Coulomb-equivalent c_e = 4F_f/(πωA)); ``hysteretic`` k_e/ω (c_e = η·k_e/ω); sums of the last three.
    """
    w = np.asarray(w, float)
    A = np.asarray(A, float)
    ke = np.asarray(ke, float)
    one = np.ones_like(w)
    cols = {"viscous": one, "coulomb": 4.0 / (math.pi * w * A), "hysteretic": ke / w}
    if kind == "polynomial":
        return np.column_stack([w**2, w, A**2, A, one])
    if kind not in LAWS:
        raise ValueError(f"damping law = {kind!r} is unknown; valid: {', '.join(LAWS)}")
    return np.column_stack([cols[p] for p in kind.split("+")])


def feature_c(c: float, b_w: float, b_A: float, omega: float, A: float, w_ref: float, A_ref: float) -> float:
    """The dashpot of a record with features ω [rad/s], A [mm] on the feature law
    c_r = c + b_w·(ω − w_ref) + b_A·(A − A_ref) [N·s/mm] (the paper's c_e(ω, A), Eq. 21–28, linear in its
    features; ``b_w`` [N·s²/mm], ``b_A`` [N·s/mm²])."""
    return c + b_w * (omega - w_ref) + b_A * (A - A_ref)


def record_features(t: np.ndarray, x: np.ndarray) -> tuple[float, float]:
    """The features a ``feature`` damping law reads of a record: the band centre ω_c [rad/s] — Σ ω·P(ω)/Σ P(ω) over
    the displacement's periodogram (mean removed, no window: a window's taper and a detrending both shift the
    power of the lowest lines) above its white noise floor (the median power of the upper half) — and the half
    range A [mm] of x.  For a sine: its angular frequency and amplitude; for a sum of lines: their power-weighted
    mean frequency."""
    t = np.asarray(t, float)
    x = np.asarray(x, float)
    n = x.size
    if n < 8:
        raise ValueError(f"a record needs >= 8 samples for its features; got {n}")
    dt = float(np.median(np.diff(t)))
    P = np.abs(np.fft.rfft(x - float(np.mean(x)))) ** 2
    f = np.fft.rfftfreq(n, dt)
    Pc = np.maximum(P - float(np.median(P[P.size // 2:])), 0.0)
    Pc[0] = 0.0
    tot = float(Pc.sum())
    w = 2 * math.pi * float(np.sum(f * Pc) / tot) if tot > 0 else 2 * math.pi * float(f[1])
    return w, 0.5 * float(np.ptp(x))


def dominant(t: np.ndarray, x: np.ndarray) -> tuple[float, float, float]:
    """Dominant angular frequency ω [rad/s], its amplitude A [mm] and the mean x0 [mm] of the oscillation.

    ω is the largest line of the spectrum of the velocity (Hann window; x resampled on a uniform grid of
    the same number of samples when t is not uniform; refined by a parabola through the log-magnitudes):
    the velocity spectrum is not dominated by a slow ramp or drift as the displacement's is.  The velocity
    is demodulated at ω and averaged over one period: A = median of the envelope |2·z(t)|/ω where it exceeds
    half its maximum (the oscillating part of the record), x0 = the mean of x there; ω is refined twice by
    the drift rate of the demodulated phase over that part.
    """
    t = np.asarray(t, float)
    x = np.asarray(x, float)
    if t.size < 8:
        raise ValueError(f"a record needs >= 8 samples to find its dominant frequency; got {t.size}")
    tu = np.linspace(t[0], t[-1], t.size)
    xu = np.interp(tu, t, x)
    dt = (tu[-1] - tu[0]) / (tu.size - 1)
    v = np.gradient(xu, dt)
    v = v - np.mean(v)
    X = np.abs(np.fft.rfft(v * np.hanning(v.size)))
    k = int(np.argmax(X[1:])) + 1
    shift = 0.0
    if 1 <= k < X.size - 1 and X[k - 1] > 0 and X[k + 1] > 0:
        a, b, c = np.log(X[k - 1]), np.log(X[k]), np.log(X[k + 1])
        den = a - 2 * b + c
        shift = 0.5 * (a - c) / den if den != 0 else 0.0
    w = 2 * math.pi * (k + shift) / (v.size * dt)
    n = max(1, min(v.size, int(round(2 * math.pi / w / dt))))
    for _ in range(2):  # refine ω by the drift of the demodulated phase over the oscillating part
        z = v * np.exp(-1j * w * tu)
        cs = np.concatenate([[0], np.cumsum(z)])
        zm = (cs[n:] - cs[:-n]) / n
        env = 2 * np.abs(zm)
        on = env >= 0.5 * env.max()
        if np.count_nonzero(on) > 2 * n:
            ph = np.unwrap(np.angle(zm[on]))
            w += float(np.polyfit(tu[:env.size][on], ph, 1)[0])
    A = float(np.median(env[on])) / w
    idx = np.flatnonzero(on)
    x0 = float(np.mean(xu[idx[0]: idx[-1] + n]))
    return float(w), A, x0


@dataclass
class Damping:
    """A damping force in time-domain form (see the module docstring for forms and the rule).

    Attributes
    ----------
    form : str
        One of :data:`FORMS`.
    params : dict
        The form's parameters (units in the module docstring).
    law, coefficients : str, list of float
        The identified law (form ``law``).
    k_e : float or None
        k_e [N/mm] the law's ``hysteretic`` column uses; None: the model's base tangent stiffness at x0.
    rule : str
        Conversion of the law for a record: ``viscous`` (default) or ``hysteretic`` (equal energy per cycle).
    per_test : dict
        c_e [N·s/mm] of the tests the law was fitted on (test id → value).
    """

    form: str = "none"
    params: dict[str, float] = field(default_factory=dict)
    law: str | None = None
    coefficients: list[float] = field(default_factory=list)
    k_e: float | None = None
    rule: str = "viscous"
    per_test: dict[str, float] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.form not in FORMS:
            raise ValueError(f"damping form = {self.form!r} is unknown; valid: {', '.join(FORMS)}")
        unknown = set(self.params) - set(FORMS[self.form])
        if unknown:
            raise ValueError(f"damping form {self.form!r}: unknown parameter(s) {sorted(unknown)}; "
                             f"valid: {', '.join(FORMS[self.form]) or 'none'}")
        for k, v in self.params.items():
            # an identified viscous c may be negative (a law extrapolated, a delay read as damping): finite only
            if not (isinstance(v, (int, float)) and math.isfinite(v) and (v >= 0 or k in SIGNED)):
                raise ValueError(f"damping {self.form}: {k} = {v!r} is out of range; valid range >= 0 (finite)")
        for lo, hi in (("w_lo", "w_hi"), ("A_lo", "A_hi")):
            if (lo in self.params) != (hi in self.params) or lo in self.params and self.params[lo] > self.params[hi]:
                raise ValueError(f"damping {self.form}: the law's box needs both {lo} <= {hi}; got "
                                 f"{lo} = {self.params.get(lo)!r}, {hi} = {self.params.get(hi)!r}")
        if self.form == "law":
            if self.law not in LAWS:
                raise ValueError(f"damping law = {self.law!r} is unknown; valid: {', '.join(LAWS)}")
            if len(self.coefficients) != LAWS[self.law]:
                raise ValueError(f"damping law {self.law!r} has {LAWS[self.law]} coefficient(s); "
                                 f"got {len(self.coefficients)}")
        if self.rule not in RULES:
            raise ValueError(f"damping rule = {self.rule!r} is unknown; valid: {', '.join(RULES)}")

    def ce(self, omega: float, A: float, ke: float) -> float:
        """c_e [N·s/mm] of the law at ω [rad/s], A [mm], k_e [N/mm]."""
        return float(design(self.law or "viscous", [omega], [A], [ke])[0] @ np.asarray(self.coefficients, float))

    def feature_value(self, omega: float, A: float) -> float:
        """The ``feature`` form's dashpot c [N·s/mm] at record features ω [rad/s], A [mm], held within the law's
        box when it has one (no extrapolation).  A law fitted onto its passive boundary is 0 there: a sum of three
        terms is exact to 4·ε times the sum of their magnitudes, so a c below 0 by no more than that is returned as
        0 (every user of the law, the passivity rule and a chain line alike, then sees c >= 0)."""
        p = self.params
        if "w_lo" in p and "w_hi" in p:
            omega = min(max(omega, p["w_lo"]), p["w_hi"])
        if "A_lo" in p and "A_hi" in p:
            A = min(max(A, p["A_lo"]), p["A_hi"])
        c, b_w, b_A = p.get("c", 0.0), p.get("b_w", 0.0), p.get("b_A", 0.0)
        w_ref, A_ref = p.get("w_ref", 0.0), p.get("A_ref", 0.0)
        value = feature_c(c, b_w, b_A, omega, A, w_ref, A_ref)
        roundoff = 4.0 * float(np.finfo(float).eps) * (abs(c) + abs(b_w * (omega - w_ref)) + abs(b_A * (A - A_ref)))
        return 0.0 if -roundoff <= value < 0.0 else value

    def resolve(self, omega: float, A: float, ke: float, test: str | None = None,
                fitted: bool = False, x0: float = 0.0) -> "Damping":
        """The time-domain form for a record of dominant ω [rad/s], amplitude A [mm] (k_e [N/mm] at its x0); for the
        ``feature`` form ω and A are the record's features (:func:`record_features`), held within the law's box
        when it has one.

        A ``law`` becomes ``viscous`` c = c_e(ω, A, k_e) (rule ``viscous``) or the Iwan distribution of equal
        energy per cycle (rule ``hysteretic``: η·k = c·ω, x_max = A); with ``fitted`` and a ``test`` the law
        was fitted on, its own identified c_e is used instead of the law.  Other forms are returned as they are.
        """
        if self.form == "feature":
            return Damping("viscous", {"c": self.feature_value(omega, A)})
        if self.form != "law":
            return self
        c = self.per_test[test] if fitted and test in self.per_test else self.ce(omega, A, ke)
        if self.rule == "viscous":
            return Damping("viscous", {"c": c})
        eta_k = max(c, 0.0) * omega
        return Damping("hysteretic", {"eta_k": eta_k, "x_max": max(A, 1e-12), "n": IWAN_N,
                                      "k_comp": eta_k * _iwan_in_phase(), "x_c": x0})

    def force(self, x: np.ndarray, xd: np.ndarray, periodic: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """Damping force [N] and dissipated-energy increments [N·mm] (viscous: c·ẋ²·Δt is left to the caller,
        returned as zeros) over x [mm], ẋ [mm/s]; a ``law`` must be resolved first (:meth:`resolve`)."""
        p = self.params
        z = np.zeros_like(np.asarray(x, float))
        if self.form == "none":
            return z, z
        if self.form == "viscous":
            return p.get("c", 0.0) * np.asarray(xd, float), z
        if self.form == "hysteretic":
            Fc, xs = iwan_elements(p)
            F, dE = ops.iwan(x, Fc, xs, periodic=periodic)
            return F - p.get("k_comp", 0.0) * (np.asarray(x, float) - p.get("x_c", 0.0)), dE
        if self.form == "dahl":
            return ops.dahl(x, p.get("F_h", 0.0), p.get("x_h", 1.0), periodic=periodic)
        if self.form == "coulomb":
            if p.get("x_s", 0.0) > 0:
                return ops.jenkins(x, p.get("F_c", 0.0), p["x_s"], periodic=periodic)
            return p.get("F_c", 0.0) * ops.coulomb_sign(xd, periodic), z
        raise ValueError("a damping law must be resolved for a record first (Damping.resolve)")

    def to_dict(self) -> dict[str, Any]:
        """TOML/JSON table of the damping (keys of the model file)."""
        d: dict[str, Any] = {"form": self.form, "params": dict(self.params)}
        if self.form == "law":
            d |= {"law": self.law, "coefficients": [float(c) for c in self.coefficients], "rule": self.rule,
                  "per_test": {str(k): float(v) for k, v in self.per_test.items()}}
            if self.k_e is not None:
                d["k_e"] = float(self.k_e)
        return d

    @classmethod
    def from_dict(cls, d: dict[str, Any], where: str = "damping") -> "Damping":
        """Inverse of :meth:`to_dict`; unknown keys are an error naming them."""
        known = {"form", "params", "law", "coefficients", "k_e", "rule", "per_test"}
        unknown = set(d) - known
        if unknown:
            raise ValueError(f"{where}: unknown key(s) {sorted(unknown)}; valid: {sorted(known)}")
        return cls(str(d.get("form", "none")), {k: float(v) for k, v in dict(d.get("params", {})).items()},
                   d.get("law"), [float(c) for c in d.get("coefficients", [])],
                   None if d.get("k_e") is None else float(d["k_e"]), str(d.get("rule", "viscous")),
                   {str(k): float(v) for k, v in dict(d.get("per_test", {})).items()})

