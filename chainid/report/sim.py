"""Part 4a of the gap report section: blind diagnosis of a built-in simulated test series on the report's chain
around the paper's operating point (x0 ≈ 2.2 mm, A 0.1–0.4 mm, ω 0.5–3 rad/s) with a hidden effect that is
withheld from the model (:data:`SIM_EFFECT`); three whole tests are held out (:data:`SIM_HOLDOUT`).

Units: x mm, F N, t s, ω rad/s, m kg, c_e N·s/mm.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from chainid.report.common import dump_json, md_table
from chainid.gap.core.summary import to_json
from chainid.report.diagnosis import MAX_COMBO, Progress, diagnosis_markdown, run_diagnosis, write_plots

#: Hidden effect of the built-in simulated series (withheld from the model): Coulomb friction 150 N.
SIM_EFFECT = "friction:F_c=150"
#: Gaussian noise on the simulated force [N] (standard deviation per sample).
SIM_NOISE_N = 20.0
#: Held-out tests of the simulated series (whole tests inside the plan's range).
SIM_HOLDOUT = ("5", "10", "11")
SIM_SEED = 1
SIM_CYCLES = 8
SIM_SAMPLES_PER_CYCLE = 128


# -- simulated series -------------------------------------------------------------

def simulated_plan() -> list[Any]:
    """The built-in test plan: 11 harmonic tests around the paper's operating point.

    A 3 × 3 grid ω ∈ {0.5, 1.5, 3.0} rad/s × A ∈ {0.1, 0.25, 0.4} mm at x0 = 2.2 mm,
    plus two off-grid tests (ω = 2.2 rad/s, x0 = 2.15 mm, A = 0.2 mm; ω = 1.0 rad/s,
    x0 = 2.3 mm, A = 0.3 mm), all inside the paper's tested 0.31–3.14 rad/s.

    Returns
    -------
    list of TestSpec
        Tests "1" … "11".
    """
    from chainid.records.simulate import grid_plan

    return grid_plan((0.5, 1.5, 3.0), (0.1, 0.25, 0.4), 2.2, extra=[(2.2, 2.15, 0.2), (1.0, 2.3, 0.3)])


def simulated_law() -> Any:
    """Damping law of the simulation: Eq. 21 refitted to Table 1 with ω in rad/s (:func:`chainid.damping.audit.eq28`).

    Returns
    -------
    PolynomialLaw
        c_e(ω [rad/s], A [mm]) [N·s/mm].
    """
    from chainid.damping import audit
    from chainid.model.laws import PolynomialLaw

    return PolynomialLaw(audit.eq28(audit.OMEGA_COLUMN_TO_RAD_S)["alpha"])


def simulated_records(model: Any, effect: str = SIM_EFFECT, noise_F: float = SIM_NOISE_N,
                      seed: int = SIM_SEED) -> tuple[list[Any], Any, Any]:
    """Simulate the built-in series with a hidden effect.

    Parameters
    ----------
    model : StiffnessModel
        Chain model (F_k [N], mass [kg]).
    effect : str
        Effect spec ``NAME[:p=v,...]`` (:func:`chainid.model.effects.parse_effect`).
    noise_F : float
        Force noise σ [N].
    seed : int
        Noise seed.

    Returns
    -------
    records, law, hook
        Records (t s, x mm, F N), the damping law used, and the effect hook
        (``hook.effect_name``, ``hook.effect_params``).
    """
    from chainid.records.simulate import simulate
    from chainid.model.effects import parse_effect

    law = simulated_law()
    hook = parse_effect(effect, model)
    recs = simulate(simulated_plan(), model, law, n_cycles=SIM_CYCLES, samples_per_cycle=SIM_SAMPLES_PER_CYCLE,
                    noise_F=noise_F, seed=seed, force_fn=hook)
    return recs, law, hook


def _recovery(res: dict[str, Any], hook: Any, model: Any, x0: float) -> dict[str, Any]:
    """True vs recovered parameters of the hidden effect, each with the diagnosis's jack-knife sd; ``sd`` None with
    ``sd_resolved`` False: the leave-one-test-out refits did not move it (no spread to quote)."""
    name = hook.effect_name
    true = {f"{name}.{k}": float(v) for k, v in hook.effect_params.items()}
    verdict = res["verdict"]
    best = res.get("best") or {}
    rec = best.get("params", {}) if name in verdict.split("+") else {}
    sd = best.get("params_sd", {}) or {}
    rows = []
    for k, v in true.items():
        rows.append({"param": k, "true": v, "recovered": rec.get(k), "sd": sd.get(k),
                     "sd_resolved": sd.get(k) is not None or k not in sd})
    out: dict[str, Any] = {"effect": name, "verdict": verdict, "matches": verdict == name,
                           "contains": name in verdict.split("+"), "params": rows}
    if name == "friction" and rec:
        Fk0 = float(np.asarray(model.force(np.array([x0])), dtype=float)[0])
        tot_true = true["friction.F_c"] + true["friction.mu"] * Fk0
        tot_rec = rec.get("friction.F_c", 0.0) + (rec.get("friction.mu") or 0.0) * Fk0
        out["friction_force_at_x0"] = {"x0_mm": x0, "F_k_N": Fk0, "true_N": tot_true, "recovered_N": tot_rec}
    return out


def simulated_section(folder: Path, model: Any, say: Progress) -> str:
    """Part 4a: blind diagnosis of the built-in simulated series with a hidden effect."""
    say(f"gap: simulated series with a hidden effect ({SIM_EFFECT}), blind diagnosis")
    recs, law, hook = simulated_records(model)
    res, secs = run_diagnosis(recs, SIM_HOLDOUT, model)
    figs = write_plots(res, folder, "gap_simulated")
    plan = simulated_plan()
    check = _recovery(res, hook, model, 2.2)
    ce = {p.test: float(law.predict(p.omega, p.A, p.x0)[0]) for p in plan}
    doc = to_json(res)
    doc["simulation"] = {
        "hidden_effect": SIM_EFFECT, "hidden_params": dict(hook.effect_params),
        "noise_F_sigma_N": SIM_NOISE_N, "seed": SIM_SEED, "n_cycles": SIM_CYCLES,
        "samples_per_cycle": SIM_SAMPLES_PER_CYCLE, "damping_law": "Eq. 21 refitted to Table 1, omega in rad/s",
        "damping_law_alpha": [float(a) for a in law.params], "max_combo": MAX_COMBO,
        "plan": [{"test": p.test, "omega_rad_s": p.omega, "x0_mm": p.x0, "A_mm": p.A, "c_e_N_s_per_mm": ce[p.test]}
                 for p in plan],
        "diagnosis_seconds": secs,
    }
    doc["check"] = check
    doc["figures"] = figs
    j = dump_json(folder, "gap_simulated.json", to_json(doc))
    ws = sorted({p.omega for p in plan})
    As = sorted({p.A for p in plan})
    head = [
        "### 4a. Blind diagnosis of a simulated series with a hidden effect\n",
        f"{len(plan)} harmonic tests simulated on this chain around the paper's operating point: x₀ = "
        f"{min(p.x0 for p in plan):g}–{max(p.x0 for p in plan):g} mm, A = {As[0]:g}–{As[-1]:g} mm, "
        f"ω = {ws[0]:g}–{ws[-1]:g} rad/s, {SIM_CYCLES} cycles of {SIM_SAMPLES_PER_CYCLE} samples, force noise "
        f"σ = {SIM_NOISE_N:g} N; damping c_e = {min(ce.values()):.0f}–{max(ce.values()):.0f} N·s/mm from Eq. 21 "
        f"refitted to Table 1 with ω in rad/s. **Hidden effect (withheld from the model): `{SIM_EFFECT}`.** "
        f"The diagnosis sees only the records, the chain model and the held-out ids "
        f"({', '.join(SIM_HOLDOUT)}); it took {secs:.1f} s (effects and pairs of effects).\n",
    ]
    tail = ["\n**Check against the hidden truth:** verdict "
            f"`{check['verdict']}` {'matches' if check['matches'] else ('contains' if check['contains'] else 'does NOT match')}"
            f" the hidden effect `{check['effect']}`.\n"]
    prow = [[r["param"], f"{r['true']:.4g}", "–" if r["recovered"] is None else f"{r['recovered']:.4g}",
             f"{r['sd']:.2g}" if r["sd"] is not None else ("–" if r["sd_resolved"] else "not resolved")]
            for r in check["params"]]
    tail.append(md_table(["parameter", "true", "recovered", "jackknife sd"], prow))
    ff = check.get("friction_force_at_x0")
    if ff:
        tail.append(f"\nThe fit shares the friction between F_c and μ·F_k; the total friction force at x₀ = "
                    f"{ff['x0_mm']:g} mm (F_k = {ff['F_k_N']:.0f} N) is {ff['recovered_N']:.1f} N recovered against "
                    f"{ff['true_N']:.1f} N true ({100 * (ff['recovered_N'] / ff['true_N'] - 1):+.1f} %).")
    return "\n".join(head) + "\n" + diagnosis_markdown(res, "figures/gap_simulated", j) + "\n".join(tail) + "\n"
