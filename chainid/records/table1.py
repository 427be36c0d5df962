"""The paper's Table 1: the nine harmonic tests' identified c_e, as shipped in ``chainid/data/table1.csv``."""
from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

__all__ = ["load_table1"]

def load_table1() -> dict[str, np.ndarray]:
    """Table 1 as shipped in ``chainid/data/table1.csv``.

    Returns
    -------
    dict of ndarray
        ``test`` (int), ``omega_col`` (the printed "omega / rad/s" column, see the
        file header for the unit question), ``x0`` [mm], ``A`` [mm], ``F_ac`` [N],
        ``c_e`` [N·s/mm].
    """
    text = (Path(__file__).resolve().parents[1] / "data" / "table1.csv").read_text()
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
    rows = list(csv.DictReader(lines))
    out = {k: np.array([float(r[k]) for r in rows]) for k in ("omega_col", "x0", "A", "F_ac", "c_e")}
    out["test"] = np.array([int(r["test"]) for r in rows])
    return out
