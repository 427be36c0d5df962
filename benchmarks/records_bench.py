"""Records benchmark (issue 13 items 11-12): cost vs record length, peak memory of reading a CSV.

Usage (from the repository root)::

    python benchmarks/records_bench.py            # N = 1e4 .. 2e6 samples, ~200 MB CSV
    python benchmarks/records_bench.py --quick    # N = 1e4 .. 3e5, ~40 MB CSV
    python benchmarks/records_bench.py --json out.json

1. **Analysis time vs N.**  One harmonic test (18 Hz shaker at 10 kHz, 2 % cycle-to-cycle
   amplitude jitter, noise) of N samples; wall time of ``records.analyse_record`` (harmonic
   estimate + adaptive steady selection + validation), median of repeats, against a
   baseline measured in the same run on the same record: one ``numpy.fft.rfft`` of x.
   Prints the scaling exponent (least-squares slope of log time vs log N) of both and the
   time per million samples.  Target: 1e6 samples <= 2 s.
2. **Peak RSS of reading a CSV.**  A long CSV ``test,t,x,F`` (10 tests) of about the
   requested size is written to a temp folder; a fresh subprocess imports chainid, notes its
   RSS, runs ``records.read_records`` (parse only, then with validation, each in its own
   process) and reports the peak RSS (``VmHWM`` after resetting it through
   ``/proc/self/clear_refs`` once chainid is imported, so the import's own transient peak
   does not count; else ``resource.getrusage``).  Reported: file size, peak RSS, increment
   over the after-import RSS, both as multiples of the file size, and bytes per row.
   Target: peak RSS <= 2 x file size.

Every ratio is computed from numbers measured in the same run.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from chainid.records import files as records  # noqa: E402
from timing import PEAK_RSS_AFTER, PEAK_RSS_BEFORE, median_time, run_child  # benchmarks/timing.py (this folder is on sys.path when run)  # noqa: E402


def shaker(n: int, seed: int = 0, f: float = 18.0, fs: float = 10_000.0) -> records.Record:
    """N samples of an 18 Hz test at 10 kHz, amplitude 1 mm +- 2 % per cycle, x0 = 5 mm, noise 2 um."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) / fs
    n_per = int(n / fs * f) + 2
    Ak = 1.0 + 0.02 * rng.standard_normal(n_per)
    env = Ak[np.floor(t * f + 1e-9).astype(int)]
    x = 5.0 + env * np.sin(2 * math.pi * f * t) + rng.normal(0, 2e-3, n)
    F = 20000.0 + 1000.0 * (x - 5.0)
    return records.Record("S", t, x, F)




def bench_scaling(sizes: list[int]) -> dict:
    rows = []
    for n in sizes:
        rec = shaker(n)
        reps = 5 if n <= 100_000 else (3 if n <= 500_000 else 1)

        def run() -> None:
            rec.estimate = None
            records.analyse_record(rec)

        run()  # warm-up (imports, caches)
        t_an = median_time(run, reps)
        t_fft = median_time(lambda: np.fft.rfft(rec.x), max(reps, 3))
        est = records.analyse_record(rec)
        rows.append({"n": n, "analyse_s": t_an, "rfft_s": t_fft, "ratio_to_rfft": t_an / t_fft,
                     "cycles_kept": est.window.n_cycles, "tol": est.window.rel_tol})
        print(f"  N = {n:>9,d}: analyse {t_an * 1e3:9.1f} ms  rfft {t_fft * 1e3:7.2f} ms  "
              f"ratio {t_an / t_fft:7.0f}x  ({t_an / n * 1e6:.2f} s per 1e6 samples; "
              f"{est.window.n_cycles} cycles kept at {100 * est.window.rel_tol:.2g} %)", flush=True)
    ln = np.log([r["n"] for r in rows])
    slope_an = float(np.polyfit(ln, np.log([r["analyse_s"] for r in rows]), 1)[0])
    slope_fft = float(np.polyfit(ln, np.log([r["rfft_s"] for r in rows]), 1)[0])
    print(f"  scaling exponent: analyse {slope_an:.2f}, rfft {slope_fft:.2f} (1 = linear, 2 = quadratic)")
    if 1_000_000 in [r["n"] for r in rows]:
        t1m = next(r["analyse_s"] for r in rows if r["n"] == 1_000_000)
        how = "measured"
    else:  # power-law extrapolation from the two largest sizes
        (n1, a1), (n2, a2) = [(r["n"], r["analyse_s"]) for r in rows[-2:]]
        t1m = a2 * (1e6 / n2) ** (math.log(a2 / a1) / math.log(n2 / n1))
        how = "extrapolated from the two largest N"
    verdict = "PASS" if t1m <= 2.0 else "MISS"
    print(f"  1e6 samples: {t1m:.2f} s ({how}; target <= 2 s): {verdict}")
    return {"rows": rows, "exponent_analyse": slope_an, "exponent_rfft": slope_fft, "t_1e6_s": t1m,
            "target_1e6_s": 2.0, "pass": t1m <= 2.0}


def write_csv(path: Path, target_bytes: int, n_tests: int = 10) -> tuple[int, int]:
    """Write ~target_bytes of ``test,t,x,F`` (n_tests tests); returns (bytes, rows)."""
    row_bytes = 32.4  # bytes per row of this format (measured: 32.4)
    n = max(2000, int(target_bytes / row_bytes / n_tests))
    rows = 0
    with path.open("w") as fh:
        fh.write("test,t,x,F\n")
        for k in range(n_tests):
            r = shaker(n, seed=k)
            block = np.column_stack([r.t, r.x, r.F])
            lines = "\n".join(f"T{k},{a:.9g},{b:.9g},{c:.9g}" for a, b, c in block) + "\n"
            fh.write(lines)
            rows += n
    return path.stat().st_size, rows


_CHILD = r"""
import json, sys, time
sys.path.insert(0, sys.argv[2])
from chainid import records
""" + PEAK_RSS_BEFORE + r"""
t0 = time.perf_counter()
recs = records.read_records(sys.argv[1], validate=sys.argv[3] == "1")
dt = time.perf_counter() - t0
""" + PEAK_RSS_AFTER + r"""
print(json.dumps({"base": base, "peak": peak, "seconds": dt, "tests": len(recs),
                  "samples": sum(r.t.size for r in recs)}))
"""


def _child(path: Path, validate: bool) -> dict:
    return run_child(_CHILD, [str(path), str(ROOT), "1" if validate else "0"], str(ROOT))


def bench_memory(target_mb: float) -> dict:
    with tempfile.TemporaryDirectory() as d:
        p = Path(d) / "big.csv"
        t0 = time.perf_counter()
        size, rows = write_csv(p, int(target_mb * 1e6))
        print(f"  wrote {size / 1e6:.0f} MB, {rows:,d} rows ({size / rows:.1f} bytes/row) "
              f"in {time.perf_counter() - t0:.0f} s", flush=True)
        res: dict = {"file_bytes": size, "rows": rows, "bytes_per_row_file": size / rows,
                     "target_peak_over_file": 2.0}
        for validate in (False, True):
            m = _child(p, validate)
            inc = m["peak"] - m["base"]
            key = "validated" if validate else "parse_only"
            r = {"peak_rss": m["peak"], "rss_after_import": m["base"], "increment": inc,
                 "peak_over_file": m["peak"] / size, "increment_over_file": inc / size,
                 "increment_bytes_per_row": inc / rows, "read_s": m["seconds"], "pass": m["peak"] <= 2.0 * size}
            res[key] = r
            print(f"  read_records({'validate=True' if validate else 'validate=False'}): {m['seconds']:.1f} s "
                  f"({rows / m['seconds'] / 1e6:.2f} M rows/s); peak RSS {m['peak'] / 1e6:.0f} MB = "
                  f"{r['peak_over_file']:.2f} x file; RSS after import {m['base'] / 1e6:.0f} MB, increment "
                  f"{inc / 1e6:.0f} MB = {r['increment_over_file']:.2f} x file = {r['increment_bytes_per_row']:.0f} "
                  f"bytes/row; target peak <= 2 x file: {'PASS' if r['pass'] else 'MISS'}", flush=True)
    return res


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="smaller sizes (N <= 3e5, ~40 MB CSV)")
    ap.add_argument("--mb", type=float, default=None, help="CSV size for the memory test [MB]")
    ap.add_argument("--json", metavar="FILE", help="write the numbers as JSON (refuses to overwrite)")
    args = ap.parse_args(argv)
    if args.json and Path(args.json).exists():
        print(f"error: {args.json!r} exists; refusing to overwrite it", file=sys.stderr)
        return 2
    sizes = [10_000, 30_000, 100_000, 300_000] if args.quick else \
        [10_000, 30_000, 100_000, 300_000, 1_000_000, 2_000_000]
    print("1. analyse_record time vs N (18 Hz at 10 kHz, 2 % amplitude jitter)")
    scal = bench_scaling(sizes)
    mb = args.mb if args.mb is not None else (40.0 if args.quick else 200.0)
    print(f"2. peak RSS of read_records on a ~{mb:.0f} MB CSV (fresh process)")
    mem = bench_memory(mb)
    if args.json:
        tmp = Path(args.json).with_name(Path(args.json).name + ".tmp")
        tmp.write_text(json.dumps({"scaling": scal, "memory": mem}, indent=2) + "\n")
        os.replace(tmp, args.json)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
