"""Mutation testing per package with cosmic-ray (a real mutation tool), outside CI.

For every package of ``chainid`` (chain, signal, model, records, damping, gap, dynamics, infra, cli, report)
this script

1. copies the repository to a temporary folder (cosmic-ray mutates the files in place; the working tree is
   never touched), with a sibling ``shared`` linked to ``../shared`` (real-data tests look there);
2. runs ``cosmic-ray init`` on ``chainid/<package>`` with that package's targeted tests (``TARGETS``) as the
   test command, which enumerates every mutant of cosmic-ray's operators;
3. keeps a seeded random sample of ``--sample`` mutants (the rest are removed from the session);
4. checks that the targeted tests pass on the unmutated copy (else the package is reported, not counted);
5. runs ``cosmic-ray exec`` with a per-mutant timeout (3 × the baseline time + 10 s; a timeout counts as
   killed, as in cosmic-ray) and a per-package time budget (``--budget`` minutes over all packages);
6. writes the kill rate per package to ``benchmarks/MUTATION.md`` (date, tool version, command) and every
   surviving mutant with its diff to ``benchmarks/mutation_survivors.json``.  The triage of the survivors
   (equivalent, or a missing test) is kept by hand in ``benchmarks/mutation_survivors.md``.

Kill rate = killed / (killed + survived); incompetent mutants (the mutated code does not import) are
reported, not counted.

Usage (from the repository root; needs ``pip install ".[mutation]"``)::

    python benchmarks/mutation.py                          # all packages, 15 mutants each, seed 20, 40 min
    python benchmarks/mutation.py --packages chain infra --sample 10
    python benchmarks/mutation.py --list                   # number of mutants per package, no run
    python benchmarks/mutation.py --retest benchmarks/mutation_survivors.json --retest-out F.md
                                                           # the survivors again, against today's tests

Not part of the test suite (it takes tens of minutes of CPU).
"""
from __future__ import annotations

import argparse
import ast
import datetime as _dt
import json
import os
import random
import shlex
import shutil
import subprocess
import sys
import tempfile
import time
from importlib import metadata
from pathlib import Path

from chainid.infra.fileio import atomic_write_text
from mutation_targets import TARGETS  # benchmarks/ is the script's folder, first on sys.path

REPO = Path(__file__).resolve().parents[1]

PACKAGES = tuple(TARGETS)


def copy_repo(dst: Path) -> None:
    ignore = shutil.ignore_patterns(".git", "__pycache__", ".pytest_cache", "*.egg-info", ".hypothesis", "build",
                                    "mutants", "*.sqlite")
    shutil.copytree(REPO, dst, ignore=ignore, symlinks=True)


def package_targets(pkg: str, root: Path) -> list[str]:
    """The package's targeted tests that exist in ``root`` (a listed file may not exist yet)."""
    return [t for t in TARGETS[pkg] if t.startswith("-") or (root / t.split("::")[0]).is_file()]


#: packages whose njit functions are compiled into other modules' njit functions (numba's cache of the caller
#: does not see a change in the callee's file): every mutant gets a fresh NUMBA_CACHE_DIR (slower, but not stale)
FRESH_NUMBA_CACHE = {"dynamics", "model"}


def _test_command(tests: list[str], fresh_cache: bool = False) -> str:
    cmd = " ".join(shlex.quote(a) for a in
                   [sys.executable, "-m", "pytest", "-x", "-q", "-n", "0", "-p", "no:cacheprovider", "--no-header",
                    *tests])
    if not fresh_cache:
        return cmd
    script = f'd=$(mktemp -d); NUMBA_CACHE_DIR="$d" {cmd}; rc=$?; rm -rf "$d"; exit $rc'
    return f"sh -c {shlex.quote(script)}"


def _config(pkg: str, command: str, timeout: float) -> str:
    return (f'[cosmic-ray]\nmodule-path = "chainid/{pkg}"\ntimeout = {timeout:.1f}\nexcluded-modules = []\n'
            f"test-command = {json.dumps(command)}\n\n[cosmic-ray.distributor]\nname = \"local\"\n")


def run_env(copy: Path) -> dict[str, str]:
    return {**os.environ, "PYTHONPATH": str(copy), "NUMBA_CACHE_DIR": str(copy / ".numba_cache"),
            "MPLBACKEND": "Agg", "PYTHONDONTWRITEBYTECODE": "1"}


def init_session(pkg: str, copy: Path, timeout: float) -> tuple[Path, Path, int]:
    cfg, session = copy / f"cr_{pkg}.toml", copy / f"cr_{pkg}.sqlite"
    cfg.write_text(_config(pkg, _test_command(package_targets(pkg, copy), pkg in FRESH_NUMBA_CACHE), timeout),
                   encoding="utf-8")
    if session.exists():
        session.unlink()
    subprocess.run(["cosmic-ray", "init", str(cfg), str(session)], cwd=copy, env=run_env(copy), check=True,
                   capture_output=True)
    from cosmic_ray.work_db import WorkDB, use_db

    with use_db(str(session), WorkDB.Mode.open) as db:
        n = db.num_work_items
    return cfg, session, n


def _annotation_spans(path: Path) -> list[tuple[tuple[int, int], tuple[int, int]]]:
    """(start, end) positions of every annotation of a module that has ``from __future__ import annotations``
    (such annotations are never evaluated, so a mutant inside one is equivalent by construction)."""
    text = path.read_text(encoding="utf-8")
    tree = ast.parse(text)
    if not any(isinstance(n, ast.ImportFrom) and n.module == "__future__" and
               any(a.name == "annotations" for a in n.names) for n in tree.body):
        return []
    spans = []
    for node in ast.walk(tree):
        anns = []
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            a = node.args
            anns = [x.annotation for x in (*a.posonlyargs, *a.args, *a.kwonlyargs, a.vararg, a.kwarg)
                    if x is not None and x.annotation is not None] + ([node.returns] if node.returns else [])
        elif isinstance(node, ast.AnnAssign):
            anns = [node.annotation]
        for an in anns:
            spans.append(((an.lineno, an.col_offset), (an.end_lineno, an.end_col_offset)))
    return spans


def _in_annotation(m, spans_of: dict, root: Path) -> bool:
    f = m.module_path
    if f not in spans_of:
        spans_of[f] = _annotation_spans(root / f)
    s = tuple(m.start_pos)
    return any(a <= s < b for a, b in spans_of[f])


def sample_session(session: Path, k: int, seed: int, root: Path) -> tuple[int, int]:
    """Keep a seeded random sample of k mutants (after dropping those inside unevaluated annotations).
    Returns (kept, dropped as annotation mutants)."""
    from cosmic_ray.work_db import WorkDB, use_db

    with use_db(str(session), WorkDB.Mode.open) as db:
        # sorted by what the mutant is (job ids are random uuids), so that a seed gives the same sample
        items = sorted(db.work_items, key=lambda w: (str(w.mutations[0].module_path), w.mutations[0].operator_name,
                                                      w.mutations[0].occurrence))
        spans: dict = {}
        real = [w for w in items if not _in_annotation(w.mutations[0], spans, root)]
        keep = random.Random(seed).sample(real, min(k, len(real)))
        db.clear()
        db.add_work_items(keep)
        return len(keep), len(items) - len(real)


def _results(session: Path) -> list[dict]:
    from cosmic_ray.work_db import WorkDB, use_db

    out = []
    with use_db(str(session), WorkDB.Mode.open) as db:
        for item, res in db.completed_work_items:
            m = item.mutations[0]
            out.append({"job": item.job_id, "file": str(m.module_path), "line": m.start_pos[0],
                        "operator": m.operator_name, "occurrence": m.occurrence,
                        "outcome": (res.test_outcome.value if res.test_outcome is not None
                                    else res.worker_outcome.value),
                        "worker": res.worker_outcome.value, "diff": res.diff or ""})
    return out


def run_package(pkg: str, copy: Path, sample: int, seed: int, budget_s: float) -> dict:
    """Baseline, init, sample and exec for one package; its counts and survivors."""
    tests = package_targets(pkg, copy)
    t0 = time.perf_counter()
    base = subprocess.run(shlex.split(_test_command(tests, pkg in FRESH_NUMBA_CACHE)), cwd=copy, env=run_env(copy),
                          capture_output=True, text=True)
    t_base = time.perf_counter() - t0
    row: dict = {"package": pkg, "tests": tests, "baseline_s": round(t_base, 1)}
    if base.returncode != 0:
        row["error"] = "targeted tests fail on the unmutated copy: " + (base.stdout.strip().splitlines() or ["?"])[-1]
        return row
    timeout = 3.0 * t_base + 10.0
    cfg, session, n_all = init_session(pkg, copy, timeout)
    kept, n_ann = sample_session(session, sample, seed, copy)
    row.update(mutants_total=n_all, annotation_mutants=n_ann, sampled=kept, timeout_s=round(timeout, 1))
    t1 = time.perf_counter()
    proc = subprocess.Popen(["cosmic-ray", "exec", str(cfg), str(session)], cwd=copy, env=run_env(copy),
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        proc.wait(timeout=budget_s)
        row["budget_hit"] = False
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, 9)  # the mutant in place is left in this package's copy, which is discarded
        proc.wait()
        row["budget_hit"] = True
    row["exec_s"] = round(time.perf_counter() - t1, 1)
    res = _results(session)
    killed = sum(r["outcome"] == "killed" for r in res)
    survived = [r for r in res if r["outcome"] == "survived"]
    row.update(run=len(res), killed=killed, survived=len(survived),
               incompetent=sum(r["outcome"] not in ("killed", "survived") for r in res),
               kill_rate=killed / (killed + len(survived)) if killed + len(survived) else None,
               survivors=survived)
    return row


def retest(survivors_json: Path, out_md: Path | None, packages: tuple[str, ...] = PACKAGES) -> list[dict]:
    """Apply every survivor of an earlier run again (``cosmic-ray apply``, in a fresh copy of the repository as it
    is now) and run its package's current targeted tests: killed now (a test was added) or still surviving."""
    rows = json.loads(survivors_json.read_text(encoding="utf-8"))
    out = []
    with tempfile.TemporaryDirectory(prefix="chainid-retest-") as tmp:
        shared = REPO.parent / "shared"
        if shared.is_dir():
            (Path(tmp) / "shared").symlink_to(shared)
        pristine = Path(tmp) / "pristine"
        copy_repo(pristine)
        for r in rows:
            if r["package"] not in packages:
                continue
            for sv in r.get("survivors", []):
                copy = Path(tmp) / "work"
                if copy.exists():
                    shutil.rmtree(copy)
                shutil.copytree(pristine, copy, symlinks=True)
                subprocess.run(["cosmic-ray", "apply", sv["file"], sv["operator"], str(sv["occurrence"])], cwd=copy,
                               env=run_env(copy), check=True, capture_output=True)
                cmd = shlex.split(_test_command(package_targets(r["package"], copy), r["package"] in FRESH_NUMBA_CACHE))
                try:
                    rc = subprocess.run(cmd, cwd=copy, env=run_env(copy), capture_output=True, timeout=600).returncode
                except subprocess.TimeoutExpired:
                    rc = -1
                row = {"package": r["package"], "file": sv["file"], "line": sv["line"], "operator": sv["operator"],
                       "occurrence": sv["occurrence"], "now": "killed" if rc != 0 else "survived"}
                out.append(row)
                print(f"{row['package']:9s} {row['file']}:{row['line']} {row['operator']}: {row['now']}", flush=True)
    if out_md is not None:
        k = sum(r["now"] == "killed" for r in out)
        lines = ["| package | where | operator | with today's targeted tests |", "|---|---|---|---|"]
        lines += [f"| {r['package']} | {r['file']}:{r['line']} | {r['operator']} (#{r['occurrence']}) | {r['now']} |"
                  for r in out]
        lines += ["", f"{k} of {len(out)} survivors are killed by today's targeted tests."]
        out_md.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return out


def _rel(p: Path) -> str:
    """*p* relative to the repository when it lies inside it (the report names files as a reader finds them)."""
    try:
        return p.resolve().relative_to(REPO).as_posix()
    except ValueError:
        return str(p)


TARGETED = "each run against the package's targeted tests (`TARGETS` in `benchmarks/mutation_targets.py`)"


def write_markdown(rows: list[dict], args: argparse.Namespace, path: Path, started: str, minutes: float,
                   how: str = TARGETED) -> None:
    ver = metadata.version("cosmic-ray")
    cmd = "python benchmarks/mutation.py " + " ".join(
        [f"--packages {' '.join(args.packages)}" if tuple(args.packages) != PACKAGES else "",
         f"--sample {args.sample} --seed {args.seed} --budget {args.budget:g}"]).strip()
    tot_k = sum(r.get("killed", 0) for r in rows)
    tot_s = sum(r.get("survived", 0) for r in rows)
    lines = [
        "# Mutation testing per package (cosmic-ray)", "",
        f"Run {started} UTC, cosmic-ray {ver}, Python {sys.version.split()[0]}"
        + (f", {minutes:.1f} min." if minutes == minutes else "."), "",
        "Commands: " + ", ".join(sorted({f"`{r.get('command', cmd)}` ({r.get('run_started_utc', started)} UTC)"
                                           for r in rows})), "",
        f"A seeded random sample of {args.sample} of cosmic-ray's mutants per package (seed {args.seed}), {how}; "
        "kill rate = killed / "
        "(killed + survived); a timeout counts as killed; incompetent mutants are not counted. Survivors and their "
        f"triage: `{_rel(Path(args.survivors).with_suffix('.md'))}` (raw diffs: `{_rel(Path(args.survivors))}`).", "",
        "Mutants inside type annotations are dropped before sampling: every module has `from __future__ import "
        "annotations`, so its annotations are never evaluated and such a mutant (`str | None` → `str % None`) is "
        "equivalent by construction.", "",
        "| package | mutants (all) | in annotations | sampled | run | killed | survived | incompetent | kill rate "
        "| budget hit |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---|",
    ]
    for r in rows:
        if "error" in r:
            lines.append(f"| {r['package']} | – | – | – | – | – | – | – | not run: {r['error']} | |")
            continue
        kr = f"{100 * r['kill_rate']:.0f} %" if r["kill_rate"] is not None else "–"
        lines.append(f"| {r['package']} | {r['mutants_total']} | {r['annotation_mutants']} | {r['sampled']} | "
                     f"{r['run']} | {r['killed']} | "
                     f"{r['survived']} | {r['incompetent']} | {kr} | {'yes' if r['budget_hit'] else 'no'} |")
    if any("rules" in r for r in rows):
        lines += ["", "Tests chosen by (mutants per rule): " + "; ".join(
            f"{r['package']} " + ", ".join(f"{k} {v}" for k, v in r["rules"].items() if v) for r in rows
            if "rules" in r) + "."]
    if tot_k + tot_s:
        lines += ["", f"All packages: {tot_k} of {tot_k + tot_s} killed ({100 * tot_k / (tot_k + tot_s):.0f} %)."]
    atomic_write_text(path, "\n".join(lines) + "\n", force=True)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--packages", nargs="+", default=list(PACKAGES), choices=PACKAGES)
    ap.add_argument("--sample", type=int, default=15, help="mutants per package (seeded random sample)")
    ap.add_argument("--seed", type=int, default=20)
    ap.add_argument("--budget", type=float, default=40.0, help="minutes for the whole run (split over packages)")
    ap.add_argument("--list", action="store_true", help="only count the mutants per package")
    ap.add_argument("--out", default=str(REPO / "benchmarks" / "MUTATION.md"))
    ap.add_argument("--survivors", default=str(REPO / "benchmarks" / "mutation_survivors.json"))
    ap.add_argument("--merge", action="store_true",
                    help="keep the other packages' rows of the survivors JSON and MUTATION.md (re-run some packages)")
    ap.add_argument("--retest", metavar="SURVIVORS.json",
                    help="re-apply the survivors of an earlier run and run today's targeted tests on each")
    ap.add_argument("--retest-out", metavar="FILE.md", help="with --retest: write the table to FILE.md")
    args = ap.parse_args(argv)
    if shutil.which("cosmic-ray") is None:
        print("mutation.py: cosmic-ray is not installed: pip install '.[mutation]'", file=sys.stderr)
        return 2
    if args.retest:
        retest(Path(args.retest), Path(args.retest_out) if args.retest_out else None, tuple(args.packages))
        return 0
    started = _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M")
    t0 = time.perf_counter()
    rows = []
    with tempfile.TemporaryDirectory(prefix="chainid-mut-") as tmp:
        shared = REPO.parent / "shared"
        if shared.is_dir():
            (Path(tmp) / "shared").symlink_to(shared)
        pristine = Path(tmp) / "pristine"  # one snapshot at the start: edits made during the run do not leak in
        copy_repo(pristine)
        for i, pkg in enumerate(args.packages):
            copy = Path(tmp) / f"repo_{pkg}"  # a fresh copy per package: a run cut by the budget leaves a mutant
            shutil.copytree(pristine, copy, symlinks=True)
            if args.list:
                _, _, n = init_session(pkg, copy, 60.0)
                print(f"{pkg:10s} {n:6d} mutants; tests: {' '.join(package_targets(pkg, copy))}")
                continue
            left = args.budget * 60.0 - (time.perf_counter() - t0)
            budget_s = max(60.0, left / (len(args.packages) - i))
            row = run_package(pkg, copy, args.sample, args.seed, budget_s)
            rows.append(row)
            kr = row.get("kill_rate")
            print(f"{pkg:10s} " + (row["error"] if "error" in row else
                  f"{row['killed']}/{row['killed'] + row['survived']} killed"
                  + (f" ({100 * kr:.0f} %)" if kr is not None else "")
                  + f", {row['incompetent']} incompetent, {row['exec_s']:.0f} s"), flush=True)
    if args.list:
        return 0
    minutes = (time.perf_counter() - t0) / 60.0
    for r in rows:
        r["run_started_utc"] = started
        r["command"] = " ".join(["python benchmarks/mutation.py", *(argv if argv is not None else sys.argv[1:])])
    if args.merge and Path(args.survivors).is_file():
        old_rows = json.loads(Path(args.survivors).read_text(encoding="utf-8"))
        new = {r["package"]: r for r in rows}
        rows = [new.pop(r["package"], r) for r in old_rows] + list(new.values())
        minutes = float("nan")
    write_markdown(rows, args, Path(args.out), started, minutes)
    atomic_write_text(args.survivors, json.dumps(rows, indent=1) + "\n", force=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
