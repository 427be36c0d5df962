"""Rig files as they are written, built in a test's tmp_path, with the numbers they hold (the references).

* :func:`write_daq`: a DAQ logger's text (the MR damper's layout): 6 metadata lines (``Header Size: 7`` counting the
  name line, ``Sampling Interval``), the names ``Sample Number, Date/Time, CHANNEL0, CHANNEL1, Events``, rows of 4
  fields and a 5th ``Events`` field on event rows only (``DAQ Start``, ``DAQ Pause``, ``DAQ Resume``), CRLF.
* :func:`write_seal`: the pneumatic seal rig's logger: tab-separated, no names, 7 columns (t ms, 3 volt channels,
  x mm, p bar, F N).

The returned references are the floats of the text written (``float(f"{v:.4f}")``), so a test compares the reader
with the file's own numbers, parsed independently.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np


def write_daq(path: Path, lengths: list[int], interval: float = 0.005, force_first: bool = True,
              seed: int = 0) -> list[dict[str, np.ndarray]]:
    """Write a ragged DAQ file of ``len(lengths)`` segments; returns per segment the volts written
    (``disp``, ``force``) and the sample numbers."""
    rng = np.random.default_rng(seed)
    n = sum(lengths)
    head = ["Header Size:  7", "Version:  2", f"Sampling Interval:  {interval}", f"Sampling Rate:  {1 / interval:g}",
            f"Sample Count:  {n}", "Device Serial Number:  0", "Sample Number, Date/Time, CHANNEL0, CHANNEL1, Events"]
    rows, out, num = [], [], 0
    for k, m in enumerate(lengths):
        i = np.arange(m)
        disp = -2.99 + 0.1 * (k + 1) * np.sin(2 * math.pi * i / 50.0) * (i > 30) + rng.normal(0, 2e-4, m)
        force = 0.3 * (k + 1) * np.cos(2 * math.pi * i / 50.0) + rng.normal(0, 1e-3, m)
        dv = [float(f"{v:.4f}") for v in disp]
        fv = [float(f"{v:.4f}") for v in force]
        for j in range(m):
            num += 1
            ev = "DAQ Pause" if j == m - 1 else ("DAQ Start" if num == 1 else ("DAQ Resume" if j == 0 else ""))
            c0, c1 = (fv[j], dv[j]) if force_first else (dv[j], fv[j])
            rows.append(f"{num:10d},   04/29/2022 12:11:14.596 PM, {c0:.4f}, {c1:.4f}" + (f", {ev}" if ev else ""))
        out.append({"disp": np.array(dv), "force": np.array(fv), "sample": np.arange(num - m + 1, num + 1)})
    path.write_bytes(("\r\n".join(head + rows) + "\r\n").encode())
    return out


def write_seal(path: Path, n: int = 600, p_bar: float = 3.0, seed: int = 0) -> dict[str, np.ndarray]:
    """Write a seal-rig file (tab-separated, no names); returns the columns written (t_ms, x_mm, p_bar, F_N)."""
    rng = np.random.default_rng(seed)
    i = np.arange(n)
    t = 10.0 * i + np.where(i > n // 2, 290.0, 0.0)  # a 0.3 s gap half way
    x = 17.0 + 21.0 * np.sin(2 * math.pi * i / 150.0)
    p = p_bar + 0.01 * np.cos(2 * math.pi * i / 37.0)
    F = p * 51.875 + 6.0 * np.sign(np.cos(2 * math.pi * i / 150.0)) + rng.normal(0, 0.05, n)
    cols = {"t_ms": t, "x_mm": x, "p_bar": p, "F_N": F}
    ref = {k: np.array([float(f"{v:.3f}") for v in a]) for k, a in cols.items()}
    lines = [f"{a:.3f}\t3.401\t0.499\t1.041\t{b:.3f}\t{c:.3f}\t{d:.3f}"
             for a, b, c, d in zip(t, x, p, F)]
    path.write_bytes(("\r\n".join(lines) + "\r\n").encode())
    return ref
