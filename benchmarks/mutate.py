"""Mutation run: do the tests fail on realistic single-line bugs?

Each mutation is (id, file, exact original text, replacement, pytest selection).  Mutations are applied one
at a time to a temporary COPY of the repository (the working tree is never touched); the selected tests run
there with a timeout.  Outcomes:

* ``killed``   – the selected tests failed (or errored / timed out) on the mutant: good;
* ``survived`` – they passed on the mutant: a test is missing or too weak;
* ``stale``    – the original text is not in the file (any more): the list needs updating after a refactor.

The kill percentage is killed / (killed + survived); stale mutations are reported, not counted.

Usage (from the repository root)::

    python benchmarks/mutate.py              # run them all (~10-20 min on 2 cores)
    python benchmarks/mutate.py --list       # list mutations and whether their text is still found
    python benchmarks/mutate.py --only K1,E2 # run some
    python benchmarks/mutate.py --baseline   # first check the selected tests pass on the unmutated copy
    python benchmarks/mutate.py --json out.json

The copy is placed in a temporary folder whose sibling ``shared`` links to the repository's ``../shared`` (the
real-data tests look there), with its own NUMBA_CACHE_DIR.
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


@dataclass(frozen=True)
class Mutation:
    id: str
    file: str  # relative to the repository root
    old: str  # exact original text (must occur exactly once... the first occurrence is replaced)
    new: str
    tests: tuple[str, ...]  # pytest arguments (node ids, files, -k expressions)
    what: str


def M(id: str, file: str, old: str, new: str, tests: str | tuple[str, ...], what: str) -> Mutation:
    return Mutation(id, file, old, new, (tests,) if isinstance(tests, str) else tuple(tests), what)


T_KER = "tests/model/test_kernels.py"
T_GEN = "tests/derive/test_generated.py"
T_ID = "tests/damping/test_identify.py"
T_AUD = "tests/damping/test_audit.py"
T_GAP = "tests/gap/harmonic/test_harmonic_diagnosis.py"
T_EFF = "tests/model/test_effects.py"
T_DER = "tests/derive/test_derive.py"

MUTATIONS: list[Mutation] = [
    # -- kernels / spec -------------------------------------------------------------------------------------------
    M("K1", "chainid/model/kernels.py", "m = chain.mass_kg if mass_kg is None else float(mass_kg)", "m = chain.mass_kg",
      (f"{T_KER}::test_damping_residual_explicit_mass", f"{T_KER}::test_damping_residual_units"),
      "damping_residual ignores an explicit mass_kg"),
    M("K2", "chainid/model/kernels.py", "if np.any(arr < 0):", "if np.any(arr <= 0):",
      (f"{T_KER}::test_displacement_of_zero_force_is_zero", f"{T_KER}::test_domain_guards"),
      "displacement(0) raises"),
    M("K3", "chainid/model/kernels.py", "        return float(out.reshape(()))\n", "        return out.reshape(())\n",
      f"{T_KER}::test_shapes_preserved", "a scalar in gives a 0-d array out"),
    M("K4", "chainid/model/kernels.py", "c_lin > 0 and c_hertz >= 0", "c_lin > 0 and c_hertz > 0",
      f"{T_KER}::test_single_link_has_no_contact_and_constant_stiffness", "a single link (no contact) refused"),
    M("K5", "chainid/chain/spec.py", "return self.mass_per_m * self.length_mm * 1e-3", "return self.mass_per_m * self.length_mm",
      (f"{T_KER}::test_damping_residual_explicit_mass", f"{T_KER}::test_damping_residual_units"),
      "chain mass in g instead of kg"),
    M("K6", "chainid/model/kernels.py", 'if mod.CONTACT == "inner" and not chain.width > chain.d:',
      'if mod.CONTACT == "inner" and not chain.width >= chain.d:',
      f"{T_KER}::test_inner_bend_needs_width_above_d", "inner-bend guard lets width = d through (contact radius R - d/2 = d/2... degenerate)"),
    # -- generated / derive (the numerical core) ------------------------------------------------------------------
    M("N1", "generated/stiffness_paper.py", "return ", "return 1.0000001*",
      (f"{T_KER}::test_coefficients_match_independent_closed_forms", f"{T_GEN}::test_generated_is_fresh"),
      "a generated kernel edited by hand"),
    M("N2", "derive/section.py", "return sp.pi * d**2 / 4", "return sp.pi * d**2 / 2", (f"{T_GEN}::test_generated_is_fresh",),
      "section area wrong in the derivation (generated/ no longer matches it)"),
    # -- chainid/cli/main.py ---------------------------------------------------------------------------------------------------
    M("C1", "chainid/cli/parser.py", "            return 1\n", "            return 0\n",
      f"{T_GEN}::test_cli_check_exit_codes_on_fresh_and_stale_copy", "generate --check returns 0 on a stale tree"),
    M("C2", "chainid/cli/parser.py", '"c_hertz_mm_per_N23": c_h', '"c_hertz_mm_per_N": c_h',
      f"{T_KER}::test_cli_stiffness_json", "renamed key in stiffness --json"),
    M("C3", "chainid/cli/parser.py", '"k_e_N_per_mm": float(c)', '"k_N_per_mm": float(c)',
      f"{T_KER}::test_cli_stiffness_json", "renamed point key in stiffness --json"),
    M("C4", "chainid/cli/parser.py", "xs += [float(v) for v in np.atleast_1d(kernels.displacement(np.asarray(args.F, dtype=float), chain, args.variant))]",
      "xs += [float(v) for v in np.atleast_1d(kernels.displacement(np.asarray(args.F, dtype=float), chain))]",
      f"{T_KER}::test_cli_stiffness_json", "stiffness --F ignores --variant"),
    # -- chainid/cli/identify.py ------------------------------------------------------------------------------------------
    M("I1", "chainid/cli/identify.py", 'out["ranking"] = ', 'out["laws"] = ',
      f"{T_AUD}::test_cli_simulate_then_identify", "renamed key in identify --json (ranking)"),
    M("I2", "chainid/cli/identify.py", '"model": {"name": getattr(model, "name", None), "mass_kg": results[0].mass_kg},',
      '"model": {"name": getattr(model, "name", None), "mass": results[0].mass_kg},',
      f"{T_AUD}::test_cli_simulate_then_identify", "renamed model key in identify --json"),
    # -- chainid/damping/identify.py ----------------------------------------------------------------------------------------------
    M("I3", "chainid/damping/identify.py", "Fs.append(r.F[mwin] - inertia_force_N(mass_kg, est.xddot(r.t[mwin])))",
      "Fs.append(r.F[mwin])", f"{T_ID}::test_linear_spring_fit_removes_inertia",
      "linear-spring fit in identify keeps the inertia"),
    M("I4", "chainid/model/predict.py", "return np.multiply(m_kg, xddot_mm_s2) * 1e-3", "return np.multiply(m_kg, xddot_mm_s2)",
      (f"{T_ID}::test_inertia_force_units", f"{T_ID}::test_mass_term_units"), "inertia in kg·mm/s² not N"),
    M("I5", "chainid/damping/identify.py", "c_e = F_ac / (est.omega * est.A)", "c_e = F_ac / est.omega",
      (T_ID, "-k", "ce_exact"), "Eq. 27 without A"),
    M("I6", "chainid/model/laws.py", "dof = M - p", "dof = M",
      (f"{T_ID}::test_fit_law_stats_against_brute_force", f"{T_AUD}::test_eq28_standard_errors_textbook"),
      "standard errors with the wrong degrees of freedom"),
    M("I7", "chainid/model/laws.py", "return (4.0 / (math.pi * omega * A))[:, None]", "return (4.0 / (omega * A))[:, None]",
      f"{T_ID}::test_law_predictions", "Coulomb law without pi"),
    M("I8", "chainid/damping/identify.py", "mass = float(model.mass_kg if mass_kg is None else mass_kg)", "mass = float(model.mass_kg)",
      f"{T_ID}::test_mass_term_units", "identify ignores an explicit mass"),
    # -- chainid/damping/audit.py -------------------------------------------------------------------------------------------------
    M("A1", "chainid/damping/audit.py", "OMEGA_COLUMN_TO_RAD_S = math.pi / 10.0", "OMEGA_COLUMN_TO_RAD_S = math.pi / 5.0",
      (T_AUD, "-k", "finding"), "Table 1 column converted with the wrong factor"),
    M("A2", "chainid/damping/audit.py", "implied_omega = F_ac / (c_e * A)", "implied_omega = F_ac / c_e",
      f"{T_AUD}::test_finding_a_omega_unit", "implied omega without A"),
    M("A3", "chainid/damping/audit.py", 'kdyn = EQ26["FA"] / EQ27["A"]', 'kdyn = EQ26["FA"] / (2 * EQ27["A"])',
      (T_AUD, "-k", "finding_c"), "Eq. 26 dynamic stiffness from the peak-to-peak amplitude (ratio 5.1, not 10.2)"),
    M("A4", "chainid/damping/audit.py", "f29 = factor[1:]", "f29 = factor",
      f"{T_AUD}::test_finding_a_omega_unit", "test 1 included in the omega-factor mean"),
    # -- gap: forward / effects / problem / laws----------------------------------------------------------------------
    M("D1", "chainid/gap/core/selection.py", "return excess < NONE_FRACTION * sigma or ratio",
      "return excess < NONE_FRACTION * sigma and ratio",
      f"{T_GAP}::test_sub_noise_effect_gives_none", "the none verdict's `or` turned into `and`"),
    M("D2", "chainid/gap/core/selection.py", "NONE_FRACTION = 0.5", "NONE_FRACTION = 5.0",
      f"{T_GAP}::test_small_effect_above_half_the_noise_is_named", "noise threshold 10x too high"),
    M("E1", "chainid/model/effects.py", "((-5.0 * x_scale, 5.0 * x_scale),)", "((0.0, 5.0 * x_scale),)",
      f"{T_GAP}::test_negative_slack_recovered", "slack bound forbids negative offsets"),
    M("E2", "chainid/model/effects.py", '4.0 * p.get("F_f", 0.0) / (math.pi * omega * A)', '4.0 * p.get("F_f", 0.0) / (omega * A)',
      f"{T_EFF}::test_damping_law_effect_hook_by_hand", "Coulomb-equivalent term without pi (simulation)"),
    M("E3", "chainid/model/effects.py", "(1e-3 * x_scale, 10 * x_scale)", "(0.12 * x_scale, 10 * x_scale)",
      (T_GAP, "-k", "effect_recovered and hysteresis"), "hysteresis travel pinned at its lower bound"),
    M("E4", "chainid/model/effects.py", 'play_operator(x, 0.5 * p.get("b", 0.0))', 'play_operator(x, p.get("b", 0.0))',
      (T_GAP, "-k", "effect_recovered and backlash"), "backlash b used as the half width"),
    M("S1", "chainid/gap/harmonic/problem.py", "(v >= 1 - 1e-6 or (v <= 1e-6 and a != 0.0))", "(v >= 1 - 1e-6 or v <= 1e-6)",
      (T_GAP, "-k", "effect_recovered and friction"), "an absent effect part (zero lower bound) flagged at_bound"),
    M("S2", "chainid/gap/harmonic/problem.py", "        tr, ho = self.train, self.hold\n", "        tr, ho = self.data, self.hold\n",
      f"{T_GAP}::test_baseline_law_fitted_on_training_tests_only", "leakage: damping law fitted on held-out tests too"),
    M("S3", "chainid/gap/harmonic/problem.py", '"nrmse_holdout": nrmse(ho, c_hold),',
      '"nrmse_holdout": nrmse(ho, [c_e[d.test] for d in ho]),',
      f"{T_GAP}::test_baseline_law_fitted_on_training_tests_only", "leakage: held-out tests scored with their own c_e"),
    M("S4", "chainid/gap/harmonic/law_choice.py", '"coulomb": 4.0 / (math.pi * w * A)', '"coulomb": 4.0 / (w * A)',
      f"{T_GAP}::test_coulomb_equivalent_damping_recovered", "Coulomb-equivalent law term without pi (fit)"),
    M("S5", "chainid/gap/harmonic/problem.py", 'cand.shrinkage = 1.0 - ev["nrmse_holdout"] / base_hold',
      'cand.shrinkage = 1.0 - ev["nrmse_loto"] / base_hold',
      f"{T_GAP}::test_cli_json_contract", "shrinkage from the training LOTO error instead of held-out"),
    M("S6", "chainid/gap/harmonic/problem.py", "x, xd, xdd = d.xfun(t - tau)", "x, xd, xdd = d.xfun(t + tau)",
      f"{T_GAP}::test_damping_law_and_delay_recovered", "sensor delay with the wrong sign"),
    # -- simulate / records ---------------------------------------------------------------------------------------
    M("R1", "chainid/records/validate.py", "if not allow_compression and np.any(rec.F < 0):",
      "if not allow_compression and np.any(rec.F < -1e9):",
      f"{T_AUD}::test_cli_identify_linear_model_allows_compression", "compressive chain records accepted silently"),
    M("A5", "chainid/damping/audit.py", "w1 = w_col[0] * OMEGA_COLUMN_TO_RAD_S", "w1 = w_col[0]",
      f"{T_AUD}::test_finding_b_test1_factor_20", "test 1's omega left in the column unit"),
    M("R3", "chainid/records/simulate.py", "return inertia_force_N(m, xddot) + np.asarray(model.force(x), dtype=float) + c_e * xdot",
      "return np.asarray(model.force(x), dtype=float) + c_e * xdot",
      f"{T_ID}::test_mass_term_units", "simulated records without the inertia term"),
    M("I9", "chainid/model/laws.py", 'rows.sort(key=lambda r: (r["loo_rmse"], r["n_params"]))',
      'rows.sort(key=lambda r: (r["rmse"], r["n_params"]))',
      (f"{T_ID}::test_rank_laws_prefers_true_law",
       f"{T_AUD}::test_cli_simulate_then_identify"),
      "laws ranked by in-sample RMSE instead of leave-one-out"),
    M("I10", "chainid/damping/identify.py", "W = loop_energy(xs, Fs) / win.n_cycles", "W = loop_energy(xs, Fs)",
      (T_ID, "-k", "ce_exact or loop_shape"), "loop energy summed over the cycles, not per cycle"),
    M("D3", "chainid/gap/core/verdict.py", "NONSTAT_FRACTION = 0.25", "NONSTAT_FRACTION = 25.0",
      f"{T_GAP}::test_out_of_library_drift_not_misnamed", "a drifting record given a library name"),
    M("D4", "chainid/gap/core/selection.py", "    return st[\"delta_loto\"] > Z * st[\"se_jackknife\"] and st",
      "    return st[\"delta_loto\"] > -1e9 * st[\"se_jackknife\"] and st",
      ("tests/gap/harmonic/test_compound_causes.py", "tests/gap/core/test_selection.py::test_step_rule_by_hand", "-k",
       "step_rule or mismatch"),
      "a step accepted without significance over the tests"),
    M("R2", "chainid/report/eq26.py", "k_in = FA * math.cos(phi) / A", "k_in = FA / A",
      "tests/report/test_report_gap.py::test_eq26_numbers", "Eq. 26 in-phase stiffness without cos(phi)"),
]


def _copy_repo(dst: Path) -> None:
    ignore = shutil.ignore_patterns(".git", "__pycache__", ".pytest_cache", "*.egg-info", ".hypothesis", "build")
    shutil.copytree(REPO, dst, ignore=ignore, symlinks=True)


def status(mut: Mutation, root: Path = REPO) -> str:
    p = root / mut.file
    if not p.is_file():
        return "stale"
    return "ok" if mut.old in p.read_text(encoding="utf-8") else "stale"


def run_tests(copy: Path, tests: tuple[str, ...], timeout: float, cache: Path) -> tuple[str, float, str]:
    """Run pytest in the copy; ('pass' | 'fail' | 'timeout', seconds, last output line)."""
    env = {**os.environ, "PYTHONPATH": str(copy), "NUMBA_CACHE_DIR": str(cache), "PYTHONDONTWRITEBYTECODE": "1"}
    cmd = [sys.executable, "-m", "pytest", "-x", "-q", "-n", "0", "-p", "no:cacheprovider", "--no-header", *tests]
    t0 = time.perf_counter()
    try:
        out = subprocess.run(cmd, cwd=copy, env=env, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return "timeout", time.perf_counter() - t0, ""
    lines = [ln for ln in out.stdout.splitlines() if ln.strip()]
    last = lines[-1] if lines else (out.stderr.strip().splitlines() or [""])[-1]
    failed = [ln for ln in lines if ln.startswith(("FAILED ", "ERROR "))]
    if failed:  # which test caught it, and why (pytest's short summary, -ra)
        last = f"{last}; {failed[0][:300]}"
    if out.returncode == 5:  # no tests collected: the selection is stale
        return "nocollect", time.perf_counter() - t0, str(last)
    return ("pass" if out.returncode == 0 else "fail"), time.perf_counter() - t0, str(last)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--list", action="store_true", help="list the mutations and whether their text is found")
    ap.add_argument("--only", help="comma-separated mutation ids")
    ap.add_argument("--baseline", action="store_true", help="check every selection passes on the unmutated copy first")
    ap.add_argument("--timeout", type=float, default=300.0, help="seconds per mutation (a timeout counts as killed)")
    ap.add_argument("--json", metavar="FILE", help="write the results as JSON")
    args = ap.parse_args(argv)

    muts = MUTATIONS
    if args.only:
        want = [s.strip() for s in args.only.split(",") if s.strip()]
        unknown = sorted(set(want) - {m.id for m in MUTATIONS})
        if unknown:
            print(f"mutate: unknown id(s) {unknown}", file=sys.stderr)
            return 2
        muts = [m for m in MUTATIONS if m.id in want]
    if args.list:
        for m in muts:
            print(f"{m.id:4} {status(m):6} {m.file:32} {m.what}")
        return 0
    if args.json and Path(args.json).exists():
        print(f"mutate: {args.json} exists; not overwriting", file=sys.stderr)
        return 2

    results = []
    with tempfile.TemporaryDirectory(prefix="chainid_mutate_") as tmp:
        tmp = Path(tmp)
        copy = tmp / "repo"
        _copy_repo(copy)
        shared = REPO.parent / "shared"
        if shared.is_dir():
            (tmp / "shared").symlink_to(shared)
        cache = tmp / "numba_cache"
        if args.baseline:
            sels = sorted({m.tests for m in muts if status(m, copy) == "ok"})
            for sel in sels:
                res, secs, last = run_tests(copy, sel, args.timeout, cache)
                print(f"baseline {res:8} {secs:6.1f}s  {' '.join(sel)}  {last}", flush=True)
                if res != "pass":
                    print("mutate: a selection fails on the unmutated copy; fix that first", file=sys.stderr)
                    return 1
        for m in muts:
            p = copy / m.file
            if status(m, copy) == "stale":
                results.append({"id": m.id, "file": m.file, "what": m.what, "outcome": "stale", "seconds": 0.0})
                print(f"{m.id:4} stale     {m.what}", flush=True)
                continue
            original = p.read_text(encoding="utf-8")
            p.write_text(original.replace(m.old, m.new, 1), encoding="utf-8")
            try:
                res, secs, last = run_tests(copy, m.tests, args.timeout, cache)
            finally:
                p.write_text(original, encoding="utf-8")
            outcome = {"pass": "survived", "fail": "killed", "timeout": "killed", "nocollect": "stale"}[res]
            results.append({"id": m.id, "file": m.file, "what": m.what, "outcome": outcome, "seconds": round(secs, 1),
                            "tests": list(m.tests), "detail": last})
            print(f"{m.id:4} {outcome:9} {secs:6.1f}s  {m.what}" + (f"   [{last}]" if outcome != "killed" else ""),
                  flush=True)
    killed = sum(r["outcome"] == "killed" for r in results)
    survived = [r for r in results if r["outcome"] == "survived"]
    stale = [r for r in results if r["outcome"] == "stale"]
    n = killed + len(survived)
    pct = 100.0 * killed / n if n else float("nan")
    print(f"\n{killed} killed, {len(survived)} survived, {len(stale)} stale: {pct:.0f} % killed")
    for r in survived:
        print(f"  survived {r['id']}: {r['what']} ({r['file']})")
    for r in stale:
        print(f"  stale    {r['id']}: {r['what']} ({r['file']})")
    if args.json:  # atomic: temp file beside the target, then rename
        target = Path(args.json)
        fd, tmpname = tempfile.mkstemp(prefix=f".{target.name}.", dir=target.parent or ".")
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            json.dump({"killed": killed, "survived": len(survived), "stale": len(stale), "kill_percent": pct,
                       "results": results}, fh, indent=2)
            fh.write("\n")
        os.replace(tmpname, target)
    return 0


if __name__ == "__main__":
    sys.exit(main())
