"""Performance benchmarks of chainid (issue 5).  Not part of the test suite.

Usage (from the repository root)::

    python benchmarks/run.py                       # full run, < 3 min on 2 cores
    python benchmarks/run.py --quick               # smaller sizes / fewer repeats, < 1 min
    python benchmarks/run.py --write-readme-table  # also writes benchmarks/RESULTS.md

Sections
--------
1. Kernels: F_k(x), k_e(x) on 10^6 float64 displacements, single thread (the
   serial ``*_array`` kernels) vs (a) SymPy lambdify (numpy backend) of the
   closed-form root of c_lin u^3 + c_hertz u^2 = x, (b) per-point
   scipy.optimize.brentq inversion of x(F) (timed on a subsample, scaled per
   point), (c) the floor numpy.cbrt over the same array.  Plus the prange
   kernels on all cores for 10^7 points.
2. Start-up in fresh processes: import numba (floor), import chainid, import +
   first F_k call with a warm / cold numba cache (temp NUMBA_CACHE_DIR), and a
   check that SymPy is never imported.
3. Identification of 9 tests x 8 cycles x 256 samples and the gap diagnosis of
   11 such tests (skipped with a message when the APIs are not importable):
   wall time and the share of time spent in the stiffness kernels (cProfile).
4. Peak RSS of the runs of section 3 (resource.getrusage in the subprocess).

Every ratio is computed from numbers measured in the same run.  Medians of
several repetitions.  PASS/MISS is printed per target of issue 5.
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from datetime import datetime, timezone
from pathlib import Path
from timing import median_time  # benchmarks/timing.py (this folder is on sys.path when run)

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent

TARGETS = {
    "kernel_vs_floor": 3.0,       # kernel time <= 3x numpy.cbrt
    "speedup_vs_lambdify": 5.0,   # >= 5x faster than lambdify
    "speedup_vs_brentq": 500.0,   # >= 500x faster than brentq
    "import_vs_numba": 1.5,       # import chainid <= 1.5x import numba
    "first_call_warm_s": 0.15,    # first call with warm cache adds <= 0.15 s
}


# --------------------------------------------------------------------------- helpers


def verdict(ok: bool) -> str:
    return "PASS" if ok else "MISS"


def displacements(n: int, seed: int = 0):
    """n float64 elongations, log-uniform over 1e-9 ... 1e3 mm (the kernels' accuracy domain)."""
    import numpy as np

    rng = np.random.default_rng(seed)
    return 10.0 ** rng.uniform(-9.0, 3.0, n)


# --------------------------------------------------------------------------- 1. kernels
def lambdify_baseline():
    """numpy functions F(x, c_lin, c_hertz), k(x, c_lin, c_hertz) from the SymPy closed form.

    u = (c_hertz/c_lin) s with s^3 + s^2 = xi, xi = x c_lin^2 / c_hertz^3: the
    Cardano root of derive.chain.cardano_root for xi > 4/27, the trigonometric
    root below.  F = u^3; k_e = derive.chain.stiffness_in_u at that u.
    """
    import sympy as sp

    sys.path.insert(0, str(ROOT))
    from derive import chain as dc
    from derive.symbols import c_hertz, c_lin, u, x  # noqa: F401

    xi = x * c_lin**2 / c_hertz**3
    a = sp.Rational(27, 2) * xi - 1
    s_trig = sp.Rational(2, 3) * sp.cos(sp.acos(a) / 3) - sp.Rational(1, 3)
    u_trig = c_hertz / c_lin * s_trig
    u_expr = sp.Piecewise((u_trig, xi <= sp.Rational(4, 27)), (dc.cardano_root(), True))
    F_expr = u_expr**3
    k_expr = dc.stiffness_in_u().subs(u, u_expr)
    fF = sp.lambdify((x, c_lin, c_hertz), F_expr, modules="numpy")
    fk = sp.lambdify((x, c_lin, c_hertz), k_expr, modules="numpy")
    return fF, fk


def brentq_force(xs, cl, ch):
    import math

    from scipy.optimize import brentq

    out = []
    for xv in xs:
        out.append(brentq(lambda F: cl * F + ch * F ** (2.0 / 3.0) - xv, 0.0, xv / cl, xtol=1e-300, rtol=1e-15))
    return out


def brentq_stiffness(xs, cl, ch):
    return [1.0 / (cl + (2.0 / 3.0) * ch / F ** (1.0 / 3.0)) for F in brentq_force(xs, cl, ch)]


def bench_kernels(quick: bool) -> dict:
    import numba
    import numpy as np

    import chainid
    from chainid.model import kernels

    gen = kernels.variant_module("paper")
    cl, ch = kernels.coefficients(None)
    n = 10**6
    reps = 5 if quick else 11
    x = displacements(n)
    out: dict = {"n": n, "reps": reps, "c_lin": cl, "c_hertz": ch}

    # warm up / compile
    gen.force_array(x[:10], cl, ch), gen.stiffness_array(x[:10], cl, ch)
    gen.force_parallel(x[:10], cl, ch), gen.stiffness_parallel(x[:10], cl, ch)
    chainid.force(x[:10])

    t_floor = median_time(lambda: np.cbrt(x), reps)
    t_F = median_time(lambda: gen.force_array(x, cl, ch), reps)
    t_k = median_time(lambda: gen.stiffness_array(x, cl, ch), reps)
    t_api = median_time(lambda: chainid.force(x), reps)

    fF, fk = lambdify_baseline()
    with np.errstate(all="ignore"):
        fF(x[:10], cl, ch)
        lreps = 3 if quick else 5
        t_lF = median_time(lambda: fF(x, cl, ch), lreps)
        t_lk = median_time(lambda: fk(x, cl, ch), lreps)
        lam_err = float(np.nanmax(np.abs(fF(x, cl, ch) / gen.force_array(x, cl, ch) - 1.0)))

    nb = 500 if quick else 2000
    xb = x[:nb]
    t_bF = median_time(lambda: brentq_force(xb, cl, ch), 3) / nb * n
    t_bk = median_time(lambda: brentq_stiffness(xb, cl, ch), 3) / nb * n

    # round trip of the kernel on the same data (information; the test suite owns the guarantee)
    rt = float(np.max(np.abs(gen.displacement_array(gen.force_array(x, cl, ch), cl, ch) / x - 1.0)))

    npar = 10**6 if quick else 10**7
    xp = displacements(npar, seed=1)
    t_pF = median_time(lambda: gen.force_parallel(xp, cl, ch), reps)
    t_pk = median_time(lambda: gen.stiffness_parallel(xp, cl, ch), reps)
    t_sF10 = median_time(lambda: gen.force_array(xp, cl, ch), 3)
    t_floor10 = median_time(lambda: np.cbrt(xp), 3)

    out.update(
        t_floor=t_floor, t_F=t_F, t_k=t_k, t_api=t_api, t_lambdify_F=t_lF, t_lambdify_k=t_lk,
        lambdify_max_rel_diff=lam_err, brentq_subsample=nb, t_brentq_F=t_bF, t_brentq_k=t_bk,
        roundtrip_max_rel=rt, n_par=npar, threads=numba.get_num_threads(), t_par_F=t_pF, t_par_k=t_pk,
        t_serial_F_npar=t_sF10, t_floor_npar=t_floor10,
    )
    return out


def print_kernels(r: dict) -> list[tuple[str, bool]]:
    n = r["n"]
    print(f"\n== 1. kernels: {n:.0e} float64 x log-uniform in [1e-9, 1e3] mm, single thread, median of {r['reps']} ==")
    rows = [
        ("numpy.cbrt (floor)", r["t_floor"], r["t_floor"]),
        ("F_k  generated force_array", r["t_F"], r["t_F"]),
        ("k_e  generated stiffness_array", r["t_k"], r["t_k"]),
        ("F_k  chainid.force (API wrapper)", r["t_api"], r["t_api"]),
        ("F_k  SymPy lambdify (numpy)", r["t_lambdify_F"], None),
        ("k_e  SymPy lambdify (numpy)", r["t_lambdify_k"], None),
        (f"F_k  brentq (scaled from {r['brentq_subsample']} pts)", r["t_brentq_F"], None),
        (f"k_e  brentq (scaled from {r['brentq_subsample']} pts)", r["t_brentq_k"], None),
    ]
    for name, t, _ in rows:
        print(f"  {name:44s} {t * 1e3:10.2f} ms  {t / n * 1e9:9.2f} ns/pt  {t / r['t_floor']:8.2f}x floor")
    checks = []
    for lab, t, tl, tb in (("F_k", r["t_F"], r["t_lambdify_F"], r["t_brentq_F"]),
                           ("k_e", r["t_k"], r["t_lambdify_k"], r["t_brentq_k"])):
        a, b, c = t / r["t_floor"], tl / t, tb / t
        checks += [
            (f"{lab} kernel / cbrt floor = {a:.2f} (target <= {TARGETS['kernel_vs_floor']})", a <= TARGETS["kernel_vs_floor"]),
            (f"{lab} lambdify / kernel = {b:.1f} (target >= {TARGETS['speedup_vs_lambdify']})", b >= TARGETS["speedup_vs_lambdify"]),
            (f"{lab} brentq / kernel = {c:.0f} (target >= {TARGETS['speedup_vs_brentq']:.0f})", c >= TARGETS["speedup_vs_brentq"]),
        ]
    print(f"  kernel round trip max |x(F(x))/x - 1| = {r['roundtrip_max_rel']:.2e};"
          f" lambdify vs kernel max rel diff = {r['lambdify_max_rel_diff']:.2e}")
    np_ = r["n_par"]
    print(f"  parallel (prange, {r['threads']} threads) on {np_:.0e} pts: F_k {r['t_par_F'] * 1e3:.1f} ms,"
          f" k_e {r['t_par_k'] * 1e3:.1f} ms; serial F_k {r['t_serial_F_npar'] * 1e3:.1f} ms"
          f" (speed-up {r['t_serial_F_npar'] / r['t_par_F']:.2f}x), numpy.cbrt {r['t_floor_npar'] * 1e3:.1f} ms")
    return checks


# --------------------------------------------------------------------------- 2. start-up
FIRST_CALL = (
    "import time, sys; t0 = time.perf_counter(); import chainid; t1 = time.perf_counter(); "
    "chainid.force(1.0); t2 = time.perf_counter(); "
    "print(t1 - t0, t2 - t1, 'sympy' in sys.modules)"
)


TRIVIAL_NJIT = "from numba import njit\n\n\n@njit(cache=True)\ndef f(x):\n    return x * 2.0\n"
TRIVIAL_CALL = "import _chainid_bench_trivial as m; m.f(1.0)"


def _run(code: str, env: dict) -> tuple[float, str]:
    t0 = time.perf_counter()
    p = subprocess.run([sys.executable, "-c", code], env=env, cwd=tempfile.gettempdir(),
                       capture_output=True, text=True)
    dt = time.perf_counter() - t0
    if p.returncode != 0:
        raise RuntimeError(f"subprocess failed: {code}\n{p.stderr}")
    return dt, p.stdout.strip()


def bench_startup(quick: bool) -> dict:
    reps = 5 if quick else 7
    base = dict(os.environ)
    res: dict = {"reps": reps}
    with tempfile.TemporaryDirectory() as warm, tempfile.TemporaryDirectory() as triv:
        env_w = {**base, "NUMBA_CACHE_DIR": warm}
        # numba's own floor: import numba + first call of a trivial cached @njit function (warm cache)
        Path(triv, "_chainid_bench_trivial.py").write_text(TRIVIAL_NJIT)
        env_t = {**env_w, "PYTHONPATH": triv}
        _run(TRIVIAL_CALL, env_t)
        _run(FIRST_CALL, env_w)  # populate the warm cache
        _run("import numba", base)  # warm the OS file cache
        t_nb, t_py, t_imp, t_w, t_c, t_triv = [], [], [], [], [], []
        inner_w, inner_c, sympy_seen = [], [], []
        for _ in range(reps):
            t_py.append(_run("pass", base)[0])
            t_nb.append(_run("import numba", base)[0])
            t_triv.append(_run(TRIVIAL_CALL, env_t)[0])
            t_imp.append(_run("import chainid", env_w)[0])
            dt, s = _run(FIRST_CALL, env_w)
            t_w.append(dt)
            a, b, sy = s.split()
            inner_w.append(float(b))
            sympy_seen.append(sy == "True")
            with tempfile.TemporaryDirectory() as cold:
                dt, s = _run(FIRST_CALL, {**base, "NUMBA_CACHE_DIR": cold})
            t_c.append(dt)
            a, b, sy = s.split()
            inner_c.append(float(b))
            sympy_seen.append(sy == "True")
        sy_after_import = _run("import sys, chainid; print('sympy' in sys.modules)", env_w)[1] == "True"
    med = statistics.median
    res.update(t_python=med(t_py), t_numba=med(t_nb), t_trivial=med(t_triv), t_chainid=med(t_imp), t_first_warm=med(t_w),
               t_first_cold=med(t_c), first_call_warm_inproc=med(inner_w), first_call_cold_inproc=med(inner_c),
               sympy_imported=any(sympy_seen) or sy_after_import)
    return res


def print_startup(r: dict) -> list[tuple[str, bool]]:
    print(f"\n== 2. start-up, fresh processes, wall time of `python -c ...`, median of {r['reps']} ==")
    for name, k in (("python -c pass", "t_python"), ("import numba (floor)", "t_numba"),
                    ("import numba + first trivial @njit, warm cache", "t_trivial"),
                    ("import chainid", "t_chainid"), ("import chainid + first F_k, warm cache", "t_first_warm"),
                    ("import chainid + first F_k, cold cache", "t_first_cold")):
        print(f"  {name:44s} {r[k]:8.3f} s  {r[k] / r['t_numba']:6.2f}x numba")
    print(f"  first call alone (in-process): warm cache {r['first_call_warm_inproc']:.3f} s,"
          f" cold cache {r['first_call_cold_inproc']:.3f} s")
    print(f"  sympy in sys.modules after import + first call: {r['sympy_imported']}")
    a = r["t_chainid"] / r["t_numba"]
    add = r["t_first_warm"] - r["t_chainid"]
    # chainid imports numba lazily (on the first kernel call), so `add` includes `import numba`;
    # shown separately: what the first call costs beyond import chainid + import numba.
    beyond = r["t_first_warm"] - r["t_chainid"] - (r["t_numba"] - r["t_python"])
    print(f"  first call with warm cache adds {add:.3f} s over import chainid, of which import numba"
          f" {r['t_numba'] - r['t_python']:.3f} s; beyond both: {beyond:.3f} s")
    over = r["t_first_warm"] - r["t_trivial"]
    print(f"  import chainid + first F_k vs import numba + first trivial cached @njit (numba's own first-call floor):"
          f" {over:+.3f} s")
    return [
        (f"import chainid / import numba = {a:.2f} (target <= {TARGETS['import_vs_numba']})", a <= TARGETS["import_vs_numba"]),
        (f"first F_k call with warm cache adds {add:.3f} s (target <= {TARGETS['first_call_warm_s']} s)",
         add <= TARGETS["first_call_warm_s"]),
        (f"SymPy never imported (imported: {r['sympy_imported']})", not r["sympy_imported"]),
    ]


# --------------------------------------------------------------------------- 3./4. workflows
def _kernel_share(prof) -> float:
    """Seconds spent inside the stiffness-model calls (models.py force/stiffness, incl. their thin wrappers)."""
    import pstats

    st = pstats.Stats(prof)
    tot = 0.0
    for (fname, _line, func), (_cc, _nc, _tt, ct, callers) in st.stats.items():
        if fname.endswith(os.path.join("chainid", "models.py")) and func in ("force", "stiffness"):
            # count only calls from outside models.py (avoid double counting nested calls)
            for (cf, _cl, _cfn), (_a, _b, _t, cct) in callers.items():
                if not cf.endswith(os.path.join("chainid", "models.py")):
                    tot += cct
    return tot


def child_workflow(which: str) -> None:
    """Run in a subprocess: one workflow, print JSON {wall, kernel_s, peak_rss_MB} (or {skip})."""
    import cProfile
    import resource

    try:
        import numpy as np  # noqa: F401

        from chainid.damping.identify import PolynomialLaw, identify_records
        from chainid.model.base import ChainModel
        from chainid.records.simulate import paper_plan, simulate
        if which == "gap":
            from chainid.gap import diagnose
            from chainid.gap.benchmark.grid import grid3x3_plan
    except Exception as e:  # noqa: BLE001
        print(json.dumps({"skip": f"{type(e).__name__}: {e}"}))
        return
    try:
        model = ChainModel()
        model.force(np.array([1.0])), model.stiffness(np.array([1.0]))  # compile / load cache outside the timing
        if which == "identify":
            plan = paper_plan()
            k = float(np.median(model.stiffness(np.array([p.x0 for p in plan]))))
            law = PolynomialLaw([0.0, 0.0, 0.0, 0.0, 0.02 * k])
            recs = simulate(plan, model, law, n_cycles=8, samples_per_cycle=256, noise_F=0.01, seed=0)

            def work():
                return identify_records(recs, model)
        else:
            plan = grid3x3_plan("a")
            k = float(np.median(model.stiffness(np.array([p.x0 for p in plan]))))
            law = PolynomialLaw([0.0, 0.0, 0.0, 0.0, 0.02 * k / 4.0])
            recs = simulate(plan, model, law, n_cycles=8, samples_per_cycle=256, noise_F=0.01, seed=0)
            hold = ["a3", "a6", "a11"]

            def work():
                return diagnose(recs, hold, model, uncertainty=False)
        t0 = time.perf_counter()
        work()
        wall = time.perf_counter() - t0
        prof = cProfile.Profile()
        prof.enable()
        t0 = time.perf_counter()
        work()
        wall_prof = time.perf_counter() - t0
        prof.disable()
        ks = _kernel_share(prof)
        # ru_maxrss survives fork+exec (it would report the parent's peak); VmHWM is reset at exec.
        rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # kB on Linux
        try:
            for line in Path("/proc/self/status").read_text().splitlines():
                if line.startswith("VmHWM:"):
                    rss = float(line.split()[1]) / 1024.0
        except OSError:
            pass
        print(json.dumps({"wall": wall, "wall_profiled": wall_prof, "kernel_s": ks,
                          "kernel_share": ks / wall_prof, "peak_rss_MB": rss, "n_tests": len(plan)}))
    except Exception as e:  # noqa: BLE001
        print(json.dumps({"skip": f"API present but failed: {type(e).__name__}: {e}"}))


def bench_workflows() -> dict:
    out = {}
    for which in ("identify", "gap"):
        p = subprocess.run([sys.executable, str(Path(__file__).resolve()), "--_child", which],
                           capture_output=True, text=True, cwd=str(ROOT))
        try:
            out[which] = json.loads(p.stdout.strip().splitlines()[-1])
        except Exception:  # noqa: BLE001
            out[which] = {"skip": f"child failed (rc {p.returncode}): {p.stderr.strip()[-300:]}"}
    return out


def print_workflows(r: dict) -> None:
    print("\n== 3./4. workflows (8 cycles x 256 samples per test; fresh subprocess, kernels precompiled/cached) ==")
    names = {"identify": "identification, 9 tests (identify_records)",
             "gap": "gap diagnosis, 11 tests (diagnose, uncertainty=False)"}
    for k, name in names.items():
        v = r[k]
        if "skip" in v:
            print(f"  {name}: SKIPPED - {v['skip']}")
            continue
        print(f"  {name}: wall {v['wall']:.3f} s; in stiffness kernels {v['kernel_share'] * 100:.1f} %"
              f" ({v['kernel_s']:.3f} of {v['wall_profiled']:.3f} s under cProfile), Python/numpy rest"
              f" {100 - v['kernel_share'] * 100:.1f} %; peak RSS {v['peak_rss_MB']:.0f} MB")


# --------------------------------------------------------------------------- report
def machine() -> dict:
    import numba
    import numpy as np

    cpu = platform.processor() or "?"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return {"cpu": cpu, "cores": os.cpu_count(), "date": datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
            "python": platform.python_version(), "numba": numba.__version__, "numpy": np.__version__}


def write_results(path: Path, m: dict, k: dict, s: dict, w: dict, checks: list, quick: bool) -> None:
    n = k["n"]
    L = ["# Benchmark results", "",
         "Generated by `python benchmarks/run.py --write-readme-table`" + (" --quick" if quick else "")
         + "; do not edit by hand.", "",
         f"Machine: {m['cpu']}, {m['cores']} cores; {m['date']}; Python {m['python']}, numba {m['numba']},"
         f" numpy {m['numpy']}.", "",
         f"## Kernels ({n:.0e} float64 displacements, single thread, median of {k['reps']})", "",
         "| method | F_k ms | F_k x floor | k_e ms | k_e x floor |", "|---|---:|---:|---:|---:|"]
    fl = k["t_floor"]
    L.append(f"| numpy.cbrt (floor) | {fl * 1e3:.2f} | 1.00 | {fl * 1e3:.2f} | 1.00 |")
    for name, a, b in (("generated numba kernel", k["t_F"], k["t_k"]),
                       ("SymPy lambdify (numpy)", k["t_lambdify_F"], k["t_lambdify_k"]),
                       (f"brentq per point (scaled from {k['brentq_subsample']})", k["t_brentq_F"], k["t_brentq_k"])):
        L.append(f"| {name} | {a * 1e3:.2f} | {a / fl:.2f} | {b * 1e3:.2f} | {b / fl:.2f} |")
    L += ["", f"Parallel (prange, {k['threads']} threads), {k['n_par']:.0e} points: F_k {k['t_par_F'] * 1e3:.1f} ms"
          f" (serial {k['t_serial_F_npar'] * 1e3:.1f} ms, speed-up {k['t_serial_F_npar'] / k['t_par_F']:.2f}x),"
          f" k_e {k['t_par_k'] * 1e3:.1f} ms.", "",
          f"## Start-up (fresh processes, median of {s['reps']})", "", "| command | s | x import numba |", "|---|---:|---:|"]
    for name, key in (("`python -c pass`", "t_python"), ("`import numba`", "t_numba"),
                      ("import numba + first call of a trivial cached `@njit` (numba's floor)", "t_trivial"),
                      ("`import chainid`", "t_chainid"),
                      ("import + first F_k, warm cache", "t_first_warm"), ("import + first F_k, cold cache", "t_first_cold")):
        L.append(f"| {name} | {s[key]:.3f} | {s[key] / s['t_numba']:.2f} |")
    L += ["", f"First F_k call with a warm cache, beyond numba's own first-call floor: "
          f"{s['t_first_warm'] - s['t_trivial']:+.3f} s. SymPy imported: {s['sympy_imported']}.", "", "## Workflows (8 cycles x 256 samples per test)", "",
          "| run | wall s | share in kernels | peak RSS MB |", "|---|---:|---:|---:|"]
    for key, name in (("identify", "identification, 9 tests"), ("gap", "gap diagnosis, 11 tests")):
        v = w[key]
        if "skip" in v:
            L.append(f"| {name} | skipped | | |")
        else:
            L.append(f"| {name} | {v['wall']:.3f} | {v['kernel_share'] * 100:.1f} % | {v['peak_rss_MB']:.0f} |")
    L += ["", "## Targets (issue 5)", ""] + [f"- {verdict(ok)}: {msg}" for msg, ok in checks] + [""]
    path.write_text("\n".join(L))


README_START = "<!-- benchmarks:start (written by benchmarks/run.py --write-readme-table) -->"
README_END = "<!-- benchmarks:end -->"


def splice_readme(readme: Path, results_md: str) -> bool:
    """Replace the README's text between the benchmark markers by RESULTS.md (its headings one level down)."""
    if not readme.is_file():
        return False
    text = readme.read_text()
    i, j = text.find(README_START), text.find(README_END)
    if i < 0 or j < i:
        return False
    body = "\n".join(("#" + ln if ln.startswith("## ") else ln) for ln in results_md.splitlines()
                     if not ln.startswith("# "))
    readme.write_text(text[: i + len(README_START)] + "\n" + body.strip() + "\n" + text[j:])
    return True


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="fewer repetitions and 10^6 parallel points (< 1 min)")
    ap.add_argument("--write-readme-table", action="store_true", help="write benchmarks/RESULTS.md")
    ap.add_argument("--skip-workflows", action="store_true", help="skip section 3/4")
    ap.add_argument("--_child", help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    if a._child:
        child_workflow(a._child)
        return 0
    t_start = time.perf_counter()
    m = machine()
    print(f"machine: {m['cpu']}, {m['cores']} cores; {m['date']}; python {m['python']}, numba {m['numba']},"
          f" numpy {m['numpy']}")
    k = bench_kernels(a.quick)
    checks = print_kernels(k)
    s = bench_startup(a.quick)
    checks += print_startup(s)
    w = {"identify": {"skip": "--skip-workflows"}, "gap": {"skip": "--skip-workflows"}} if a.skip_workflows \
        else bench_workflows()
    print_workflows(w)
    print("\n== targets ==")
    for msg, ok in checks:
        print(f"  {verdict(ok)}  {msg}")
    if a.write_readme_table:
        p = HERE / "RESULTS.md"
        write_results(p, m, k, s, w, checks, a.quick)
        print(f"\nwrote {p}")
        if splice_readme(HERE.parent / "README.md", p.read_text()):
            print(f"updated the benchmark table in {HERE.parent / 'README.md'}")
    print(f"\ntotal benchmark time {time.perf_counter() - t_start:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
