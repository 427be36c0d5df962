"""Mutation testing with the tests each mutant can reach (coverage-guided selection), outside CI.

``benchmarks/mutation.py`` runs one fixed list of targeted tests per package on every mutant; for model, gap and
dynamics that list takes 8–14 min on one core, so 30 mutants of those packages never fitted a session. This
script asks instead, for every mutant, which tests of the **whole suite** execute its line, and runs just those:

1. a snapshot of the repository in a temporary folder (as ``mutation.py``: the working tree is never touched), with
   a sibling ``shared`` linked to ``../shared`` for the real-data tests;
2. the whole suite once under coverage.py with one context per test and phase (pytest-cov's ``--cov-context=test``:
   ``node id|setup``, ``|run``, ``|teardown``) and a JUnit file for each test's time (``--coverage DIR`` reuses an
   earlier map).  A line run while a test's fixtures are set up is mapped to every test of that test's file: a
   module-scoped fixture runs once, in the setup of its file's first test, and serves all of them (a session-scoped
   one serves other files too, which this mapping misses: the suite has three, in the derivation's and the CLI's
   conftest files).  (coverage.py's own ``dynamic_context = test_function`` leaves fixture code with the empty
   context, so a mutant in code that only a shared fixture runs got no test that reads its output, and survived;
   the report's Eq. 26 figure was one.);
3. per package, ``cosmic-ray init`` and the same seeded sample as ``mutation.py`` (mutants inside unevaluated
   annotations dropped first);
4. for each mutant the tests are chosen by the first rule that gives any (the rule is recorded per mutant):

   - ``line``: the tests that execute the mutated line;
   - ``function``: the tests that execute any line of the function around it (a default value, a decorator);
   - ``package``: in a module that compiles code with numba (whose bodies coverage cannot trace), the tests that
     execute any line of its package (the callers of the compiled code are plain Python);
   - ``module``: the tests that execute any line of its module (a line run only at import);
   - ``targets``: the package's ``TARGETS`` of ``mutation.py``.

   A test that does not execute a mutant's code cannot fail because of it, so the selection loses no kill that
   the whole suite would make, except through import-time effects read by tests of other modules;
5. ``cosmic-ray apply`` in one of ``--workers`` copies, the chosen tests, fastest first, with ``pytest -x -n 0``
   (a kill stops at the first failing test) and a timeout of 60 s + 5 × their time in the coverage run (a
   timeout counts as killed, as in cosmic-ray), then the file is put back. A mutant in a module that holds
   numba-compiled code runs with a fresh ``NUMBA_CACHE_DIR`` (a caller's cache does not see a change in its
   callee's file); the others share their worker's cache.

It writes the same table and survivors JSON as ``mutation.py``, the selection stated in the table's text.

Usage (from the repository root; needs ``pip install ".[mutation]"``, which brings coverage.py)::

    python benchmarks/mutation_select.py --sample 30 --seed 29 --workers 2 --out F.md --survivors F.json
    python benchmarks/mutation_select.py --packages model gap --coverage /tmp/covmap   # made there once, then reused
"""
from __future__ import annotations

import argparse
import ast
import datetime as _dt
import json
import queue
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import mutation
from chainid.infra.fileio import atomic_write_text
from mutation_targets import TARGETS

REPO = mutation.REPO
PACKAGES = tuple(TARGETS)
RULES = ("line", "package", "function", "module", "targets")


def coverage_map(copy: Path, out: Path) -> Path:
    """Run the whole suite in *copy* under pytest-cov with one context per test and phase (``--cov-context=test``;
    the xdist workers combined by pytest-cov, subprocesses measured through ``patch = subprocess`` and appended);
    the data file and a JUnit file of the tests' times go to *out*.  Returns *out*."""
    out.mkdir(parents=True, exist_ok=True)
    rc = out / "coveragerc"
    rc.write_text(f"[run]\nsource = chainid\nparallel = true\npatch = subprocess\n"
                  f"data_file = {out / '.coverage'}\n", encoding="utf-8")
    env = mutation.run_env(copy)
    cmd = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "--cov=chainid", f"--cov-config={rc}",
           "--cov-context=test", "--cov-report=", f"--junitxml={out / 'junit.xml'}"]
    proc = subprocess.run(cmd, cwd=copy, env=env, capture_output=True, text=True)
    (out / "pytest.log").write_text(proc.stdout + proc.stderr, encoding="utf-8")
    # pytest-cov has combined its workers into the data file; fold in what subprocesses wrote beside it (--append:
    # a plain combine replaces the file, and one empty file of a subprocess that died at start erased the map)
    subprocess.run([sys.executable, "-m", "coverage", "combine", "--append", f"--rcfile={rc}"], cwd=copy, env=env,
                   capture_output=True)
    if not _has_contexts(out / ".coverage"):
        raise SystemExit(f"mutation_select.py: the coverage run wrote no per-test data (see {out / 'pytest.log'})")
    return out


def _has_contexts(path: Path) -> bool:
    """Whether a coverage data file exists and holds lines measured under a test's context."""
    from coverage import CoverageData
    from coverage.exceptions import DataError

    if not path.is_file():
        return False
    try:
        data = CoverageData(basename=str(path))
        data.read()
        return any(c for c in data.measured_contexts())
    except DataError:  # not a coverage file, or a damaged one: make the map anew
        return False


def node_ids(root: Path) -> dict[str, str]:
    """Test module name → its file's path under *root* (test file names are unique across the suite's folders)."""
    return {f.stem: f.relative_to(root).as_posix() for f in (root / "tests").rglob("test_*.py")}


def test_id(context: str, modules: dict[str, str]) -> str | None:
    """A pytest node id without parameters from a context: pytest-cov's ``path::name[params]|phase`` (``phase``
    setup, run or teardown), or coverage.py's ``module.function`` / ``module.Class.function`` of an older map; None
    for the empty context (import time) or a module that is not a test file."""
    if "::" in context:
        return context.rsplit("|", 1)[0].split("[", 1)[0]
    parts = context.split(".")
    if len(parts) < 2 or parts[0] not in modules:
        return None
    return "::".join([modules[parts[0]], *parts[1:]])


def line_tests(contexts: list[str], modules: dict[str, str], by_file: dict[str, set[str]]) -> set[str]:
    """The tests that reach a line from its contexts: each context's test (:func:`test_id`), and for a context of a
    fixture's set-up (``…|setup``) every test of that test's file (``by_file``: test file → its node ids), which
    the fixture may serve."""
    tests: set[str] = set()
    for c in contexts:
        t = test_id(c, modules)
        if t:
            tests.add(t)
            if c.endswith("|setup"):
                tests |= by_file.get(t.split("::", 1)[0], set())
    return tests


def test_times(junit: Path) -> dict[str, float]:
    """Seconds per test (node id without parameters, summed over its parameters) from a JUnit file."""
    times: dict[str, float] = {}
    for case in ET.parse(junit).getroot().iter("testcase"):
        parts = case.get("classname", "").split(".")
        # the module path dotted, then any class names (test files are test_*.py, test classes Test*)
        k = 1 + max((i for i, part in enumerate(parts) if part.startswith("test_")), default=len(parts) - 1)
        node = "/".join(parts[:k]) + ".py::" + "::".join([*parts[k:], case.get("name", "").split("[", 1)[0]])
        times[node] = times.get(node, 0.0) + float(case.get("time", 0.0))
    return times


class Selector:
    """The tests that reach each line of ``chainid`` (read once from the coverage data)."""

    def __init__(self, cov_dir: Path, root: Path):
        from coverage import CoverageData

        data = CoverageData(basename=str(cov_dir / ".coverage"))
        data.read()
        modules = node_ids(root)
        self.root = root
        self.times = test_times(cov_dir / "junit.xml") if (cov_dir / "junit.xml").is_file() else {}
        in_file: dict[str, set[str]] = {}
        for t in self.times:
            in_file.setdefault(t.split("::", 1)[0], set()).add(t)
        self.by_file: dict[str, dict[int, set[str]]] = {}
        for f in data.measured_files():
            rel = _package_path(f)
            lines = data.contexts_by_lineno(f)
            self.by_file[rel] = {ln: line_tests(cs, modules, in_file) for ln, cs in lines.items()}

    def _union(self, rel: str, lo: int, hi: int) -> set[str]:
        lines = self.by_file.get(rel, {})
        return set().union(*[lines[ln] for ln in lines if lo <= ln <= hi]) if lines else set()

    def select(self, rel: str, line: int, pkg: str) -> tuple[str, list[str]]:
        """(rule, node ids) for a mutant at *line* of the module *rel* (a path relative to the repository)."""
        tests = self.by_file.get(rel, {}).get(line, set())
        if tests:
            return "line", self.fastest_first(tests)
        if in_compiled(self.root / rel, line):  # compiled bodies are never traced: every test that runs the package
            pkg_dir = rel.rsplit("/", 1)[0] + "/"
            tests = set().union(*[self._union(f, 1, 10 ** 9) for f in self.by_file if f.startswith(pkg_dir)])
            if tests:
                return "package", self.fastest_first(tests)
        span = enclosing_function(self.root / rel, line)
        if span is not None:
            tests = self._union(rel, *span)
            if tests:
                return "function", self.fastest_first(tests)
        tests = self._union(rel, 1, 10 ** 9)
        if tests:
            return "module", self.fastest_first(tests)
        return "targets", mutation.package_targets(pkg, self.root)

    def fastest_first(self, tests: set[str]) -> list[str]:
        """The tests in order of their time in the coverage run, the fastest first (ties by name): with ``-x`` a
        mutant that a quick test kills stops there instead of after the slow ones."""
        return sorted(tests, key=lambda t: (self.times.get(t, 5.0), t))

    def seconds(self, tests: list[str]) -> float:
        """Their time in the coverage run (unknown ids count 5 s)."""
        return sum(self.times.get(t, 5.0) for t in tests if not t.startswith("-"))


def _package_path(measured: str) -> str:
    """A measured file's path from its ``chainid/`` folder on (the map may come from another copy's run)."""
    parts = Path(measured).as_posix().split("/")
    k = max(i for i, part in enumerate(parts) if part == "chainid")
    return "/".join(parts[k:])


def enclosing_function(path: Path, line: int) -> tuple[int, int] | None:
    """(first, last) line of the innermost function whose body holds *line*, or None at module level."""
    best = None
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and node.lineno <= line <= node.end_lineno:
            if best is None or node.lineno >= best[0]:
                best = (node.lineno, node.end_lineno)
    return best


def in_compiled(path: Path, line: int) -> bool:
    """Whether *line* lies in a function that numba compiles (a decorator that names ``jit``, as ``@njit`` or
    ``@numba.jit(...)``): coverage.py never traces such a body."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and node.lineno <= line <= node.end_lineno:
            if any("jit" in ast.unparse(d) for d in node.decorator_list):
                return True
    return False


def holds_numba(path: Path) -> bool:
    """Whether a module compiles code with numba (its mutants need a fresh cache)."""
    return "numba" in path.read_text(encoding="utf-8")


def sampled_mutants(pkg: str, copy: Path, sample: int, seed: int) -> tuple[list[dict], int, int]:
    """The seeded sample of *pkg*'s mutants, as ``mutation.py`` draws it: (mutants, all, in annotations)."""
    from cosmic_ray.work_db import WorkDB, use_db

    _, session, n_all = mutation.init_session(pkg, copy, 60.0)
    kept, n_ann = mutation.sample_session(session, sample, seed, copy)
    with use_db(str(session), WorkDB.Mode.open) as db:
        items = [w.mutations[0] for w in db.work_items]
    rows = [{"file": str(m.module_path), "line": m.start_pos[0], "operator": m.operator_name,
             "occurrence": m.occurrence} for m in items]
    rows.sort(key=lambda r: (r["file"], r["line"], r["operator"], r["occurrence"]))
    return rows, n_all, n_ann


def run_mutant(mut: dict, pkg: str, copy: Path, pristine: Path, sel: Selector, cache: Path) -> dict:
    """Apply one mutant in *copy*, run its selected tests, put the file back: the mutant's row."""
    rule, tests = sel.select(mut["file"], mut["line"], pkg)
    fresh = holds_numba(pristine / mut["file"])
    timeout = 60.0 + 5.0 * sel.seconds(tests)
    env = mutation.run_env(copy)
    row = {**mut, "package": pkg, "rule": rule, "n_tests": len([t for t in tests if not t.startswith("-")])}
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="nc-") as nc:
        env["NUMBA_CACHE_DIR"] = nc if fresh else str(cache)
        ap = subprocess.run(["cosmic-ray", "apply", mut["file"], mut["operator"], str(mut["occurrence"])], cwd=copy,
                            env=env, capture_output=True, text=True)
        try:
            if ap.returncode != 0:
                row.update(outcome="incompetent", diff=ap.stderr.strip()[-300:])
                return row
            row["diff"] = _diff(pristine / mut["file"], copy / mut["file"], mut["file"])
            cmd = [sys.executable, "-m", "pytest", "-x", "-q", "-n", "0", "-p", "no:cacheprovider", "--no-header",
                   *tests]
            try:
                rc = subprocess.run(cmd, cwd=copy, env=env, capture_output=True, timeout=timeout).returncode
                row["outcome"] = "survived" if rc == 0 else "killed"
            except subprocess.TimeoutExpired:
                row["outcome"] = "killed"
                row["timeout"] = True
        finally:
            shutil.copy2(pristine / mut["file"], copy / mut["file"])
    row["seconds"] = round(time.perf_counter() - t0, 1)
    return row


def _diff(before: Path, after: Path, name: str) -> str:
    import difflib

    return "".join(difflib.unified_diff(before.read_text(encoding="utf-8").splitlines(keepends=True),
                                        after.read_text(encoding="utf-8").splitlines(keepends=True),
                                        fromfile=name, tofile=name, n=1))


def run_all(jobs: list[tuple[str, dict]], copies: list[Path], pristine: Path, sel: Selector,
            budget_s: float) -> list[dict]:
    """Every (package, mutant) job on a pool of worker copies, each with its own numba cache; jobs not started
    within the budget are left out."""
    free: queue.Queue = queue.Queue()
    for c in copies:
        free.put(c)
    t0 = time.perf_counter()

    def one(job: tuple[str, dict]) -> dict | None:
        if time.perf_counter() - t0 > budget_s:
            return None
        copy = free.get()
        try:
            row = run_mutant(job[1], job[0], copy, pristine, sel, copy / ".numba_cache")
        finally:
            free.put(copy)
        print(f"{row['package']:9s} {row['file']}:{row['line']} {row['operator']}#{row['occurrence']}: "
              f"{row['outcome']} ({row['rule']}, {row['n_tests']} tests, {row.get('seconds', 0):.0f} s)", flush=True)
        return row

    with ThreadPoolExecutor(max_workers=len(copies)) as ex:
        return [r for r in ex.map(one, jobs) if r is not None]


def _changed(diff: str) -> list[str]:
    """The removed and added lines of a unified diff (its headers and line numbers left out)."""
    return [ln for ln in diff.splitlines() if ln[:1] in "-+" and not ln.startswith(("---", "+++"))]


def _first_changed_line(before: Path, after: Path) -> int:
    """The 1-based number of the first line where two versions of a file differ."""
    a = before.read_text(encoding="utf-8").splitlines()
    b = after.read_text(encoding="utf-8").splitlines()
    return next((i + 1 for i, (x, y) in enumerate(zip(a, b)) if x != y), min(len(a), len(b)) + 1)


def find_occurrence(mut: dict, copy: Path, pristine: Path) -> tuple[int, int] | None:
    """The occurrence of ``mut``'s operator in its file (as the file is now) that makes the same change as the
    stored ``mut["diff"]``, and the line it changes now: the stored occurrence first, then every other (up to 200
    past it) until cosmic-ray has no more; None when none does (the mutated code is gone).  Each try is put back."""
    want = _changed(mut["diff"])
    most = mut["occurrence"] + 200
    order = [mut["occurrence"], *(i for i in range(most) if i != mut["occurrence"])]
    env = mutation.run_env(copy)
    for occ in order:
        ap = subprocess.run(["cosmic-ray", "apply", mut["file"], mut["operator"], str(occ)], cwd=copy, env=env,
                            capture_output=True, text=True)
        try:
            changed = _changed(_diff(pristine / mut["file"], copy / mut["file"], mut["file"]))
            if ap.returncode != 0 or not changed:  # past the last occurrence (cosmic-ray may change nothing)
                if occ > mut["occurrence"]:
                    return None
                continue
            if changed == want:
                return occ, _first_changed_line(pristine / mut["file"], copy / mut["file"])
        finally:
            shutil.copy2(pristine / mut["file"], copy / mut["file"])
    return None


def rerun_jobs(prev: list[dict], pkgs: list[str], copy: Path, pristine: Path) -> tuple[list[tuple[str, dict]], dict]:
    """The survivors of an earlier run (its survivors JSON) as jobs on today's code, each at the occurrence that
    makes its stored change; per package the earlier counts and the survivors whose code is gone (``gone``)."""
    jobs, info = [], {}
    for r in prev:
        if r["package"] not in pkgs:
            continue
        gone = []
        for sv in r.get("survivors", []):
            found = find_occurrence(sv, copy, pristine)
            if found is None:
                gone.append(sv)
            else:
                jobs.append((r["package"], {"file": sv["file"], "operator": sv["operator"], "occurrence": found[0],
                                            "line": found[1]}))
        info[r["package"]] = {"jobs": sum(j[0] == r["package"] for j in jobs),
                              "mutants_total": r.get("mutants_total"), "annotation_mutants": r.get("annotation_mutants"),
                              "sampled": r["sampled"], "killed_before": r["killed"], "survived_before": r["survived"],
                              "incompetent_before": r["incompetent"], "gone": gone}
    return jobs, info


def rerun_rows(info: dict, results: list[dict]) -> list[dict]:
    """Per package: the earlier run's kills, plus its survivors killed by today's tests; survivors whose code is gone
    count neither way."""
    rows = []
    for pkg, i in info.items():
        res = [r for r in results if r["package"] == pkg]
        now_k = sum(r["outcome"] == "killed" for r in res)
        surv = [r for r in res if r["outcome"] == "survived"]
        killed = i["killed_before"] + now_k
        now_inc = sum(r["outcome"] == "incompetent" for r in res)
        rows.append({"package": pkg, "tests": "coverage-selected (rerun of the survivors)",
                     "mutants_total": i["mutants_total"], "annotation_mutants": i["annotation_mutants"],
                     "sampled": i["sampled"],
                     "run": i["killed_before"] + i["survived_before"] + i["incompetent_before"], "killed": killed,
                     "survived": len(surv), "incompetent": i["incompetent_before"] + now_inc,
                     "kill_rate": killed / (killed + len(surv)) if killed + len(surv) else None,
                     "budget_hit": len(res) < i["jobs"],  # survivors the budget left out: neither way, and said
                     "killed_now": now_k, "gone": i["gone"], "rules": {k: sum(r["rule"] == k for r in res)
                                                                        for k in RULES},
                     "mutants": res, "survivors": surv})
    return rows


def package_rows(pkgs: list[str], info: dict, results: list[dict], budget_hit: bool) -> list[dict]:
    """One row per package in ``mutation.py``'s format (its table writer reads them)."""
    rows = []
    for pkg in pkgs:
        res = [r for r in results if r["package"] == pkg]
        killed = sum(r["outcome"] == "killed" for r in res)
        surv = [r for r in res if r["outcome"] == "survived"]
        n_all, n_ann, kept = info[pkg]
        rows.append({"package": pkg, "tests": "coverage-selected", "mutants_total": n_all, "annotation_mutants": n_ann,
                     "sampled": kept, "run": len(res), "killed": killed, "survived": len(surv),
                     "incompetent": sum(r["outcome"] == "incompetent" for r in res),
                     "kill_rate": killed / (killed + len(surv)) if killed + len(surv) else None,
                     "budget_hit": budget_hit and len(res) < kept,
                     "rules": {k: sum(r["rule"] == k for r in res) for k in RULES},
                     "mutants": res, "survivors": surv})
    return rows


HOW = ("each run against the tests of the whole suite that execute its line (coverage.py's per-test contexts; "
       "in a numba-compiled body, every test that runs its package; else its function's lines, else its module's, "
       "else the package's `TARGETS`: "
       "`benchmarks/mutation_select.py`)")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--packages", nargs="+", default=list(PACKAGES), choices=PACKAGES)
    ap.add_argument("--sample", type=int, default=30, help="mutants per package (seeded random sample)")
    ap.add_argument("--seed", type=int, default=29)
    ap.add_argument("--workers", type=int, default=2, help="repository copies run at once")
    ap.add_argument("--budget", type=float, default=180.0, help="minutes for the mutants (the coverage run apart)")
    ap.add_argument("--coverage", metavar="DIR",
                    help="the coverage map's folder: reused when it holds one, else the map is made there and kept "
                         "(without this option it is made in the temporary folder and dropped)")
    ap.add_argument("--rerun", metavar="SURVIVORS.json",
                    help="run only the survivors of an earlier run (its --survivors file) against today's tests, each "
                         "at the occurrence that makes its stored change; the kill rate counts the earlier kills")
    ap.add_argument("--out", default=str(REPO / "benchmarks" / "MUTATION.md"))
    ap.add_argument("--survivors", default=str(REPO / "benchmarks" / "mutation_survivors.json"))
    args = ap.parse_args(argv)
    if shutil.which("cosmic-ray") is None:
        print("mutation_select.py: cosmic-ray is not installed: pip install '.[mutation]'", file=sys.stderr)
        return 2
    for target in (args.out, args.survivors):
        if Path(target).is_dir():
            print(f"mutation_select.py: {target} is a folder, not a file", file=sys.stderr)
            return 2
    started = _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M")
    t_start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="chainid-mutsel-") as tmp:
        shared = REPO.parent / "shared"
        if shared.is_dir():
            (Path(tmp) / "shared").symlink_to(shared)
        pristine = Path(tmp) / "pristine"
        mutation.copy_repo(pristine)
        cov = Path(args.coverage) if args.coverage else Path(tmp) / "coverage"
        if not _has_contexts(cov / ".coverage"):  # a map made before is reused
            coverage_map(pristine, cov)
        sel = Selector(cov, pristine)
        info, jobs = {}, []
        work = Path(tmp) / "init"
        shutil.copytree(pristine, work, symlinks=True)
        if args.rerun:
            jobs, info = rerun_jobs(json.loads(Path(args.rerun).read_text(encoding="utf-8")), args.packages, work,
                                    pristine)
        for pkg in ([] if args.rerun else args.packages):
            muts, n_all, n_ann = sampled_mutants(pkg, work, args.sample, args.seed)
            info[pkg] = (n_all, n_ann, len(muts))
            jobs += [(pkg, m) for m in muts]
        shutil.rmtree(work)
        copies = []
        for i in range(args.workers):
            copies.append(Path(tmp) / f"worker_{i}")
            shutil.copytree(pristine, copies[-1], symlinks=True)
        t0 = time.perf_counter()
        results = run_all(jobs, copies, pristine, sel, args.budget * 60.0)
        hit = time.perf_counter() - t0 > args.budget * 60.0
    rows = rerun_rows(info, results) if args.rerun else package_rows(args.packages, info, results, hit)
    cmd = " ".join(["python benchmarks/mutation_select.py", *(argv if argv is not None else sys.argv[1:])])
    for r in rows:
        r["run_started_utc"], r["command"] = started, cmd
    mutation.write_markdown(rows, args, Path(args.out), started, (time.perf_counter() - t_start) / 60.0, how=HOW)
    atomic_write_text(args.survivors, json.dumps(rows, indent=1) + "\n", force=True)
    return 0


def terminate(signum: int, frame: object) -> None:
    """SIGTERM as SystemExit(128 + signum): the run unwinds, so its temporary folder (the repository copies, the
    coverage map made without --coverage) is removed once the mutants in flight end, as after Ctrl-C."""
    raise SystemExit(128 + signum)


if __name__ == "__main__":
    signal.signal(signal.SIGTERM, terminate)
    sys.exit(main())
