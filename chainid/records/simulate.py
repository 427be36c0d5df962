"""Test-series simulator: test plan → records in the input format.

Each test is a displacement-controlled harmonic test (paper Eq. 18, 25)::

    x(t) = ramp_rate * t                             0 <= t <= t0 = x0 / ramp_rate
    x(t) = x0 + A e(t) sin(omega (t - t0))           t > t0

(e(t) = 1, or a linear taper in and out over ``taper_cycles`` cycles), and the
force is the model of Eq. 1::

    F_model = m xddot + F_k(x) + c_e(omega, A, x0) xdot

with F_k and m from a :class:`~chainid.model.base.StiffnessModel` and c_e from a
damping law (or a constant).  The force is built by :func:`model_force`, then
passed through an optional hook ``force_fn(t, x, xdot, xddot, F_model) -> F``
so that unmodelled effects can be added (friction, backlash, delay, …),
then Gaussian noise is added to x and F (seeded).

Units: t s, x mm, F N, omega rad/s, m kg.
"""
from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Sequence

import numpy as np

from chainid.model.laws import DampingLaw
from chainid.model.predict import inertia_force_N
from chainid.records.files import Record

__all__ = ["TestSpec", "ForceHook", "PAPER_RAMP_RATE", "OMEGA_COLUMN_TO_RAD_S", "paper_plan", "read_plan",
           "write_plan", "model_force", "simulate_test", "simulate", "DEFAULT_MAX_MEMORY", "n_samples",
           "estimate_memory", "simulate_model"]

#: Ramp rate of the paper's Eq. 25 [mm/s].
PAPER_RAMP_RATE = 0.08973

#: Conversion of Table 1's "omega" column to rad/s: omega = (pi/10) * column.
#: Evidence: Eq. 25/27 give test 3 (column 6) as 1.884 rad/s, and c_e = F_ac/(omega A)
#: holds for tests 2–9 only with this factor (see chainid.damping.audit, finding a).
OMEGA_COLUMN_TO_RAD_S = math.pi / 10.0

#: Default ceiling of :func:`simulate`'s memory estimate [bytes]: 2 GiB (``chainid simulate --max-memory`` in GiB).
DEFAULT_MAX_MEMORY = 2 * 1024**3

#: Bytes per sample while one test is built (float64 temporaries of :func:`simulate_test`, measured with
#: tracemalloc and rounded up) and bytes per sample kept afterwards (t, x, F).
PEAK_BYTES_PER_SAMPLE = 200
KEPT_BYTES_PER_SAMPLE = 24

#: ``force_fn(t, x, xdot, xddot, F_model) -> F``: s, mm, mm/s, mm/s², N -> N.
ForceHook = Callable[[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray], np.ndarray]


@dataclass(frozen=True)
class TestSpec:
    """One planned test: x = x0 + A sin(omega t).

    Attributes
    ----------
    test : str
        Test id.
    omega : float
        Angular frequency [rad/s], > 0.
    x0 : float
        Mean elongation [mm], > 0.
    A : float
        Amplitude [mm], 0 < A.
    """

    __test__ = False  # not a pytest test class

    test: str
    omega: float
    x0: float
    A: float

    def __post_init__(self) -> None:
        for name, v, ok, rng in (
            ("omega", self.omega, self.omega > 0, "> 0 rad/s"),
            ("x0", self.x0, self.x0 > 0, "> 0 mm"),
            ("A", self.A, self.A > 0, "> 0 mm"),
        ):
            if not (math.isfinite(v) and ok):
                raise ValueError(f"test {self.test!r}: {name} = {v!r} is invalid: valid range {rng}")


def paper_plan() -> list[TestSpec]:
    """The paper's 9 tests (Table 1) with omega converted to rad/s.

    omega [rad/s] = (pi/10) x the table's "omega" column (test 3: 1.885 rad/s,
    the paper's 1.884 of Eq. 25); x0 and A [mm] as printed.

    Returns
    -------
    list of TestSpec
        Tests "1" … "9".
    """
    from chainid.records.table1 import load_table1

    tb = load_table1()
    return [
        TestSpec(str(n), float(w) * OMEGA_COLUMN_TO_RAD_S, float(x0), float(a))
        for n, w, x0, a in zip(tb["test"], tb["omega_col"], tb["x0"], tb["A"])
    ]


def grid_plan(
    omegas: Sequence[float],
    amplitudes: Sequence[float],
    x0: float,
    extra: Sequence[tuple[float, float, float]] = (),
    prefix: str = "",
) -> list[TestSpec]:
    """A test plan: the grid ω × A at one mean elongation, then extra off-grid tests.

    Parameters
    ----------
    omegas : sequence of float
        Angular frequencies [rad/s] (outer loop).
    amplitudes : sequence of float
        Amplitudes A [mm] (inner loop).
    x0 : float
        Mean elongation of the grid tests [mm].
    extra : sequence of (omega, x0, A)
        Further tests [rad/s, mm, mm], appended in order.
    prefix : str
        Test ids are ``prefix + "1"``, ``prefix + "2"``, … in plan order.

    Returns
    -------
    list of TestSpec
    """
    specs = [(w, x0, A) for w in omegas for A in amplitudes] + [tuple(e) for e in extra]
    return [TestSpec(f"{prefix}{i}", float(w), float(xm), float(A)) for i, (w, xm, A) in enumerate(specs, start=1)]


#: Most tests one simulated series holds (a rig's test series has tens to hundreds; each test is a record of
#: thousands of samples): a larger plan is refused before any work, naming the limit
MAX_PLAN_TESTS = 10_000


def _too_many(n: int, where: str) -> ValueError:
    """The error for a plan of ``n`` tests, above the bound of one series."""
    return ValueError(f"{where}: the plan has {n} tests: valid range <= {MAX_PLAN_TESTS} tests in one series; split "
                      "the plan into several series")


def read_plan(path: str | Path) -> list[TestSpec]:
    """Read a plan CSV ``test,omega,x0,A`` (omega rad/s, x0 mm, A mm).

    Raises
    ------
    ValueError
        Missing columns, non-numeric value (with line number), a repeated test id, values out of range, or
        more than :data:`MAX_PLAN_TESTS` tests (refused as soon as the reading passes the limit).
    """
    p = Path(path)
    if not p.is_file():
        raise ValueError(f"plan file {str(p)!r} does not exist")
    out = []
    ids: set[str] = set()
    with p.open(newline="") as fh:
        reader = csv.DictReader(ln for ln in fh if not ln.lstrip().startswith("#"))
        cols = [c.strip() for c in (reader.fieldnames or [])]
        missing = [c for c in ("test", "omega", "x0", "A") if c not in cols]
        if missing:
            raise ValueError(f"{p}: missing column(s) {missing}; required test,omega,x0,A (rad/s, mm, mm)")
        for i, row in enumerate(reader, start=2):
            row = {k.strip(): (v or "").strip() for k, v in row.items() if k is not None}
            vals = {}
            for c in ("omega", "x0", "A"):
                try:
                    vals[c] = float(row[c])
                except ValueError:
                    raise ValueError(f"{p}, row {i}: test {row['test']!r}: {c} = {row[c]!r} is not a number") from None
            if row["test"] in ids:
                raise ValueError(f"{p}, row {i}: test id {row['test']!r} is repeated; test ids must be unique")
            if len(out) >= MAX_PLAN_TESTS:
                raise _too_many(sum(1 for _ in reader) + len(out) + 1, str(p))
            ids.add(row["test"])
            out.append(TestSpec(row["test"], **vals))
    if not out:
        raise ValueError(f"{p}: plan has no tests")
    return out


def write_plan(path: str | Path, plan: Sequence[TestSpec], overwrite: bool = False) -> Path:
    """Write a plan CSV ``test,omega,x0,A`` (rad/s, mm, mm); never overwrites unless asked."""
    from chainid.infra.fileio import atomic_open

    p = Path(path)
    with atomic_open(p, "w", force=overwrite, what="plan", newline="") as fh:
        fh.write("test,omega,x0,A\n")
        for s in plan:
            fh.write(f"{s.test},{s.omega:.10g},{s.x0:.10g},{s.A:.10g}\n")
    return p


def _damping(law_or_ce: DampingLaw | float, spec: TestSpec) -> float:
    """c_e [N·s/mm] of the law at the test's (omega, A, x0), or the constant; ValueError unless finite."""
    w, x0, A = spec.omega, spec.x0, spec.A
    c_e = float(law_or_ce.predict(w, A, x0)[0] if isinstance(law_or_ce, DampingLaw) else law_or_ce)
    if not math.isfinite(c_e):
        raise ValueError(f"test {spec.test!r}: the damping law gives c_e = {c_e!r} N·s/mm at omega = {w:g} rad/s, "
                         f"A = {A:g} mm, x0 = {x0:g} mm: valid range finite (check the law parameters)")
    return c_e


def model_force(
    x: np.ndarray, xdot: np.ndarray, xddot: np.ndarray, model: Any, c_e: float, mass_kg: float | None = None
) -> np.ndarray:
    """Eq. 1: F = m xddot + F_k(x) + c_e xdot [N].

    Parameters
    ----------
    x, xdot, xddot : ndarray
        [mm], [mm/s], [mm/s²].
    model : StiffnessModel
        F_k(x) [N], mass_kg [kg].
    c_e : float
        Damping [N·s/mm].
    mass_kg : float, optional
        Default model.mass_kg.
    """
    m = float(model.mass_kg if mass_kg is None else mass_kg)
    return inertia_force_N(m, xddot) + np.asarray(model.force(x), dtype=float) + c_e * xdot


def _envelope(tau: np.ndarray, T: float, n_cycles: float, taper_cycles: float) -> tuple[np.ndarray, np.ndarray]:
    """Amplitude envelope e(tau) and de/dtau for a linear taper in and out."""
    if taper_cycles <= 0:
        return np.ones_like(tau), np.zeros_like(tau)
    Tt = taper_cycles * T
    Ttot = n_cycles * T
    up = np.clip(tau / Tt, 0, 1)
    down = np.clip((Ttot - tau) / Tt, 0, 1)
    e = np.minimum(up, down)
    de = np.where((tau < Tt) & (up <= down), 1.0 / Tt, 0.0) - np.where((Ttot - tau < Tt) & (down < up), 1.0 / Tt, 0.0)
    return e, de


def _planned_motion(spec: TestSpec, n_cycles: float, samples_per_cycle: int, ramp_rate: float | None,
                    taper_cycles: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Planned motion at dt = T / samples_per_cycle (ramp, tapered oscillation): t [s], x [mm], ẋ [mm/s], ẍ [mm/s²]."""
    w, x0, A = spec.omega, spec.x0, spec.A
    T = 2 * math.pi / w
    dt = T / samples_per_cycle
    t0 = x0 / ramp_rate if ramp_rate is not None else 0.0
    n = int(round((t0 + n_cycles * T) / dt))
    t = np.arange(n) * dt
    tau = t - t0
    e, de = _envelope(tau, T, n_cycles, taper_cycles)
    s, c = np.sin(w * tau), np.cos(w * tau)
    osc = tau > 0
    x = np.where(osc, x0 + A * e * s, (ramp_rate or 0.0) * t)
    xdot = np.where(osc, A * (e * w * c + de * s), (ramp_rate or 0.0))
    xddot = np.where(osc, A * (-e * w * w * s + 2 * de * w * c), 0.0)
    if ramp_rate is None:
        x = np.where(osc, x, x0)
    return t, x, xdot, xddot


def _check_force(spec: TestSpec, model: Any, t: np.ndarray, x: np.ndarray, F: np.ndarray,
                 allow_compression: bool | None) -> None:
    """ValueError where the noise-free force F [N] (at t [s], x [mm]) is not finite, or < 0 where a chain is slack."""
    bad = ~np.isfinite(F)
    if bad.any():
        i = int(np.argmax(bad))
        raise ValueError(f"test {spec.test!r}: the simulated force is {float(F[i])!r} N at t = {t[i]:.6g} s "
                         f"(x = {x[i]:.6g} mm): valid range finite (check the law parameters and the effect)")
    if allow_compression is None:
        allow_compression = not _is_chain(model)
    if not allow_compression and F.min() < 0:
        # a taut chain's force can dip below zero through its damping and inertia (the spring stays in tension);
        # where the chain is slack (F_k = 0) nothing is transmitted, so a force there is the model's artefact
        slack = (F < 0) & (np.asarray(model.force(x), dtype=float) <= 0)
        if slack.any():
            i = int(np.argmin(np.where(slack, F, np.inf)))
            raise ValueError(f"test {spec.test!r}: the force goes compressive where the chain is slack (F = "
                             f"{F[i]:.6g} N at x = {x[i]:.6g} mm, F_k = 0; x0 = {spec.x0:g} mm, A = {spec.A:g} mm): a "
                             f"slack chain transmits nothing, valid range A < x0 (or a linear model, --model linear)")


def simulate_test(spec: TestSpec, model: Any, law_or_ce: DampingLaw | float, *, n_cycles: float = 6,
                  samples_per_cycle: int = 200, ramp_rate: float | None = None, taper_cycles: float = 0.0,
                  noise_x: float = 0.0, noise_F: float = 0.0, rng: np.random.Generator | int | None = None,
                  force_fn: ForceHook | None = None, mass_kg: float | None = None,
                  allow_compression: bool | None = None) -> Record:
    """Simulate one harmonic test.

    Parameters
    ----------
    spec : TestSpec
        omega [rad/s], x0 [mm], A [mm].
    model : StiffnessModel
        F_k(x) [N] and mass [kg].
    law_or_ce : DampingLaw or float
        Damping law evaluated at (omega, A, x0) or constant c_e [N·s/mm].
    n_cycles : float
        Oscillation cycles after the ramp (default 6), > 0.
    samples_per_cycle : int
        Sampling: dt = 2 pi / (omega * samples_per_cycle) [s] (default 200), >= 16.
    ramp_rate : float, optional
        Ramp from x = 0 to x0 at this rate [mm/s] (paper Eq. 25: 0.08973); None: no ramp.
    taper_cycles : float
        Linear amplitude taper in and out over this many cycles (default 0).
    noise_x, noise_F : float
        Standard deviations of Gaussian noise on x [mm] and F [N].
    rng : Generator or int or None
        Random generator or seed.
    force_fn : callable, optional
        Hook ``force_fn(t, x, xdot, xddot, F_model) -> F`` applied to the noise-free
        force (unmodelled effects).
    mass_kg : float, optional
        Default model.mass_kg; >= 0 kg.
    allow_compression : bool, optional
        Accept a noise-free force below 0 N where the chain is slack (F_k(x) = 0: its damper and inertia would
        push through a chain that transmits nothing).  Default: False for a chain model
        (:class:`~chainid.model.base.ChainModel`), True otherwise.  A taut chain's force may dip below zero
        through its damping (the spring force stays positive): always accepted.

    Returns
    -------
    Record
        Noisy t [s], x [mm], F [N].

    Raises
    ------
    ValueError
        An option out of range (naming it, its value and the valid range), a
        non-finite force, or a compressive force where a chain is slack.
    """
    _check_options(n_cycles, samples_per_cycle, ramp_rate, taper_cycles, noise_x, noise_F, mass_kg)
    gen = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)
    t, x, xdot, xddot = _planned_motion(spec, n_cycles, samples_per_cycle, ramp_rate, taper_cycles)
    c_e = _damping(law_or_ce, spec)
    F = model_force(x, xdot, xddot, model, c_e, mass_kg)
    if force_fn is not None:
        F = np.asarray(force_fn(t, x, xdot, xddot, F), dtype=float)
        if F.shape != t.shape:
            raise ValueError(f"force_fn returned shape {F.shape}; expected {t.shape}")
    _check_force(spec, model, t, x, F, allow_compression)
    xm = x + (gen.normal(0.0, noise_x, t.size) if noise_x > 0 else 0.0)
    Fm = F + (gen.normal(0.0, noise_F, t.size) if noise_F > 0 else 0.0)
    return Record(spec.test, t, xm, Fm)


def simulate(
    plan: Sequence[TestSpec],
    model: Any,
    law_or_ce: DampingLaw | float,
    *,
    seed: int | None = 0,
    max_memory: float | None = DEFAULT_MAX_MEMORY,
    **kwargs: Any,
) -> list[Record]:
    """Simulate a test series; see :func:`simulate_test` for the keyword arguments.

    Parameters
    ----------
    plan : sequence of TestSpec
    model : StiffnessModel
    law_or_ce : DampingLaw or float
        [N·s/mm].
    seed : int or None
        Seed of the noise generator (one generator for the whole series).
    max_memory : float or None
        Refuse a series whose estimated memory (:func:`estimate_memory`) exceeds
        this many bytes (default :data:`DEFAULT_MAX_MEMORY`, 2 GiB); None: no limit.

    Returns
    -------
    list of Record

    Raises
    ------
    ValueError
        Repeated test ids, more than :data:`MAX_PLAN_TESTS` tests, an estimate beyond ``max_memory``, or an
        invalid option (see :func:`simulate_test`); raised before anything large is allocated.
    """
    plan = list(plan)
    if len(plan) > MAX_PLAN_TESTS:
        raise _too_many(len(plan), "plan")
    seen: set[str] = set()
    for sp in plan:
        if sp.test in seen:
            raise ValueError(f"plan: test id {sp.test!r} is repeated; test ids must be unique")
        seen.add(sp.test)
    opts = {k: kwargs[k] for k in ("n_cycles", "samples_per_cycle", "ramp_rate") if k in kwargs}
    _check_options(opts.get("n_cycles", 6), opts.get("samples_per_cycle", 200), opts.get("ramp_rate"),
                   kwargs.get("taper_cycles", 0.0), kwargs.get("noise_x", 0.0), kwargs.get("noise_F", 0.0),
                   kwargs.get("mass_kg"))
    if max_memory is not None:
        if not (isinstance(max_memory, (int, float)) and math.isfinite(max_memory) and max_memory > 0):
            raise ValueError(f"max_memory = {max_memory!r} bytes is invalid: valid range > 0 (or None)")
        need = estimate_memory(plan, **opts)
        if need > max_memory:
            big = max(plan, key=lambda sp: n_samples(sp, **opts))
            raise ValueError(
                f"the simulation would need about {need / 1024**3:.3g} GiB ({sum(n_samples(sp, **opts) for sp in plan):.4g} "
                f"samples; largest: test {big.test!r}, omega = {big.omega:g} rad/s, {n_samples(big, **opts):.4g} "
                f"samples), over the limit of {max_memory / 1024**3:.3g} GiB: valid range <= the limit; "
                f"use fewer --cycles/--samples-per-cycle, a faster --ramp-rate, or raise --max-memory")
    rng = np.random.default_rng(seed)
    return [simulate_test(s, model, law_or_ce, rng=rng, **kwargs) for s in plan]


def _check_options(n_cycles: Any, samples_per_cycle: Any, ramp_rate: Any, taper_cycles: Any, noise_x: Any,
                   noise_F: Any, mass_kg: Any) -> None:
    """Range checks of the simulation options (ValueError naming option, value and valid range)."""

    def num(v: Any) -> bool:
        return isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, (bool, np.bool_)) \
            and math.isfinite(float(v))

    if not (num(n_cycles) and n_cycles > 0):
        raise ValueError(f"n_cycles = {n_cycles!r} is invalid: valid range > 0 (finite)")
    if not (num(samples_per_cycle) and float(samples_per_cycle).is_integer() and samples_per_cycle >= 16):
        raise ValueError(f"samples_per_cycle = {samples_per_cycle!r} is invalid: valid range integer >= 16")
    if ramp_rate is not None and not (num(ramp_rate) and ramp_rate > 0):
        raise ValueError(f"ramp_rate = {ramp_rate!r} mm/s is invalid: valid range > 0 (or None for no ramp)")
    if not (num(taper_cycles) and 0 <= taper_cycles <= n_cycles / 2):
        raise ValueError(f"taper_cycles = {taper_cycles!r} is invalid: valid range 0 to n_cycles/2 = {n_cycles / 2:g}")
    for name, v, unit in (("noise_x", noise_x, "mm"), ("noise_F", noise_F, "N")):
        if not (num(v) and v >= 0):
            raise ValueError(f"{name} = {v!r} {unit} is invalid: valid range >= 0 (finite)")
    if mass_kg is not None and not (num(mass_kg) and mass_kg >= 0):
        raise ValueError(f"mass_kg = {mass_kg!r} kg is invalid: valid range >= 0 (finite)")


def _is_chain(model: Any) -> bool:
    """Whether ``model`` is a chain (its force is tension only)."""
    from chainid.model.base import ChainModel

    return isinstance(model, ChainModel)


def n_samples(spec: TestSpec, n_cycles: float = 6, samples_per_cycle: int = 200,
              ramp_rate: float | None = None) -> float:
    """Number of samples :func:`simulate_test` will allocate for ``spec`` (a float: may be huge or inf).

    n = (t0 + n_cycles T) / dt with T = 2 pi / omega [s], dt = T / samples_per_cycle, t0 = x0 / ramp_rate [s].
    """
    T = 2 * math.pi / spec.omega
    t0 = spec.x0 / ramp_rate if ramp_rate is not None else 0.0
    with np.errstate(over="ignore"):
        n = (t0 + n_cycles * T) / (T / samples_per_cycle)
    return float(n) if math.isfinite(n) else math.inf


def estimate_memory(plan: Sequence[TestSpec], n_cycles: float = 6, samples_per_cycle: int = 200,
                    ramp_rate: float | None = None) -> float:
    """Estimated peak memory [bytes] of :func:`simulate` for ``plan``.

    Every test's samples are kept (:data:`KEPT_BYTES_PER_SAMPLE` each) and the
    largest test needs :data:`PEAK_BYTES_PER_SAMPLE` per sample while it is built.
    """
    ns = [n_samples(sp, n_cycles, samples_per_cycle, ramp_rate) for sp in plan]
    if not ns:
        return 0.0
    return sum(ns) * KEPT_BYTES_PER_SAMPLE + max(ns) * PEAK_BYTES_PER_SAMPLE


def simulate_model(plan: Sequence[TestSpec], model: Any, *, seed: int | None = 0,
                   max_memory: float | None = DEFAULT_MAX_MEMORY, **kwargs: Any) -> list[Record]:
    """Records of a test plan from an augmented model (``chainid simulate --model M.toml``).

    ``model`` is a :class:`chainid.augmented.AugmentedModel`: its force F(t) = model.force(t, x) (exact ẋ, ẍ
    of the planned motion; memory operators from their initial state at t = 0; a damping law resolved at
    each record's dominant ω and A) replaces Eq. 1; noise and the other options as :func:`simulate`.

    Raises
    ------
    ValueError
        The model's damping is a negative dashpot at a planned test's ω [rad/s], A [mm], x0 [mm]
        (:func:`chainid.model.passivity.check_passive`: such records would come from an active device).
    """
    from chainid.model.passivity import OperatingPoint, check_passive

    check_passive(model, [OperatingPoint(s.test, s.omega, s.A, s.x0, s.test) for s in plan], what="the model",
                  hint="the planned tests are its operating points")

    def hook(t: np.ndarray, x: np.ndarray, xd: np.ndarray, xdd: np.ndarray, F: np.ndarray) -> np.ndarray:
        return model.force(t, x, xd=xd, xdd=xdd)

    return simulate(plan, model.base, 0.0, seed=seed, max_memory=max_memory, force_fn=hook, mass_kg=model.mass,
                    **kwargs)
