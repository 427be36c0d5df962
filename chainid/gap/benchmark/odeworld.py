"""``chainid benchmark-gap --generator ode``: a second simulated world, written apart from the project's simulator.

Why: the diagnosis is scored on data of the project's own simulator (:mod:`chainid.records.simulate`, the effect
operators of :mod:`chainid.model`).  This world shares only the chain spring with it: its effects are ODEs in time
integrated with LSODA (:mod:`.odedevice`), its excitations are other shapes (:mod:`.odeshapes`), a resonant device
is driven by a force and carries its inertia, and the logger adds lag, noise, quantisation and offsets
(:mod:`.odemeasure`).  Where the two worlds' scores disagree, the diagnosis is tuned to one of them.

A case is a dict (family, base, excitation, effects by name → relative level, outside mechanisms, covariate,
seed); :func:`build` draws everything else from the seed (:mod:`.odecases`) and returns the records, the held-out
ids and the truth ``{"base": …, "effects": {name: {param: value}}, "outside": …, "covariate": …}``.
:func:`run_case` diagnoses the records blind with the base a user would choose (the chain's
:class:`~chainid.model.base.ChainModel` for a chain, ``model=None`` — a linear spring — for other devices) and
scores the verdict (:mod:`.odescore`).  :func:`run_world` runs the families in parallel
(:func:`chainid.infra.parallel.run_cases`).

Units: mm, N, s, kg, Hz.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import replace
from typing import Any

import numpy as np

from chainid.gap.benchmark import odecases as oc
from chainid.gap.benchmark.odedevice import Device, run_displacement, run_force
from chainid.gap.benchmark.odemeasure import Logger, measure
from chainid.gap.benchmark.simtruth import interval_parts, trusted_index
from chainid.gap.benchmark.odescore import FAMILIES, score_row

__all__ = ["build", "run_case", "world_cases", "selected_world_cases", "run_world", "FAMILIES"]


#: how a case's dashpot varies over its records (``law_form`` of a case): ``linear`` in the record features, or
#: ``table1``, the shape of the paper's Table 1 (a power law, falling with the band centre, rising with the amplitude)
LAW_FORMS = ("linear", "table1")
#: Table 1's shape: c_e ∝ ω^(−p)·A^q, with p = 0.39 (log-log least squares over its tests 1–5, 5095.5 → 1964.3
#: N·s/mm for ω = 1 → 10 rad/s at A = 0.25 mm) and q = 0.24 (tests 6–9 and 3, 2614.1 → 3090.5 N·s/mm for A = 0.2 →
#: 0.4 mm at ω = 6 rad/s); a case draws each within these ranges, times its level
TABLE1_P, TABLE1_Q = (0.25, 0.55), (0.10, 0.35)


def _damping_per_record(c: float, spread: float, omegas: np.ndarray, amps: np.ndarray,
                        rng: np.random.Generator) -> tuple[np.ndarray, dict[str, float]]:
    """c_r = c + b_w·(ω_r − ω̄) + b_A·(A_r − Ā) [N·s/mm] with |c_r − c| <= spread·c (ω̄, Ā over the case)."""
    dw, dA = omegas - omegas.mean(), amps - amps.mean()
    share = float(rng.uniform(0.3, 0.7)) if np.ptp(omegas) > 0 and np.ptp(amps) > 0 else (
        1.0 if np.ptp(omegas) > 0 else 0.0)
    sw, sA = (1.0 if rng.random() < 0.5 else -1.0), (1.0 if rng.random() < 0.5 else -1.0)
    b_w = sw * share * spread * c / max(float(np.abs(dw).max()), 1e-300) if share > 0 else 0.0
    b_A = sA * (1 - share) * spread * c / max(float(np.abs(dA).max()), 1e-300) if share < 1 else 0.0
    return c + b_w * dw + b_A * dA, {"b_w": b_w, "b_A": b_A, "omega_mean": float(omegas.mean()),
                                     "A_mean": float(amps.mean()), "c": c, "form": "linear"}


def _damping_table1(c: float, level: float, omegas: np.ndarray, amps: np.ndarray,
                    rng: np.random.Generator) -> tuple[np.ndarray, dict[str, float]]:
    """c_r = c·(ω_r/ω̄)^(−p)·(A_r/Ā)^q [N·s/mm]: the paper's Table 1 shape (:data:`TABLE1_P`, :data:`TABLE1_Q`,
    each exponent times ``level``), curved in both features, so a law linear in them is only a local fit."""
    p = level * float(rng.uniform(*TABLE1_P))
    q = level * float(rng.uniform(*TABLE1_Q))
    w_m, A_m = float(np.exp(np.mean(np.log(omegas)))), float(np.exp(np.mean(np.log(amps))))
    c_r = c * (omegas / w_m) ** (-p) * (amps / A_m) ** q
    return c_r, {"p": p, "q": q, "omega_mean": w_m, "A_mean": A_m, "c": c, "form": "table1"}


def _covariate(case: dict[str, Any], nrec: int, effects: dict[str, dict[str, float]], rng: np.random.Generator
               ) -> tuple[np.ndarray | None, dict[str, Any] | None]:
    """Operating condition per record and the truth of the amplitude parameter's linear law."""
    cov = case.get("covariate")
    if not cov:
        return None, None
    levels = np.linspace(cov["lo"], cov["hi"], int(cov["levels"]))
    values = levels[np.arange(nrec) % levels.size]
    p = effects[cov["effect"]]
    p0 = p[cov["param"]]
    p1 = cov["slope_rel"] * p0 / max(cov["hi"], 1e-12)
    return values, {"name": cov["name"], "unit": cov["unit"], "effect": cov["effect"], "param": cov["param"],
                    "p0": p0, "p1": p1, "label": f"{cov['effect']}.{cov['param']}@{cov['name']}",
                    "values": values.tolist()}


def build(case: dict[str, Any], clean: bool = False) -> tuple[list[Any], list[str], dict[str, Any]]:
    """The records of a case, its held-out ids and its truth (see the module docstring); ``clean``: the logger
    adds no noise and no ADC steps (lag, offsets and drift stay; the truth still states the noise it would add)."""
    rng = np.random.default_rng(case["seed"])
    base = case["base"]
    b = oc.draw_base(base, rng)
    sc = oc.scales(b)
    plan = oc.draw_plan(base, b, case["excitation"], rng)
    shapes = [oc.make_shape(r, rng) for r in plan]
    effects = {n: oc.effect_params(n, lv, sc, rng, case.get("sign", 1.0)) for n, lv in case["effects"].items()}
    outside = {n: oc.outside_params(n, lv, sc, rng) for n, lv in case.get("outside", {}).items()}
    c = b["c"] if b["kind"] == "linear" else b["loss"] * sc["k"] / (2 * math.pi * 0.5 * (b["f_lo"] + b["f_hi"]))
    force = oc.DRIVE[base] == "force"
    xs = [r["mean"] + r["amp"] * s.y[s.record_index] for r, s in zip(plan, shapes)]
    omegas = np.array([2 * math.pi * s.f_centre for s in shapes])
    c_r, law = np.full(len(plan), c), None
    if "damping_law" in effects:
        if force:
            raise ValueError("damping_law is simulated on displacement-driven bases only (A_r is the drive's)")
        amps = np.array([0.5 * np.ptp(x) for x in xs])
        form = case.get("law_form", "linear")
        if form not in LAW_FORMS:
            raise ValueError(f"law_form = {form!r} is unknown; valid: {', '.join(LAW_FORMS)}")
        if form == "table1":  # a curved law: no linear coefficients to score, the truth states its exponents
            c_r, law = _damping_table1(c, float(case["effects"]["damping_law"]), omegas, amps, rng)
            effects["damping_law"] = {}
        else:
            c_r, law = _damping_per_record(c, effects["damping_law"]["spread"], omegas, amps, rng)
            effects["damping_law"] = {"b_w": law["b_w"], "b_A": law["b_A"]}
    cov_values, cov_truth = _covariate(case, len(plan), effects, rng)
    noise = float(rng.uniform(0.001, 0.005))
    T = np.array([r["n"] / r["fs"] for r in plan])
    starts = np.concatenate([[0.0], np.cumsum(1.1 * T)[:-1]])
    recs, meas = [], []
    noise_rng = np.random.default_rng([case["seed"], 1])  # its own stream: a clean build draws the same case
    for i, (r, s) in enumerate(zip(plan, shapes)):
        eff = {n: dict(p) for n, p in effects.items() if n not in ("sensor_delay", "damping_law")}
        if cov_values is not None:
            p = eff[cov_truth["effect"]]
            new = cov_truth["p0"] + cov_truth["p1"] * cov_values[i]
            if cov_truth["effect"] == "stribeck" and cov_truth["param"] == "F_c":
                p["F_s"] += new - p["F_c"]  # the amplitude F_s − F_c stays
            p[cov_truth["param"]] = new
        dev = _device(b, base, eff, outside, float(c_r[i]))
        hmax = max(1.0 / r["fs"], 1.0 / (8.0 * s.f_hi))
        if force:
            tr = run_force(dev, s.t, r["mean"] + r["amp"] * s.y, r["amp"] * s.yd, hmax)
        else:
            tr = run_displacement(dev, s.t, r["mean"] + r["amp"] * s.y, r["amp"] * s.yd, r["amp"] * s.ydd, hmax)
        Fr = float(np.ptp(tr.F[s.record_index]))
        log = Logger(tau=effects.get("sensor_delay", {}).get("tau", 0.0), sigma_F=noise * Fr,
                     sigma_x=float(rng.uniform(0.0, 5e-4)) * float(np.ptp(tr.x[s.record_index])),
                     q_F=1.5 * Fr / 4096 if rng.random() < 0.3 else 0.0,
                     offset_F=float(rng.uniform(-0.05, 0.05)) * sc["S"] if case.get("offsets") else 0.0,
                     drift=_drift(outside, starts[i], T.mean()))
        recs.append(measure(f"r{i + 1}", s, tr, replace(log, sigma_F=0.0, sigma_x=0.0, q_F=0.0) if clean else log,
                            noise_rng))
        meas.append({"kind": s.kind, "fs": s.fs, "n": s.n, "f_lo": s.f_lo, "f_hi": s.f_hi, "c": float(c_r[i]),
                     "sigma_F": log.sigma_F, "sigma_x": log.sigma_x, "q_F": log.q_F, "offset_F": log.offset_F,
                     "drift": list(log.drift), **{k: v for k, v in s.info.items() if k in (
                         "n_periods", "taper_s", "rest_s", "n_sweeps", "down", "log", "f")}})
    hold = _holdout(case, len(recs), cov_values, rng)
    truth = {"base": {"name": base, "drive": oc.DRIVE[base], **b, "c": c}, "effects": effects, "outside": outside,
             "covariate": cov_truth, "damping_law": law, "noise_fraction": noise, "records": meas}
    return recs, hold, truth


def _drift(outside: dict[str, Any], t_start: float, T_mean: float) -> tuple[float, float]:
    if "drift" not in outside:
        return 0.0, 0.0
    d1 = outside["drift"]["total"] / T_mean
    return d1 * t_start, d1


def _device(b: dict[str, Any], base: str, effects: dict[str, Any], outside: dict[str, Any], c: float) -> Device:
    eff = dict(effects)
    if b["kind"] == "chain":
        kw: dict[str, Any] = {}
        if "stiffness_level" in eff:
            kw["ea_scale"] = eff.pop("stiffness_level")["scale"]
        if "contact_law" in eff:
            p = eff.pop("contact_law")
            kw["hertz_scale"] = p["scale"]
            kw["contact_exponent"] = None if abs(p["beta"] - 2 / 3) < 1e-9 else p["beta"]
        if "slack" in eff:
            kw["slack"] = eff.pop("slack")["s"]
        return Device("chain", chain=oc.chain_spec(b), chain_kw=kw, c=c, effects=eff, outside=outside)
    return Device("linear", k=b["k"], x_ref=b["x_ref"], m=b["m"], c=c, effects=eff, outside=outside)


def _holdout(case: dict[str, Any], n: int, cov: np.ndarray | None, rng: np.random.Generator) -> list[str]:
    k = 1 if n <= 6 else (2 if n <= 8 else 3)
    if cov is not None:  # one record of a middle operating condition
        mid = np.argsort(np.abs(cov - np.median(cov)), kind="stable")[:k]
        return [f"r{i + 1}" for i in sorted(mid)]
    return [f"r{i + 1}" for i in sorted(rng.choice(n, size=k, replace=False))]


def _result_row(res: dict[str, Any]) -> dict[str, Any]:
    from chainid.gap.benchmark.openworldscore import open_world_row

    steps = res.get("steps") or []
    last = steps[-1] if steps else {}
    i = trusted_index(res)  # the verdict's chain: a step after the held-out minimum is not in it
    kept = steps[i] if i is not None else {}
    b = res["baseline"]
    return {"verdict": res["verdict"], "snr": b["excess_rms_N"] / max(b["noise_sigma_N"], 1e-300),
            "shrinkage": last.get("shrinkage") if len(steps) > 1 else (res.get("best") or {}).get("shrinkage"),
            "steps": [s["effect"] for s in steps[1:]], "params": kept.get("params") or {},
            "params_sd": kept.get("params_sd") or {}, "params_ci90": kept.get("params_ci90") or {},
            "params_ci90_parts": interval_parts(res, i) if i is not None else {},
            "resample_units": (res.get("stability") or {}).get("units"), "route": res.get("route", "harmonic"),
            "base_law": b.get("damping_law"),
            "excluded": [e["test"] for e in res.get("excluded", [])],
            "open_world": open_world_row(res)}


def run_case(case: dict[str, Any]) -> dict[str, Any]:
    """Build one case, diagnose it blind and score it; a crash is a row with verdict ``error: …``."""
    from chainid.gap.diagnose import diagnose
    from chainid.model.base import ChainModel

    t0 = time.perf_counter()
    try:
        recs, hold, truth = build(case)
        t_sim = time.perf_counter() - t0
        model = ChainModel(oc.chain_spec(truth["base"])) if truth["base"]["kind"] == "chain" else None
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res = diagnose(recs, hold, model, uncertainty=False, quiet=True, resamples=int(case.get("resamples", 0)),
                           seed=int(case.get("seed", 0)))
        row = {**case, **_result_row(res), "truth": truth, "holdout": hold, "sim_seconds": t_sim,
               "seconds": time.perf_counter() - t0 - t_sim}
    except Exception as exc:  # a crash is a miss to report, not the end of the run
        row = {**case, "verdict": f"error: {type(exc).__name__}: {exc}", "snr": float("nan"), "shrinkage": None,
               "steps": [], "params": {}, "params_sd": {}, "params_ci90": {}, "truth": None, "holdout": [],
               "open_world": {"missing_effect": False, "predictable_share": None},
               "sim_seconds": time.perf_counter() - t0, "seconds": 0.0}
    row["score"] = score_row(row)
    return row


def world_cases(small: bool = False, seed: int = 0) -> list[dict[str, Any]]:
    """The ODE world's cases (:func:`chainid.gap.benchmark.odefamilies.world_cases`)."""
    from chainid.gap.benchmark.odefamilies import world_cases as cases

    return cases(small, seed)


def selected_world_cases(small: bool = False, seed: int = 0, only: str | None = None) -> list[dict[str, Any]]:
    """The ODE world's cases (:func:`world_cases`) whose label contains ``only`` (None: all).

    Raises
    ------
    ValueError
        ``only`` matches no case label.
    """
    cases = [c for c in world_cases(small, seed) if only is None or only in c["label"]]
    if not cases:
        raise ValueError(f"--cases {only!r} matches no case label of the {'small ' if small else ''}ODE world "
                         f"(labels read family/base/excitation/effects@levels, e.g. 'single/damper/multisine/"
                         f"friction@1')")
    return cases


def run_world(small: bool = False, seed: int = 0, jobs: int | None = None, json_path: str | None = None,
              overwrite: bool = False, scheduler: str | None = None, progress: bool = True,
              resamples: int = 0, only: str | None = None) -> dict[str, Any]:
    """Run the ODE world's cases in parallel, print the rates per family, optionally write the JSON (atomically).

    Parameters
    ----------
    small : bool
        The small set (12 cases).
    seed : int
        First seed (>= 0).
    jobs : int, optional
        Worker processes (default: the machine's cores).
    json_path : str, optional
        Write the summary and every row here (checked before the run).
    overwrite : bool
        Replace an existing ``json_path``.
    scheduler : str, optional
        As for :func:`chainid.infra.parallel.run_cases` (None: a dask LocalCluster or a process pool).
    progress : bool
        Progress bar on stderr.
    resamples : int
        Resamples of every diagnosis (0: none; >= 20 gives each named parameter its percentile interval
        ``params_ci90``, whose coverage of the truth the summary reports per effect).
    only : str, optional
        Run only the cases whose label contains this text (ValueError when none does).

    Returns
    -------
    dict
        :func:`chainid.gap.benchmark.odescore.summarise` of the rows, with ``rows``, ``wall_seconds`` and
        ``generator`` = ``ode``.
    """
    from chainid.infra.fileio import check_output_file, write_json
    from chainid.infra.parallel import run_cases
    from chainid.gap.benchmark.odescore import format_table, summarise

    if json_path:
        check_output_file(json_path, force=overwrite, what="--json")
    cases = [c | {"resamples": int(resamples)} for c in selected_world_cases(small, seed, only)]
    t0 = time.perf_counter()
    rows = run_cases(run_case, cases, scheduler=scheduler, n_workers=jobs, progress=progress,
                     desc="benchmark-gap (ode)")
    s = summarise(rows)
    s.update({"generator": "ode", "seed": int(seed), "small": bool(small), "resamples": int(resamples),
              "wall_seconds": time.perf_counter() - t0,
              "rows": rows})
    print(format_table(s))
    if json_path:
        write_json(s, json_path, force=overwrite, what="--json")
    return s
