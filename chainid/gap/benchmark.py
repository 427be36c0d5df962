"""``chainid benchmark-gap``: blind diagnosis of simulated data with a withheld effect.

Grid: every library effect at three strengths, two noise levels, two chain
sizes and two test plans, plus a no-effect control and an out-of-library
effect (slow linear drift of the mean force).  The diagnosis sees only the
records and the held-out ids.  "Residual over noise" of a case is the
baseline's *diagnosed* systematic held-out residual over the noise σ (what
the effect leaves after the baseline absorbs what it can).
"""

from __future__ import annotations

import time
from dataclasses import replace
from multiprocessing import get_context
from typing import Any

import numpy as np

from .effects import EFFECT_NAMES, parse_effect

LABELS = ("none",) + EFFECT_NAMES + ("unexplained", "other")


def grid3x3_plan(prefix: str = "a") -> list[Any]:
    """The 11-test plan of the benchmark: ω ∈ {1, 2, 4} rad/s × A ∈ {0.1, 0.2, 0.3} mm at x0 = 2 mm,
    plus (ω, x0, A) = (3 rad/s, 2.2 mm, 0.15 mm) and (1.5 rad/s, 1.8 mm, 0.25 mm); ids ``prefix1`` … ``prefix11``."""
    from ..simulate import grid_plan

    return grid_plan((1.0, 2.0, 4.0), (0.1, 0.2, 0.3), 2.0, extra=[(3.0, 2.2, 0.15), (1.5, 1.8, 0.25)], prefix=prefix)


def _plans() -> dict[str, list[Any]]:
    from ..simulate import TestSpec

    a, b = grid3x3_plan("a"), []
    i = 0
    for w in (0.8, 1.6, 3.2, 6.4):
        for A, x0 in ((0.08, 1.6), (0.16, 2.0), (0.24, 2.4)):
            i += 1
            b.append(TestSpec(f"b{i}", w, x0, A))
    return {"grid3x3": a, "grid4x3": b}


def _chains() -> dict[str, Any]:
    from ..spec import default_chain

    c = default_chain()
    return {"14x50": c, "small": replace(c, d=10.0, pitch=35.0, width=12.0)}


def _spec(effect: str, level: float, S: float, k: float, Amin: float, wmax: float) -> str:
    if effect == "friction":
        return f"friction:F_c={0.1 * level * S:.6g}"
    if effect == "hysteresis":
        return f"hysteresis:F_h={0.1 * level * S:.6g},x_h={0.3 * Amin:.6g}"
    if effect == "backlash":
        return f"backlash:b={0.1 * level * Amin:.6g}"
    if effect == "slack":
        return f"slack:s={0.1 * level * Amin:.6g}"
    if effect == "machine_compliance":
        return f"machine_compliance:c={0.1 * level / k:.6g}"
    if effect == "contact_law":
        return f"contact_law:scale={1 + 0.3 * level:.6g}"
    if effect == "sensor_delay":
        return f"sensor_delay:tau={0.15 * level / wmax:.6g}"
    return f"damping_law:eta={0.1 * level:.6g}"


def run_case(case: dict[str, Any]) -> dict[str, Any]:
    """Simulate one case and diagnose it blind."""
    from ..identify import PolynomialLaw
    from ..models import ChainModel
    from ..simulate import simulate
    from .diagnose import diagnose

    chain = _chains()[case["chain"]]
    plan = _plans()[case["plan"]]
    model = ChainModel(chain)
    x0s = np.array([p.x0 for p in plan])
    As = np.array([p.A for p in plan])
    k = float(np.median(model.stiffness(x0s)))
    S = float(np.median(model.stiffness(x0s) * As))
    wmax = max(p.omega for p in plan)
    law = PolynomialLaw([0.0, 0.0, 0.0, 0.0, 0.02 * k / wmax])  # ~2 % loss at the top frequency
    hook = None
    truth = case["effect"]
    if truth in EFFECT_NAMES:
        hook = parse_effect(_spec(truth, case["level"], S, k, float(As.min()), wmax), model)
    elif truth == "drift":
        rate = 0.05 * case["level"] * S

        def hook(t, x, xd, xdd, F):  # noqa: ANN001
            return F + rate * t / t[-1]
    sigma = case["noise"] * S
    recs = simulate(plan, model, law, n_cycles=8, samples_per_cycle=256, noise_F=sigma, seed=case["seed"])
    if hook is not None:
        recs = simulate(plan, model, law, n_cycles=8, samples_per_cycle=256, noise_F=sigma, seed=case["seed"],
                        force_fn=hook)
    ids = [p.test for p in plan]
    hold = [ids[2], ids[len(ids) // 2], ids[-1]]
    t0 = time.time()
    res = diagnose(recs, hold, model, uncertainty=False)
    best = res.get("best") or {}
    b = res["baseline"]
    return {**case, "verdict": res["verdict"], "seconds": time.time() - t0,
            "snr": b["excess_rms_N"] / max(b["noise_sigma_N"], 1e-300),
            "shrinkage": best.get("shrinkage"), "best": best.get("effect"), "params": best.get("params")}


def grid(small: bool = False, seed: int = 0) -> list[dict[str, Any]]:
    cases = []
    effects = list(EFFECT_NAMES)
    levels = (0.3, 1.0, 3.0)
    noises = (0.01, 0.03)
    chains = ("14x50", "small")
    plans = ("grid3x3", "grid4x3")
    if small:
        levels, noises, chains, plans = (1.0,), (0.01,), ("14x50",), ("grid3x3",)
    s = seed
    for ch in chains:
        for pl in plans:
            for nz in noises:
                for e in effects + ["drift"]:
                    for lv in levels:
                        s += 1
                        cases.append({"effect": e, "level": lv, "noise": nz, "chain": ch, "plan": pl, "seed": s})
                for rep in range(2 if small else 3):
                    s += 1
                    cases.append({"effect": "none", "level": 0.0, "noise": nz, "chain": ch, "plan": pl, "seed": s})
    return cases


def summarise(rows: list[dict[str, Any]]) -> dict[str, Any]:
    truths = sorted({r["effect"] for r in rows}, key=lambda e: (e != "none", e))
    preds = list(LABELS)
    conf = {t: {p: 0 for p in preds} for t in truths}
    for r in rows:
        v = r["verdict"]
        conf[r["effect"]][v if v in preds else "other"] += 1
    strong = [r for r in rows if r["effect"] in EFFECT_NAMES and r["snr"] >= 3]
    right = [r for r in strong if r["verdict"] == r["effect"]]
    partial = [r for r in strong if r["effect"] in r["verdict"].split("+")]
    shr = [r["shrinkage"] for r in rows if r["effect"] in EFFECT_NAMES and r["effect"] in r["verdict"].split("+")
           and r["shrinkage"] is not None]
    ctrl = [r for r in rows if r["effect"] == "none"]
    drift = [r for r in rows if r["effect"] == "drift"]
    return {
        "n_cases": len(rows),
        "confusion": conf,
        "right_rate_snr3": len(right) / len(strong) if strong else None,
        "contains_rate_snr3": len(partial) / len(strong) if strong else None,
        "n_snr3": len(strong),
        "median_shrinkage_when_right": float(np.median(shr)) if shr else None,
        "control_none_rate": sum(r["verdict"] == "none" for r in ctrl) / len(ctrl) if ctrl else None,
        "false_alarm_rate": sum(r["verdict"] != "none" for r in ctrl) / len(ctrl) if ctrl else None,
        "drift_verdicts": {v: sum(r["verdict"] == v for r in drift) for v in sorted({r["verdict"] for r in drift})},
        "median_seconds": float(np.median([r["seconds"] for r in rows])),
        "rows": rows,
    }


def format_summary(s: dict[str, Any]) -> str:
    preds = [p for p in LABELS if any(s["confusion"][t][p] for t in s["confusion"])]
    w = max(len(p) for p in preds) + 1
    lines = ["confusion matrix (rows: true effect, columns: verdict)",
             " " * 20 + "".join(f"{p[:w - 1]:>{w}}" for p in preds)]
    for t, row in s["confusion"].items():
        lines.append(f"{t:<20}" + "".join(f"{row[p]:>{w}}" for p in preds))
    f = lambda v: "n/a" if v is None else f"{100 * v:.1f} %"  # noqa: E731
    lines += [
        f"right verdicts where residual >= 3x noise: {f(s['right_rate_snr3'])} of {s['n_snr3']} "
        f"(verdict contains the effect: {f(s['contains_rate_snr3'])})",
        f"median held-out shrinkage when right: {f(s['median_shrinkage_when_right'])}",
        f"control gives none: {f(s['control_none_rate'])}; false-alarm rate {f(s['false_alarm_rate'])}",
        f"out-of-library drift verdicts: {s['drift_verdicts']}",
        f"median diagnosis time {s['median_seconds']:.2f} s over {s['n_cases']} cases",
    ]
    return "\n".join(lines)


def _ignore_sigint() -> None:
    """Pool workers leave Ctrl-C to the parent (which stops the pool): one message, no worker tracebacks."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)


def run_benchmark(small: bool = False, json_path: str | None = None, overwrite: bool = False, seed: int = 0,
                  processes: int = 2) -> dict[str, Any]:
    """Run the grid, print the confusion matrix and summary, optionally write JSON."""
    if json_path:  # before the grid runs
        from ..fileio import check_output_file

        check_output_file(json_path, force=overwrite, what="--json")
    cases = grid(small, seed)
    if processes > 1:
        with get_context("fork").Pool(processes, initializer=_ignore_sigint) as pool:
            rows = pool.map(run_case, cases, chunksize=1)
    else:
        rows = [run_case(c) for c in cases]
    s = summarise(rows)
    print(format_summary(s))
    if json_path:
        from ..fileio import write_json  # strict JSON (null for NaN), temp file + rename

        write_json(s, json_path, force=overwrite, what="--json")
    return s
