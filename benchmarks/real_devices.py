"""Diagnose the shared real devices with the commands a user would type, and tabulate what the diagnosis says.

The sets (``$CHAINID_SHARED/realdata`` or ``../shared/realdata``; each folder's SOURCE.md gives the origin and the
licence):

* ``mr``: the MR damper, three tests × five coil currents (raw DAQ text, read with
  ``examples/readers/mr_damper.toml``), the coil current I_A as a covariate, three tests held out;
* ``seal_<type>``: a pneumatic seal at four pressures (``examples/readers/pneumatic_seal.toml``), the pressure p_bar
  as a covariate, the 5 bar test held out;
* ``fd``: the friction damper's harmonic loops, three tests held out (one per frequency, amplitudes spread);
* ``eq``: the friction damper under an earthquake record, the last of four time blocks held out.

Every set is converted with ``chainid convert`` and diagnosed with ``chainid diagnose ... --model linear --json``
(the linear device m·ẍ + c·ẋ + k·x as the base, its mass fitted).  The table gives the verdict, the baseline's and
the verdict's held-out NRMSE, the shrinkage, the fit left (100·(1 − NRMSE)), the residual over the noise floor, how
much of what is left a model-free learner predicts from the state (the open-world check), and the wall time.

Usage::

    python benchmarks/real_devices.py [--sets mr,seal_NAP310,...] [--out DIR] [--markdown benchmarks/RESULTS_real.md]

Nothing is asserted here (tests/gap/test_real_devices.py pins the physics on a subset).
"""

from __future__ import annotations

import argparse
import json
import os
import shlex
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ["CHAINID_SHARED"]) if os.environ.get("CHAINID_SHARED") else REPO.parent / "shared"
REAL = SHARED / "realdata"

CONVERT = {
    "seal.csv": ["convert", str(REAL / "pneumatic-seal" / "*.csv"), "--reader",
                 str(REPO / "examples/readers/pneumatic_seal.toml"), "--to"],
    "mr.csv": ["convert", str(REAL / "mr-damper" / "*.txt"), "--reader", str(REPO / "examples/readers/mr_damper.toml"),
               "--to"],
}


def sets() -> dict[str, list[str]]:
    """The diagnose arguments of every set (the data file first; ``{out}`` is the working folder)."""
    out = {"mr": ["{out}/mr.csv", "--covariates", "{out}/mr.covariates.csv", "--model", "linear", "--holdout",
                   "ME10mm2Hz_i0.5,ME25mm0x25Hz_i0.75,ME2mm5Hz_i0.25"]}
    for s in ("NAP310", "O-ring257", "X-ring257"):
        out[f"seal_{s}"] = ["{out}/seal.csv", "--covariates", "{out}/seal.covariates.csv", "--tests", f"{s}*",
                            "--model", "linear", "--holdout", f"{s}_5bar"]
    fd = REAL / "friction-damper"
    out["fd"] = [str(fd / "brfd_ds2_tension30lb.csv"), "--model", "linear", "--holdout", "f0.25_a1.5,f0.5_a1.0,f1.0_a0.5"]
    out["eq"] = [str(fd / "brfd_ds2_earthquake_imperialvalley.csv"), "--model", "linear", "--holdout-blocks", "4"]
    return out


def _chainid(args: list[str]) -> None:
    subprocess.run([sys.executable, "-c", "import sys; from chainid.cli import main; sys.exit(main())", *args],
                   check=True, stdout=subprocess.DEVNULL)


def run_set(name: str, args: list[str], out: Path) -> dict:
    """Convert what the set needs, diagnose it, and return its row of the table."""
    args = [a.replace("{out}", str(out)) for a in args]
    data = Path(args[0])
    if not data.is_file() and data.name in CONVERT:
        _chainid([*CONVERT[data.name], str(data)])
    js = out / f"{name}.json"
    cmd = ["diagnose", *args, "--json", str(js), "--force"]
    t0 = time.perf_counter()
    _chainid(cmd)
    wall = time.perf_counter() - t0
    r = json.loads(js.read_text())
    b, res, ow = r["baseline"], r.get("residual") or {}, r.get("open_world") or {}
    part = r.get("partial") or {}
    return {"set": name, "command": "chainid " + shlex.join(cmd).replace(str(out) + "/", "").replace(str(REAL), "$REAL"),
            "verdict": r["verdict"], "partial": part.get("effects"), "mechanism": r.get("mechanism"),
            "base": b["nrmse_holdout"], "left": r["left_nrmse_holdout"],
            "shrink": 1 - r["left_nrmse_holdout"] / b["nrmse_holdout"], "fit": r["fit_holdout_pct"],
            "db": res.get("db_over_noise"), "open_world": ow.get("predictable_share"), "wall_s": wall,
            "covariates": [c["text"] for c in r.get("covariate_dependence") or []]}


def markdown(rows: list[dict]) -> str:
    """The table of the rows and the command of each."""
    lines = ["| set | verdict | held-out NRMSE base → left | shrink | fit left | dB over noise | open world | s |",
             "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        v = r["verdict"] + (f" (part: {r['partial']})" if r["partial"] else "")
        ow = "—" if r["open_world"] is None else f"{100 * r['open_world']:.0f} %"
        lines.append(f"| {r['set']} | {v} | {r['base']:.3f} → {r['left']:.3f} | {100 * r['shrink']:.0f} % | "
                     f"{r['fit']:.1f} % | {r['db']:.1f} | {ow} | {r['wall_s']:.0f} |")
    lines += ["", "Operating conditions found:", ""]
    lines += [f"- {r['set']}: {c}" for r in rows for c in r["covariates"]]
    lines += ["", "Commands (`$REAL` = the shared realdata folder; the sets' CSV made by `chainid convert` with the "
              "example readers):", ""]
    lines += [f"- {r['set']}: `{r['command']}`" for r in rows]
    return "\n".join(lines) + "\n"


def provenance() -> str:
    """The run's date (UTC), the repository's commit (``+changes`` when the tree differs from it), the cores, and
    what the table's columns mean."""
    import datetime

    def git(*args: str) -> str:
        try:
            return subprocess.run(["git", *args], cwd=REPO, capture_output=True, text=True, timeout=30).stdout.strip()
        except (OSError, subprocess.SubprocessError):
            return ""

    commit = git("rev-parse", "--short", "HEAD") or "unknown"
    if git("status", "--porcelain", "--untracked-files=no"):
        commit += "+changes"
    when = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    return (f"{when}, commit {commit}, {os.cpu_count()} cores (each run resamples 200×, the CLI's default). Origins "
            "and licences: each set's SOURCE.md in `../shared/realdata/`. \"part\": an unexplained verdict's partial "
            "explanation (passed the step rule, held on the held-out data, closes less than half the gap). \"open "
            "world\": the share of what is left that a model-free learner predicts from the state on the held-out "
            "data.")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sets", default=",".join(sets()), help="comma-separated set names (default: all)")
    ap.add_argument("--out", default="real_devices_out", help="working folder (created; its files are overwritten)")
    ap.add_argument("--markdown", default=None, help="write the table here (e.g. benchmarks/RESULTS_real.md)")
    a = ap.parse_args(argv)
    if not REAL.is_dir():
        print(f"no shared real data at {REAL} (set CHAINID_SHARED)")
        return 2
    todo, known = a.sets.split(","), sets()
    unknown = [s for s in todo if s not in known]
    if unknown:
        ap.error(f"--sets: unknown {unknown}; valid: {','.join(known)}")
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    for s in todo:
        rows.append(run_set(s, known[s], out))
        r = rows[-1]
        print(f"{s}: {r['verdict']} {r['base']:.3f} -> {r['left']:.3f} ({100 * r['shrink']:.0f} %) {r['wall_s']:.0f} s",
              flush=True)
    md = markdown(rows)
    print(md)
    if a.markdown:
        from chainid.infra.fileio import atomic_open

        with atomic_open(a.markdown, force=True, what="--markdown") as fh:
            fh.write("# Real devices: `python benchmarks/real_devices.py --markdown benchmarks/RESULTS_real.md`\n\n"
                     + provenance() + "\n\n" + md)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
