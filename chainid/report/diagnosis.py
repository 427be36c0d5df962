"""Shared parts of the gap report section (step 4 of ``chainid report``): run a diagnosis, write its figures, and
render one diagnosis result as Markdown (used by the simulated series, :mod:`chainid.report.sim`, and the
user's records, :mod:`chainid.report.data`).

Units: x mm, F N, t s, ω rad/s, m kg, c_e N·s/mm, W N·mm.
"""

from __future__ import annotations

import time
import warnings
from pathlib import Path
from typing import Any, Callable, Sequence

from chainid.gap.core.verdict import none_text
from chainid.report.common import md_table

Progress = Callable[[str], None]

#: Largest effect combination tried by the diagnosis in the report (measured: ~1 s for 11 tests).
MAX_COMBO = 2
#: Minimum number of tests for the diagnosis (6 training + 1 held out).
MIN_TESTS = 7


# -- Markdown of a diagnosis ------------------------------------------------------

def _fmt_params(params: dict[str, Any], sd: dict[str, Any] | None = None) -> str:
    """``k = v ± sd`` per parameter; where ``sd`` holds None for it (the refits did not move it,
    :func:`chainid.gap.core.candidate.jackknife_sd`): "(at bound)" for a 0, else "(sd not resolved)"."""
    sd = sd or {}
    out = []
    for k, v in params.items():
        if k.startswith("law.") or v is None:
            continue
        s = f"{k} = {v:.4g}"
        if sd.get(k) is not None:
            s += f" ± {sd[k]:.2g}"
        elif k in sd:  # no refit moved it: on a bound where it is 0 (as the terminal summary says), else unresolved
            s += " (at bound)" if v == 0 else " (sd not resolved)"
        out.append(s)
    return ", ".join(out) or "–"


def _fmt_num(v: float | None, fmt: str = ".4g") -> str:
    return "–" if v is None else format(v, fmt)


def _extrapolation_notes(res: dict[str, Any]) -> list[str]:
    """Held-out tests outside the training range of ω or A (the damping law c_e(ω, A) extrapolates there)."""
    tr = [t for t in res["tests"] if t["split"] == "train"]
    notes = []
    for t in res["tests"]:
        if t["split"] == "train":
            continue
        out = []
        for key, lab, unit in (("omega", "ω", "rad/s"), ("A", "A", "mm")):  # the inputs of the damping law
            lo, hi = min(u[key] for u in tr), max(u[key] for u in tr)
            tol = 0.05 * hi  # measured ω and A scatter by a few per cent
            if t[key] < lo - tol or t[key] > hi + tol:
                out.append(f"{lab} = {t[key]:.3g} {unit} outside the training {lo:.3g}–{hi:.3g} {unit}")
        if out:
            notes.append(f"held-out test {t['test']} is an extrapolation ({'; '.join(out)}): its baseline error "
                         "includes the damping law's extrapolation error")
    return notes


def diagnosis_markdown(res: dict[str, Any], fig_rel: str, json_rel: str, n_where: int = 6,
                        n_rank: int = 6) -> str:
    """Markdown of one diagnosis result: baseline, where, ranking, verdict, per-test table, figures."""
    b = res["baseline"]
    lines = [
        f"**Baseline** ({b['model']}, damping law Eq. 21 fitted on the training tests): NRMSE train "
        f"{b['nrmse_train']:.4g}, held-out {b['nrmse_holdout']:.4g}; systematic held-out residual "
        f"{b['excess_rms_N']:.4g} N against a noise σ of {b['noise_sigma_N']:.4g} N "
        f"({b['db_over_noise']:.1f} dB over the noise floor of the cycle means). Held out: "
        f"{', '.join(res['holdout'])}.\n",
        "**Where the model misses** (largest first):\n",
    ]
    lines += [f"- {f['finding']}" for f in res["where"][:n_where]]
    lines += [f"- {s}" for s in _extrapolation_notes(res)]
    lines.append("\n**Which effect** (each fitted on the training tests only, scored leave-one-test-out; "
                 "shrinkage = reduction of the held-out NRMSE; \"c_e law\" when the effect is best paired with "
                 "another damping law than Eq. 21):\n")
    rows = []
    for c in res["ranking"][:n_rank]:
        ps = _fmt_params(c["params"])
        law = c.get("damping_law")
        if law and law != "polynomial":  # the damping-law effect replaces Eq. 21 by another form
            ps = (f"c_e law {law}; " + ps) if ps != "–" else f"c_e law {law}"
        rows.append([c["effect"], ps, _fmt_num(c["nrmse_loto"]), _fmt_num(c["nrmse_holdout"]),
                     "–" if c["shrinkage"] is None else f"{100 * c['shrinkage']:.1f} %"])
    lines.append(md_table(["effect", "fitted parameters", "LOTO NRMSE", "held-out NRMSE", "shrinkage"], rows))
    for cf in res.get("confounded", []):
        lines.append(f"\nConfounded: {cf['pair'][0]} and {cf['pair'][1]} fit equally well; to separate them: "
                     f"{cf['separate_by']}.")
    v, best = res["verdict"], res.get("best")
    if v == "none":
        lines.append(f"\n**Verdict: none** — {none_text(res)}.")
    elif v == "unexplained":
        lines.append(f"\n**Verdict: unexplained** — no library effect halves the held-out gap (best "
                     f"{best['effect'] if best else '–'}: shrinkage "
                     f"{100 * (best['shrinkage'] if best else 0.0):.0f} %, held-out NRMSE left "
                     f"{res['left_nrmse_holdout']:.4g}).")
    else:
        lines.append(f"\n**Verdict: {v}** ({_fmt_params(best['params'], best.get('params_sd'))}) — held-out NRMSE "
                     f"{b['nrmse_holdout']:.4g} → {best['nrmse_holdout']:.4g} (shrinkage "
                     f"{100 * best['shrinkage']:.0f} %).")
    if res.get("interpretation"):
        lines.append(f"Meaning: {res['interpretation']}.")
    for w in res.get("warnings", []):
        lines.append(f"\n> Warning: {w}")
    lines.append("\nPer test (NRMSE of the cycle-mean force, baseline → with the verdict's effect):\n")
    trows = []
    for t in res["tests"]:
        after = t.get("nrmse_after")
        trows.append([t["test"], t["split"], f"{t['omega']:.3g}", f"{t['x0']:.3g}", f"{t['A']:.3g}",
                      f"{t['nrmse_before']:.3g}", "–" if after is None else f"{after:.3g}"])
    lines.append(md_table(["test", "split", "ω [rad/s]", "x₀ [mm]", "A [mm]", "NRMSE baseline", "NRMSE after"],
                           trows))
    lines.append(f"\nJSON: `{json_rel}`.\n")
    lines.append(f"![held-out loops]({fig_rel}/loops.png)\n\n![residual vs phase]({fig_rel}/residual_phase.png)\n\n"
                 f"![residual surface]({fig_rel}/residual_surface.png)\n\n![NRMSE before/after]({fig_rel}/heatmap.png)\n")
    return "\n".join(lines)


def run_diagnosis(records: Sequence[Any], holdout: Sequence[str], model: Any | None,
                   max_combo: int = MAX_COMBO) -> tuple[dict[str, Any], float]:
    from chainid.gap.diagnose import diagnose

    t0 = time.perf_counter()
    with warnings.catch_warnings():  # the warnings are kept in res["warnings"] and shown in the report
        warnings.simplefilter("ignore", UserWarning)
        res = diagnose(records, list(holdout), model, max_combo=max_combo)
    return res, time.perf_counter() - t0


def write_plots(res: dict[str, Any], folder: Path, sub: str) -> list[str]:
    from chainid.gap.plots import make_plots

    paths = make_plots(res, folder / "figures" / sub)
    return [f"figures/{sub}/{p.name}" for p in paths]
