"""``chainid benchmark-gap``: blind diagnosis of simulated data with withheld effects.

Case families (the diagnosis sees only the records, the nominal chain and the held-out ids):

* ``single``     — every library effect alone at three strengths, two noise levels, two chains, two plans;
* ``mismatch``   — the base model itself off: the links' linear stiffness EA × 0.7 … 1.4, or the Hertz
  contact compliance × 0.5 … 2;
* ``mismatch+``  — a base-model mismatch plus each library effect;
* ``pair``       — two library effects together;
* ``control``    — no effect at all;
* ``outside``    — effects outside the library: a slow linear drift and an exponential relaxation of the
  mean force within each test.

These are the ``harmonic`` excitation (steady harmonic test plans).  The same families on non-harmonic
excitations (band-limited random, sweep, start-up with load steps, earthquake-like) and the transfer
cases (fit harmonic, score random and back) are :mod:`chainid.gap.benchmark.nonharmonic`; ``excitations``
chooses which run, and each excitation is reported apart.

"Residual over noise" (snr) of a case is the baseline's systematic held-out residual over the noise σ.
Cases run in parallel through :func:`chainid.infra.parallel.run_cases` (dask LocalCluster by default, an existing
cluster by address, a process pool without dask).
"""

from __future__ import annotations

import time
from dataclasses import replace
from typing import Any

import numpy as np

from chainid.gap.benchmark.report import CANONICAL, canon, case_row, open_world_row  # noqa: F401  (part of the API)
from chainid.gap.benchmark.seeds import run_base
from chainid.gap.benchmark.chain import case_chain, on_chain, x_scale
from chainid.gap.benchmark.nonharmonic import effect_spec  # noqa: F401  (part of the benchmark API)
from chainid.gap.benchmark.simtruth import case_truth
from chainid.model.effects import EFFECT_NAMES, compose_hooks, parse_effect

#: the effects of the harmonic single-effect family, in the order their cases (and seeds) are drawn
GRID_EFFECTS = ("stiffness_level", "friction", "hysteresis", "contact_law", "slack", "backlash",
                "machine_compliance", "sensor_delay", "damping_law")
#: the second release's effects on the harmonic plans (a smaller grid: two strengths, one noise, one plan)
NEW_GRID_EFFECTS = ("stribeck", "bouc_wen", "deadband", "fixture_mass")

def grid3x3_plan(prefix: str = "a") -> list[Any]:
    """The 11-test plan of the benchmark: ω ∈ {1, 2, 4} rad/s × A ∈ {0.1, 0.2, 0.3} mm at x0 = 2 mm,
    plus (ω, x0, A) = (3 rad/s, 2.2 mm, 0.15 mm) and (1.5 rad/s, 1.8 mm, 0.25 mm); ids ``prefix1`` … ``prefix11``."""
    from chainid.records.simulate import grid_plan

    return grid_plan((1.0, 2.0, 4.0), (0.1, 0.2, 0.3), 2.0, extra=[(3.0, 2.2, 0.15), (1.5, 1.8, 0.25)], prefix=prefix)


def _plans() -> dict[str, list[Any]]:
    from chainid.records.simulate import TestSpec

    a, b = grid3x3_plan("a"), []
    i = 0
    for w in (0.8, 1.6, 3.2, 6.4):
        for A, x0 in ((0.08, 1.6), (0.16, 2.0), (0.24, 2.4)):
            i += 1
            b.append(TestSpec(f"b{i}", w, x0, A))
    return {"grid3x3": a, "grid4x3": b}


def _outside_hook(kind: str, level: float, S: float) -> Any:
    if kind == "drift":
        rate = 0.05 * level * S

        def hook(t, x, xd, xdd, F):  # noqa: ANN001
            return F + rate * t / t[-1]
    else:  # relaxation of the mean force within each test, time constant a third of the test
        dF = 0.1 * level * S

        def hook(t, x, xd, xdd, F):  # noqa: ANN001
            return F - dF * (1.0 - np.exp(-3.0 * t / t[-1]))
    return hook


def case_plan(case: dict[str, Any]) -> list[Any]:
    """The test plan of a harmonic case; on a user's chain every x0 and A × the case's ``x_scale`` (the same
    nominal stress as on the paper's chain, :mod:`chainid.gap.benchmark.chain`)."""
    s = x_scale(case)
    return [replace(p, x0=p.x0 * s, A=p.A * s) for p in _plans()[case["plan"]]]


def run_case(case: dict[str, Any]) -> dict[str, Any]:
    """Simulate one case and diagnose it blind; returns the case with the verdict and scores."""
    if case.get("excitation", "harmonic") != "harmonic":
        from chainid.gap.benchmark.nonharmonic import run_case_time, run_case_transfer

        return (run_case_transfer if case["excitation"] == "transfer" else run_case_time)(case)
    from chainid.model.laws import PolynomialLaw
    from chainid.model.base import ChainModel
    from chainid.records.simulate import simulate
    from chainid.gap.diagnose import diagnose

    chain = case_chain(case)
    plan = case_plan(case)
    nominal = ChainModel(chain)
    true = ChainModel(chain, ea_scale=case.get("ea_scale", 1.0), hertz_scale=case.get("hertz_scale", 1.0))
    x0s = np.array([p.x0 for p in plan])
    As = np.array([p.A for p in plan])
    k = float(np.median(nominal.stiffness(x0s)))
    S = float(np.median(nominal.stiffness(x0s) * As))
    wmax = max(p.omega for p in plan)
    law = PolynomialLaw([0.0, 0.0, 0.0, 0.0, 0.02 * k / wmax])  # ~2 % loss at the top frequency
    hooks, specs = [], []
    for eff, lv in zip(case["effects"], case["levels"]):
        if eff in EFFECT_NAMES:
            specs.append(effect_spec(eff, lv, S, k, float(As.min()), wmax, float(np.median(x0s))))
            hooks.append(parse_effect(specs[-1], true))
        else:
            hooks.append(_outside_hook(eff, lv, S))
    truth = case_truth(case, specs)
    sigma = case["noise"] * S
    recs = simulate(plan, true, law, n_cycles=8, samples_per_cycle=256, noise_F=sigma, seed=case["seed"],
                    force_fn=compose_hooks(hooks))
    ids = [p.test for p in plan]
    hold = [ids[2], ids[len(ids) // 2], ids[-1]]
    t0 = time.perf_counter()
    try:
        res = diagnose(recs, hold, nominal, uncertainty=False, quiet=True, resamples=int(case.get("resamples", 0)),
                       seed=int(case.get("seed", 0)))
    except Exception as exc:  # a crash is a miss to report, not the end of the run
        return {**case, "verdict": f"error: {type(exc).__name__}: {exc}", "seconds": time.perf_counter() - t0,
                "snr": float("inf"), "shrinkage": None, "steps": [], "params": None, "params_ci90": {},
                "true_params": truth, "stationary": None, "confounded": []}
    return case_row(case, res, time.perf_counter() - t0, truth)


#: every excitation of the benchmark: the harmonic plans, the non-harmonic families and the transfer cases
ALL_EXCITATIONS = ("harmonic", "random", "sweep", "startup", "quake", "transfer")


def grid(small: bool = False, seed: int = 0, excitations: Any = ALL_EXCITATIONS,
         chain: Any = None) -> list[dict[str, Any]]:
    """The benchmark cases (``small``: a subset for the tests) of the given excitations (see
    :data:`ALL_EXCITATIONS`); ``chain`` (a :class:`~chainid.ChainSpec`): every case on that chain, its
    displacements scaled to the same nominal stress (:mod:`chainid.gap.benchmark.chain`), instead of the
    built-in 14×50 and 10×35 chains."""
    excitations = tuple(excitations)
    bad = [e for e in excitations if e not in ALL_EXCITATIONS]
    if bad or not excitations:
        raise ValueError(f"--excitations {','.join(excitations)!r}: unknown {bad or 'empty'}; valid: "
                         f"{','.join(ALL_EXCITATIONS)}")
    from chainid.gap.benchmark.nonharmonic import time_grid

    cases = time_grid(seed, small, tuple(e for e in excitations if e != "harmonic"))
    if "harmonic" in excitations:
        cases = _harmonic_grid(small, seed) + cases
    return cases if chain is None else on_chain(cases, chain)


def _harmonic_grid(small: bool, seed: int) -> list[dict[str, Any]]:
    cases: list[dict[str, Any]] = []
    s = run_base(seed)

    def add(family: str, truth: list[str], effects: list[str], levels: list[float], noise: float, chain: str,
            plan: str, **kw: Any) -> None:
        nonlocal s
        s += 1
        cases.append({"excitation": "harmonic", "family": family, "truth": truth, "effects": effects, "levels": levels, "noise": noise,
                      "chain": chain, "plan": plan, "seed": s, **kw})

    singles = list(GRID_EFFECTS)
    levels, noises, chains, plans = (0.3, 1.0, 3.0), (0.01, 0.03), ("14x50", "small"), ("grid3x3", "grid4x3")
    if small:
        singles = ["friction", "stiffness_level"]
        levels, noises, chains, plans = (1.0,), (0.01,), ("14x50",), ("grid3x3",)
    for ch in chains:
        for pl in plans:
            for nz in noises:
                for e in singles:
                    for lv in levels:
                        add("single", [e], [e], [lv], nz, ch, pl)
                for rep in range(1 if small else 3):
                    add("control", [], [], [], nz, ch, pl)
    # base-model mismatch alone, and with each library effect (the effect at its typical strength)
    mism = [("stiffness_level", {"ea_scale": v}) for v in (0.7, 0.85, 1.2, 1.4)] + \
           [("contact_law", {"hertz_scale": v}) for v in (0.5, 2.0)]
    others = ["friction", "hysteresis", "backlash", "slack", "sensor_delay", "damping_law"]
    if small:
        mism, others = [("stiffness_level", {"ea_scale": 0.8})], ["friction"]
    for ch in chains:
        for nz in noises:
            for m, kw in mism:
                add("mismatch", [m], [], [], nz, ch, "grid3x3", **kw)
            for i, e in enumerate(others):
                m, kw = mism[i % len(mism)]
                add("mismatch+", [m, e], [e], [1.0], nz, ch, "grid3x3", **kw)
    pairs = [("friction", "sensor_delay"), ("backlash", "damping_law"), ("hysteresis", "slack"),
             ("friction", "slack"), ("backlash", "sensor_delay"), ("hysteresis", "damping_law")]
    if small:
        pairs = [("friction", "sensor_delay")]
    for ch in chains:
        for nz in noises:
            for a, b in pairs:
                add("pair", [a, b], [a, b], [1.0, 1.0], nz, ch, "grid3x3")
    outside = [] if small else [("drift", lv) for lv in (1.0, 3.0)] + [("relaxation", lv) for lv in (1.0, 3.0)]
    for ch in chains:
        for nz in noises:
            for kind, lv in outside:
                add("outside", [kind], [kind], [lv], nz, ch, "grid3x3")
    # the second release's effects on the chain (appended: every earlier case keeps its seed)
    for ch in ([] if small else chains):
        for e in NEW_GRID_EFFECTS:
            for lv in (1.0, 3.0):
                add("single", [e], [e], [lv], 0.01, ch, "grid3x3")
    return cases


def case_label(case: dict[str, Any]) -> str:
    """A sim case's label, ``excitation/family/effects`` (effects joined by ``+``, ``none`` for a control), e.g.
    ``harmonic/pair/friction+sensor_delay``: what ``benchmark-gap --cases`` matches."""
    return f"{case['excitation']}/{case['family']}/{'+'.join(case.get('effects') or []) or 'none'}"


def selected_cases(small: bool = False, seed: int = 0, excitations: Any = ALL_EXCITATIONS, chain: Any = None,
                   only: str | None = None) -> list[dict[str, Any]]:
    """The grid's cases (:func:`grid`), each with its ``label`` (:func:`case_label`), and only those whose label
    contains ``only`` (None: all).

    Raises
    ------
    ValueError
        ``only`` matches no case label.
    """
    cases = [c | {"label": case_label(c)} for c in grid(small, seed, excitations, chain)]
    cases = [c for c in cases if only is None or only in c["label"]]
    if not cases:
        raise ValueError(f"--cases {only!r} matches no case label of the {'small ' if small else ''}sim grid (labels "
                         f"read excitation/family/effects, e.g. 'random/pair/friction+sensor_delay')")
    return cases


def run_benchmark(small: bool = False, json_path: str | None = None, overwrite: bool = False, seed: int = 0,
                  scheduler: str | None = None, n_workers: int | None = None,
                  progress: bool = True, excitations: Any = ALL_EXCITATIONS, chain: Any = None,
                  resamples: int = 0, only: str | None = None) -> dict[str, Any]:
    """Run the grid in parallel, print the summary, optionally write JSON (atomically).

    Parameters
    ----------
    small : run the small subset
    json_path : write the summary and every row here
    overwrite : replace an existing ``json_path``
    seed : first noise seed
    scheduler : None/"local" (dask LocalCluster or a process pool), "processes", "serial", or a dask address
    n_workers : worker processes (default: the machine's cores)
    progress : progress bar on stderr
    excitations : which excitations run (:data:`ALL_EXCITATIONS`; default all)
    chain : a :class:`~chainid.ChainSpec` to run every case on (default: the built-in 14×50 and 10×35 chains);
        its displacements are scaled to the same nominal stress (:mod:`chainid.gap.benchmark.chain`)
    resamples : resamples of every diagnosis (0: none): each step's stability and percentile intervals
    only : run only the cases whose :func:`case_label` contains this text (ValueError when none does)
    """
    from chainid.infra.parallel import run_cases
    from chainid.infra.fileio import check_output_file, write_json
    from chainid.gap.benchmark.report import format_summary, summarise

    if json_path:  # check the target before the long work
        check_output_file(json_path, force=overwrite, what="--json")
    cases = [c | {"resamples": int(resamples)} for c in selected_cases(small, seed, excitations, chain, only)]
    t0 = time.perf_counter()
    rows = run_cases(run_case, cases, scheduler=scheduler, n_workers=n_workers, progress=progress,
                     desc="benchmark-gap")
    s = summarise(rows)
    s["wall_seconds"] = time.perf_counter() - t0
    if chain is not None:
        from chainid.gap.benchmark.chain import length_scale

        s["chain"] = {**chain.to_dict(), "x_scale": length_scale(chain)}
        print(f"chain: d = {chain.d:g} mm, pitch {chain.pitch:g} mm, n = {chain.n}, {chain.family or 'no family'}, grade "
              f"{chain.grade or 'none'}; displacements x {s['chain']['x_scale']:.4g} (the 14x50 chain's nominal stress)")
    print(format_summary(s))
    if json_path:  # strict JSON (null for NaN), temp file + rename
        write_json(s, json_path, force=overwrite, what="--json")
    return s
