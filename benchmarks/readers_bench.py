"""Reading and writing the canonical records CSV: the new reader/writer against today's (issue 19).

Usage (from the repository root)::

    python benchmarks/readers_bench.py                # 1e7 rows (10 tests x 1e6), ~330 MB CSV
    python benchmarks/readers_bench.py --rows 1000000 # quicker

* **Write.**  The same records (10 tests, an 18 Hz shaker at 10 kHz) written by the row-by-row writer that
  ``write_records`` used before issue 19 (kept below as ``legacy_write``: one f-string per row, ``%.9g``) and
  by :func:`chainid.records.writer.write_canonical` (exact round-trip text) on each of its paths: the default
  (polars if installed, ``chainid[fast]``), chainid's numba kernel, pyarrow's writer.  Wall and CPU, ratios.
* **Read.**  The legacy-written file read by today's row-by-row reader (``read_csv_strict``, which is the old
  ``read_records(validate=False)`` loop, kept as the fallback) and by the new ``read_records(validate=False)``,
  each in a fresh process: wall time, ratio, and peak RSS (``VmHWM`` reset after the imports through
  ``/proc/self/clear_refs``) over the file size.  Targets: >= 10x faster, peak RSS <= 2x the file.

Each number is the median of ``--repeat`` runs (default 3; reads in fresh processes).  Every ratio is computed
from numbers measured in the same run.

**Ragged DAQ text** (``--daq MB``, only this part): a DAQ file as the MR damper's logger writes it (6 metadata
lines, the names ``Sample Number, Date/Time, CHANNEL0, CHANNEL1, Events``, rows of 4 fields and a 5th ``Events``
field on event rows only: ``DAQ Start``, ``DAQ Pause`` every 10 000 rows) read with the MR reader profile (header
block, ragged rows, split at the events, zero offset, gains, t from the sampling interval) against a clean CSV of
the same rows (4 fields each, one name line, ``--fs``) read by the same ``read_any``: wall and CPU, peak RSS, and
the ratio clean/ragged time (target >= 0.5 at 1 GB)::

    python benchmarks/readers_bench.py --daq 1000      # two ~1 GB files
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from chainid.records.record import Record  # noqa: E402
from chainid.records.writer import write_canonical  # noqa: E402
from timing import PEAK_RSS_AFTER, PEAK_RSS_BEFORE, run_child  # benchmarks/timing.py  # noqa: E402


def shaker(test: str, n: int, seed: int) -> Record:
    rng = np.random.default_rng(seed)
    t = np.arange(n) / 10_000.0
    x = 5.0 + np.sin(2 * np.pi * 18.0 * t) + rng.normal(0, 2e-3, n)
    return Record(test, t, x, 20000.0 + 1000.0 * (x - 5.0))


def legacy_write(path: Path, records: list[Record]) -> None:
    """The pre-issue-19 ``write_records`` loop (one f-string per row)."""
    with path.open("w", newline="") as fh:
        fh.write("test,t,x,F\n")
        for r in records:
            for ti, xi, Fi in zip(r.t, r.x, r.F):
                fh.write(f"{r.test},{ti:.9g},{xi:.9g},{Fi:.9g}\n")


_CHILD = r"""
import json, sys, time
sys.path.insert(0, sys.argv[1])
from chainid.records import files, textcanon
import pyarrow.csv  # imported before the peak reset in both runs (its import is not reading)
""" + PEAK_RSS_BEFORE + r"""
t0, c0 = time.perf_counter(), time.process_time()
if sys.argv[3] == "legacy":
    recs = textcanon.read_csv_strict(sys.argv[2])
else:
    recs = files.read_records(sys.argv[2], validate=False)
dt, cpu = time.perf_counter() - t0, time.process_time() - c0
""" + PEAK_RSS_AFTER + r"""
print(json.dumps({"base": base, "peak": peak, "seconds": dt, "cpu_seconds": cpu, "rows": sum(r.t.size for r in recs),
                  "checksum": float(sum(float(r.F.sum()) for r in recs))}))
"""


def read_in_child(path: Path, which: str) -> dict:
    return run_child(_CHILD, [str(ROOT), str(path), which], str(ROOT))


_DAQ_CHILD = r"""
import json, sys, time
sys.path.insert(0, sys.argv[1])
from chainid.records.reader import read_any
from chainid.records.spec import spec_from_options
import pyarrow.csv
""" + PEAK_RSS_BEFORE + r"""
if sys.argv[3] == "ragged":
    spec = spec_from_options(skip_rows=6, columns="x=CHANNEL1,F=CHANNEL0", split_events="DAQ Pause",
                             zero="x=first:20", scale="x=10,F=980.665")
else:
    spec = spec_from_options(columns="x=CHANNEL1,F=CHANNEL0", fs=200.0, scale="x=10,F=980.665")
t0, c0 = time.perf_counter(), time.process_time()
recs = read_any(sys.argv[2], spec)
dt, cpu = time.perf_counter() - t0, time.process_time() - c0
""" + PEAK_RSS_AFTER + r"""
print(json.dumps({"base": base, "peak": peak, "seconds": dt, "cpu_seconds": cpu, "tests": len(recs),
                  "rows": sum(r.t.size for r in recs), "checksum": float(sum(float(r.F.sum()) for r in recs))}))
"""


def write_daq(path: Path, clean: Path, mb: float) -> int:
    """A ragged DAQ file of about ``mb`` MB and the clean CSV of the same rows; returns the rows."""
    rng = np.random.default_rng(7)
    n_blk = 10_000
    i = np.arange(n_blk)
    v_x = -2.99 + 0.1 * np.sin(2 * np.pi * i / 200.0) + rng.normal(0, 1e-4, n_blk)
    v_f = 0.8 * np.cos(2 * np.pi * i / 200.0) + rng.normal(0, 1e-3, n_blk)
    rows = [f"{k + 1:10d},   04/29/2022 12:11:14.596 PM, {a:.4f}, {b:.4f}" for k, a, b in zip(i, v_f, v_x)]
    body = "\r\n".join(rows[:-1]) + "\r\n" + rows[-1] + ", DAQ Pause\r\n"
    first = rows[0] + ", DAQ Start\r\n" + "\r\n".join(rows[1:-1]) + "\r\n" + rows[-1] + ", DAQ Pause\r\n"
    clean_body = "\r\n".join(rows) + "\r\n"
    n = max(1, int(mb * 1e6 / len(body)))
    head = ("Header Size:  7\r\nVersion:  2\r\nSampling Interval:  0.005\r\nSampling Rate:  200\r\n"
            f"Sample Count:  {n * n_blk}\r\nDevice Serial Number:  0\r\n"
            "Sample Number, Date/Time, CHANNEL0, CHANNEL1, Events\r\n")
    with path.open("w", newline="") as fh:
        fh.write(head + first)
        for _ in range(n - 1):
            fh.write(body)
    with clean.open("w", newline="") as fh:
        fh.write("Sample Number,Date/Time,CHANNEL0,CHANNEL1\r\n")
        for _ in range(n):
            fh.write(clean_body)
    return n * n_blk


def daq_main(mb: float, repeat: int) -> dict:
    """The ragged-DAQ part (see the module docstring)."""
    res: dict = {}
    with tempfile.TemporaryDirectory(dir=os.environ.get("TMPDIR")) as d:
        ragged, clean = Path(d) / "daq.txt", Path(d) / "clean.csv"
        rows = write_daq(ragged, clean, mb)
        for which, path in (("clean", clean), ("ragged", ragged)):
            ms = [run_child(_DAQ_CHILD, [str(ROOT), str(path), which], str(ROOT)) for _ in range(repeat)]
            m = {k: float(np.median([x[k] for x in ms])) for k in ms[0]}
            size = path.stat().st_size
            res[which] = {**m, "file_bytes": size, "peak_over_file": m["peak"] / size,
                          "mb_per_s": size / 1e6 / m["seconds"]}
            print(f"read the {which} file ({size / 1e6:.0f} MB, {rows:,d} rows, {int(m['tests'])} test(s)): "
                  f"{m['seconds']:.2f} s wall / {m['cpu_seconds']:.2f} s CPU ({size / 1e6 / m['seconds']:.0f} MB/s), "
                  f"peak RSS {m['peak'] / size:.2f}x the file", flush=True)
        sp = res["clean"]["seconds"] / res["ragged"]["seconds"]
        cp = res["clean"]["cpu_seconds"] / res["ragged"]["cpu_seconds"]
        res["ratio_wall"], res["ratio_cpu"] = sp, cp
        print(f"ragged DAQ speed / clean CSV speed: {sp:.2f} wall, {cp:.2f} CPU (target >= 0.5: "
              f"{'PASS' if sp >= 0.5 else 'MISS'})")
    return res


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rows", type=int, default=10_000_000, help="total rows (10 tests)")
    ap.add_argument("--daq", type=float, metavar="MB", help="only the ragged-DAQ comparison, files of about MB MB")
    ap.add_argument("--repeat", type=int, default=3, help="runs of each measurement (median; default 3)")
    ap.add_argument("--json", metavar="FILE", help="write the numbers as JSON (refuses to overwrite)")
    args = ap.parse_args(argv)
    if args.json and Path(args.json).exists():
        print(f"error: {args.json!r} exists; refusing to overwrite it", file=sys.stderr)
        return 2
    if args.daq:
        res = daq_main(args.daq, args.repeat)
        if args.json:
            Path(args.json).write_text(json.dumps(res, indent=2) + "\n")
        return 0
    recs = [shaker(f"T{k}", args.rows // 10, k) for k in range(10)]
    rows = sum(r.t.size for r in recs)
    res: dict = {"rows": rows}
    with tempfile.TemporaryDirectory(dir=os.environ.get("TMPDIR")) as d:
        old, new = Path(d) / "legacy.csv", Path(d) / "new.csv"
        def timed(fn) -> tuple[float, float]:
            runs = []
            for _ in range(args.repeat):
                t0, c0 = time.perf_counter(), time.process_time()
                fn()
                runs.append((time.perf_counter() - t0, time.process_time() - c0))
            return float(np.median([r[0] for r in runs])), float(np.median([r[1] for r in runs]))

        from chainid.infra import floattext
        from chainid.records import writer

        write_canonical(new, recs[:1], overwrite=True)  # warm-up: the kernel's compilation (cached) is not writing
        list(floattext.csv_chunks(b"", [np.zeros(1)]))
        t_old, c_old = timed(lambda: legacy_write(old, recs))
        paths = {}
        for name, patch in (("kernel", (writer, "_polars", lambda: None)),
                            ("pyarrow", (floattext, "jit_enabled", lambda: False))):
            saved = getattr(patch[0], patch[1])
            setattr(patch[0], patch[1], patch[2])
            try:
                tw, cw = timed(lambda: write_canonical(new, recs, overwrite=True))
            finally:
                setattr(patch[0], patch[1], saved)
            paths[name] = {"s": tw, "cpu_s": cw, "speedup": t_old / tw, "cpu_ratio": c_old / cw}
            print(f"  write path {name}: {tw:.1f} s wall / {cw:.1f} s CPU: {t_old / tw:.1f}x wall, "
                  f"{c_old / cw:.1f}x CPU", flush=True)
        t_new, c_new = timed(lambda: write_canonical(new, recs, overwrite=True))
        size_old, size_new = old.stat().st_size, new.stat().st_size
        res["write"] = {"legacy_s": t_old, "new_s": t_new, "speedup": t_old / t_new, "legacy_cpu_s": c_old,
                        "new_cpu_s": c_new, "legacy_bytes": size_old, "new_bytes": size_new,
                        "default_path": "polars" if writer._polars() is not None else "kernel", "paths": paths}
        print(f"write {rows:,d} rows: legacy {t_old:.1f} s wall / {c_old:.1f} s CPU ({size_old / 1e6:.0f} MB), new "
              f"{t_new:.1f} s wall / {c_new:.1f} s CPU ({size_new / 1e6:.0f} MB): {t_old / t_new:.1f}x faster wall, "
              f"{c_old / c_new:.1f}x less CPU (default path: {res['write']['default_path']}; target >= 10x: wall "
              f"{'PASS' if t_old / t_new >= 10 else 'MISS'}, CPU {'PASS' if c_old / c_new >= 10 else 'MISS'})",
              flush=True)
        del recs
        for which, path in (("legacy", old), ("new", old), ("new", new)):
            ms = [read_in_child(path, which) for _ in range(args.repeat)]
            m = {k: float(np.median([x[k] for x in ms])) for k in ms[0]}  # median of fresh processes
            size = path.stat().st_size
            key = f"read_{which}_{path.stem}"
            res[key] = {**m, "file_bytes": size, "peak_over_file": m["peak"] / size,
                        "increment_over_file": (m["peak"] - m["base"]) / size}
            print(f"read {path.name} ({size / 1e6:.0f} MB) with the {which} reader: {m['seconds']:.1f} s wall / "
                  f"{m['cpu_seconds']:.1f} s CPU, peak RSS "
                  f"{m['peak'] / 1e6:.0f} MB = {m['peak'] / size:.2f}x the file (increment "
                  f"{(m['peak'] - m['base']) / 1e6:.0f} MB = {(m['peak'] - m['base']) / size:.2f}x); "
                  f"checksum {m['checksum']:.6e}", flush=True)
        sp = res["read_legacy_legacy"]["seconds"] / res["read_new_legacy"]["seconds"]
        res["read_speedup"] = sp
        res["read_cpu_ratio"] = res["read_legacy_legacy"]["cpu_seconds"] / res["read_new_legacy"]["cpu_seconds"]
        pk = res["read_new_legacy"]["peak_over_file"]
        print(f"read speed-up on the same file: {sp:.1f}x wall, {res['read_cpu_ratio']:.1f}x less CPU (target >= 10x: {'PASS' if sp >= 10 else 'MISS'}); "
              f"new reader peak RSS {pk:.2f}x the file (target <= 2x: {'PASS' if pk <= 2 else 'MISS'})")
    if args.json:
        tmp = Path(args.json).with_name(Path(args.json).name + ".tmp")
        tmp.write_text(json.dumps(res, indent=2) + "\n")
        os.replace(tmp, args.json)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
