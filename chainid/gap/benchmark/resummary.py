"""The summary of an earlier ``chainid benchmark-gap --json`` run, computed again from its rows (no case is run).

A run of the full grid with resamples takes half an hour; its rates and tables (the confusion, the calibration
of the intervals by effect and by route) are functions of its rows, so a later version of the scoring can print
them again from the file: ``chainid benchmark-gap --summary FILE``; several files (runs of different excitations)
are pooled, each generator's rows as one run's.  The file is the JSON a run wrote: the sim
generator's (``rows`` of benchmark cases), the ODE world's (rows with ``world: "ode"``), or ``--generator
both``'s (``sim`` and ``ode`` apart).
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any, Sequence

__all__ = ["load_runs", "pooled_runs", "summary_text"]


def _rows(part: Any, where: str) -> list[dict[str, Any]]:
    if not isinstance(part, dict) or not isinstance(part.get("rows"), list) or not part["rows"]:
        raise ValueError(f"{where}: no 'rows' (a non-empty list of cases) in it: not the JSON of a "
                         "chainid benchmark-gap run")
    if not all(isinstance(r, dict) for r in part["rows"]):
        raise ValueError(f"{where}: 'rows' holds an entry that is not a case (an object)")
    for r in part["rows"]:  # JSON has no infinity: a case that raised was written with snr inf (a miss) as null
        if r.get("snr") is None and str(r.get("verdict", "")).startswith("error:"):
            r["snr"] = math.inf
    return part["rows"]


def load_runs(path: str | Path) -> dict[str, list[dict[str, Any]]]:
    """The rows of each generator in a ``benchmark-gap --json`` file: ``{"sim": rows}``, ``{"ode": rows}`` or both.

    Raises
    ------
    ValueError
        The file is missing, is not JSON, or holds no rows of a benchmark run (the message names the file).
    """
    p = Path(path)
    if not p.is_file():
        raise ValueError(f"--summary {str(p)!r}: no such file")
    try:
        data = json.loads(p.read_text(encoding="utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ValueError(f"--summary {str(p)!r}: not JSON ({exc})") from None
    if isinstance(data, dict) and data.get("generator") == "both":
        return {g: _rows(data.get(g), f"--summary {str(p)!r}, part {g!r}") for g in ("sim", "ode")}
    rows = _rows(data, f"--summary {str(p)!r}")
    return {"ode" if rows[0].get("world") == "ode" else "sim": rows}


#: the fields that name a benchmark case (its family, truth, conditions, seed and true parameters): a case in two
#: files counts once
CASE_KEYS = ("world", "excitation", "family", "truth", "effects", "levels", "chain", "base", "plan", "noise", "seed",
             "label", "direction", "hold", "ea_scale", "hertz_scale", "true_params")
#: the fields of a row that are its result: one case's rows in two files must agree in them
RESULT_KEYS = ("verdict", "steps", "params", "params_ci90", "shrinkage")


def _case_key(row: dict[str, Any]) -> str:
    return json.dumps({k: row.get(k) for k in CASE_KEYS}, sort_keys=True, default=str)


def _result(row: dict[str, Any]) -> str:
    return json.dumps({k: row.get(k) for k in RESULT_KEYS}, sort_keys=True, default=str)


def pooled_runs(paths: Sequence[str | Path]) -> tuple[dict[str, list[dict[str, Any]]], dict[str, list[str]],
                                                     dict[str, int]]:
    """The rows of several ``benchmark-gap --json`` files, each generator's rows of every file in one list (runs of
    different excitations, or seeds, or of the grid's parts, pooled as one run of them all would have been), for
    each generator the files its rows came from, and how many of its rows were left out as repeats.

    A case (:data:`CASE_KEYS`: family, truth, conditions, seed and true parameters) in more than one file with the
    same result (:data:`RESULT_KEYS`) is one simulation run twice: a copy of a run shares them all, and so do runs
    of two overlapping parts of the grid.  (Runs at different ``--seed`` share no case:
    :mod:`chainid.gap.benchmark.seeds`.)  It counts
    once, so its intervals and verdict are not counted twice.

    Raises
    ------
    ValueError
        A file is named twice; one case has different results in two files (runs of two versions: pool runs of
        one); or a file is refused by :func:`load_runs`.
    """
    seen: dict[Path, str] = {}
    owner: dict[str, tuple[str, str]] = {}
    pooled: dict[str, list[dict[str, Any]]] = {}
    sources: dict[str, list[str]] = {}
    repeats: dict[str, int] = {}
    for path in paths:
        key = Path(path).resolve()
        if key in seen:
            raise ValueError(f"--summary {str(path)!r}: the same file as {seen[key]!r}; each run's cases count once")
        seen[key] = str(path)
        for gen, rows in load_runs(path).items():
            new = []
            for r in rows:
                ck, res = f"{gen}:{_case_key(r)}", _result(r)
                if owner.setdefault(ck, (str(path), res))[0] == str(path):  # a file's own rows all count
                    new.append(r)
                elif owner[ck][1] != res:
                    raise ValueError(f"--summary {str(path)!r}: its case {_case_key(r)} is also in {owner[ck][0]!r} "
                                     "with another result (verdict, parameters or intervals): runs of two versions "
                                     "of the code? Pool the runs of one")
            repeats[gen] = repeats.get(gen, 0) + len(rows) - len(new)
            pooled.setdefault(gen, []).extend(new)
            sources.setdefault(gen, []).append(Path(path).name)
    return pooled, sources, repeats


def summary_text(paths: str | Path | Sequence[str | Path]) -> str:
    """The terminal summary of every generator in the file(s), as a run prints it (without its wall time); the rows
    of several files are pooled per generator (:func:`pooled_runs`)."""
    paths = [paths] if isinstance(paths, (str, Path)) else list(paths)
    pooled, sources, repeats = pooled_runs(paths)
    parts = []
    for gen, rows in pooled.items():
        names = " + ".join(sources[gen])
        if gen == "ode":
            from chainid.gap.benchmark.odescore import format_table, score_row, summarise as ode_summary

            for r in rows:  # scored again by this version
                r["score"] = score_row(r)
            text = format_table(ode_summary(rows))
        else:
            from chainid.gap.benchmark.report import format_summary, summarise

            text = format_summary(summarise(rows))
        again = f"; {repeats[gen]} repeated case(s) counted once" if repeats.get(gen) else ""
        parts.append(f"== generator {gen} ({len(rows)} cases, from {names}{again}) ==\n{text}")
    return "\n\n".join(parts)
