"""From a file's named columns to chainid's records: computed columns, the roles of
:class:`~chainid.records.spec.ReaderSpec` (which column is test, t, x, F), tests split by id or into segments,
units (to s, mm, N), zero offsets and gains, a time axis from ``fs`` or the file's sampling interval, extra
channels and covariates.

Every reader (:mod:`.textread`, :mod:`.formats`) returns :class:`RawTable` objects; :func:`records_from_table`
turns each into :class:`~chainid.records.record.Record` objects, in one place for every format.  The order of the
transformations is the one stated in :mod:`chainid.records.spec` (derive -> split -> units -> zero -> scale).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from chainid.records.derive import evaluate
from chainid.records.plan import ColumnPlan, plan_columns
from chainid.records.readerspec import ROLES, ReaderSpec
from chainid.records.record import Record
from chainid.records.segments import reduce_value, segment_ids, split_points, zero_offset
from chainid.records.units import channel_factor, factor

__all__ = ["RawTable", "resolve_roles", "records_from_table", "id_source"]


@dataclass
class RawTable:
    """The columns of one file (or of one group of a file) before any mapping.

    Attributes
    ----------
    source : str
        File (and group) for messages.
    columns : dict
        Column/channel name -> 1-D array (floats, or strings for a test id / events column), in file order.
    test : str or None
        Test id given by the container (an HDF5/TDMS group, a JSON key); None = from the file name.
    positional : bool
        The names are the 1-based positions "1", "2", ... (a headerless text file).
    roles : dict or None
        Role -> column name when the reader has already resolved them (it read only those columns).
    plan : ColumnPlan or None
        The columns in use, when the reader planned them (text files).
    bad_lines : int
        Data lines left out under ``bad_lines = warn|skip``; ``first_bad`` the first one's message.
    dt_meta : float or None
        The time step [s] the file's metadata state (``Sampling Interval``).
    """

    source: str
    columns: dict[str, np.ndarray] = field(default_factory=dict)
    test: str | None = None
    positional: bool = False
    roles: dict[str, str] | None = None
    plan: ColumnPlan | None = None
    bad_lines: int = 0
    first_bad: str | None = None
    dt_meta: float | None = None


def resolve_roles(names: list[str], spec: ReaderSpec, source: str, positional: bool = False,
                  skip_test: bool = False) -> dict[str, str]:
    """Role -> column name for the roles present (test, t, x, F): the spec's mapping, else a column named like the
    role (see :func:`chainid.records.plan.plan_columns`, which raises the errors)."""
    plan = plan_columns(names, spec, source, positional, skip_test)
    return {r: c for r, c in plan.roles.items() if r in ROLES}


def _numeric(a: Any, source: str, name: str, role: str) -> np.ndarray:
    try:
        arr = a if isinstance(a, np.ndarray) else np.asarray(a)
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"{source}: column {name!r} ({role}) is not numeric") from None
    if arr.dtype.kind in "bc":
        raise ValueError(f"{source}: column {name!r} ({role}) has dtype {arr.dtype} ("
                         f"{'boolean' if arr.dtype.kind == 'b' else 'complex'}); t, x, F and the columns read as "
                         "numbers must be real numbers")
    try:
        v = np.asarray(arr, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"{source}: column {name!r} ({role}) is not numeric") from None
    if v.ndim != 1:
        raise ValueError(f"{source}: column {name!r} ({role}) has shape {v.shape}; expected one dimension")
    bad = np.flatnonzero(~np.isfinite(v))
    if bad.size:
        i = int(bad[0])
        raise ValueError(f"{source}: column {name!r} ({role}) value {float(v[i])!r} at row {i + 1} (of {v.size}) "
                         f"is not finite ({bad.size} such value(s))")
    return v if v.flags.writeable else v.copy()  # zero-copy Arrow/HDF5 views are read-only


def _runs(ids: np.ndarray, size: int, source: str) -> tuple[list[str], list[tuple[int, int]]]:
    """Contiguous runs of a test-id column."""
    ids = np.char.strip(np.asarray(ids).astype(str))
    if ids.size != size:
        raise ValueError(f"{source}: test column has {ids.size} rows, the data {size}")
    change = np.flatnonzero(ids[1:] != ids[:-1]) + 1
    starts = np.concatenate(([0], change))
    ends = np.concatenate((change, [size]))
    run_ids = [str(ids[s]) for s in starts]
    seen: set[str] = set()
    for s, rid in zip(starts, run_ids):
        if not rid:
            raise ValueError(f"{source}: row {s + 1}: empty test id")
        if rid in seen:
            raise ValueError(f"{source}: row {s + 1}: test {rid!r}: rows are not contiguous "
                             "(the test appears again after other tests)")
        seen.add(rid)
    return run_ids, [(int(s), int(e)) for s, e in zip(starts, ends)]


class _Columns:
    """The numbers of one table by key (file columns and computed ones) and their per-segment transformation."""

    def __init__(self, tab: RawTable, spec: ReaderSpec, plan: ColumnPlan) -> None:
        self.spec, self.plan, self.source = spec, plan, tab.source
        role_of = {c: r for r, c in plan.roles.items()}
        self.env: dict[str, np.ndarray] = {c: _numeric(tab.columns[c], tab.source, c, role_of.get(c, "number"))
                                           for c in plan.numeric}
        for d in plan.derived:
            self.env[d.name] = evaluate(d, {s: self.env[plan.symbols[s]] for s in d.symbols}, tab.source)
        n = {k: a.size for k, a in self.env.items()}
        if len(set(n.values())) > 1:
            raise ValueError(f"{tab.source}: columns have different lengths {n}")
        self.size = next(iter(n.values()))
        if self.size == 0:
            raise ValueError(f"{tab.source}: no data rows")

    def values(self, key: str, name: str, s: int, e: int) -> np.ndarray:
        """Column ``key``, rows s..e, in chainid's units: units -> zero -> scale (``name`` = role or channel)."""
        v = self.env[key][s:e]
        unit = self.spec.units.get(name)
        k = factor(name, unit) if name in ("t", "x", "F") else (channel_factor(name, unit)[0] if unit else 1.0)
        if k != 1.0:
            v = v * k
        if name in self.spec.zero:
            v = v - zero_offset(v, self.spec.zero[name], name)
        sc = self.spec.scale.get(name, 1.0)
        return v * sc if sc != 1.0 else v

    def symbol(self, sym: str) -> str:
        return self.plan.symbols.get(sym, sym)


def _segments(tab: RawTable, spec: ReaderSpec, plan: ColumnPlan, cols: _Columns, file_id: str,
              stem: str) -> tuple[list[str], list[tuple[int, int]]]:
    size = cols.size
    if "test" in plan.roles:
        if spec.splits:
            raise ValueError(f"{tab.source}: the file has a test column ({plan.roles['test']!r}); --split-events / "
                             "--split-gap cut files without one")
        return _runs(tab.columns[plan.roles["test"]], size, tab.source)
    if not spec.splits:
        return [tab.test if tab.test is not None else file_id], [(0, size)]
    t = None
    if spec.split_gap is not None:
        if "t" not in plan.roles:
            raise ValueError(f"{tab.source}: --split-gap needs a time column (a file sampled at a constant rate has "
                             "no gaps)")
        t = cols.env[plan.roles["t"]] * factor("t", spec.units.get("t")) * spec.scale.get("t", 1.0)
    ev = tab.columns[plan.roles["events"]] if spec.split_events is not None else None
    bounds = split_points(size, ev, spec.split_events, t, spec.split_gap)
    base = tab.test if tab.test is not None else file_id
    return segment_ids(len(bounds), base, stem, spec, tab.source), bounds


def _check_time_step(t: np.ndarray, dt_meta: float | None, source: str, log: Any) -> None:
    if dt_meta is None or log is None or t.size < 3:
        return
    step = float(np.median(np.diff(t)))
    if step > 0 and not (1 / 1.5 < step / dt_meta < 1.5):
        log.warnings.append(f"file {source!r}: the time column's median step is {step:.4g} s but the file states a "
                            f"sampling interval of {dt_meta:.4g} s ({step / dt_meta:.3g}x): is t in another unit "
                            "(--units t=...)?")


def records_from_table(tab: RawTable, spec: ReaderSpec, file_id: str, stem: str | None = None,
                       log: Any = None) -> list[Record]:
    """The records of one table: computed, mapped, split, converted to s, mm, N, zeroed, scaled.

    Parameters
    ----------
    tab : RawTable
        Columns of one file or group.
    spec : ReaderSpec
        Roles, units, fs, scale, zero, derive, keep, reduce, splits.
    file_id : str
        Test id when the table has no test column and the container gives none (the file stem or the
        ``id_pattern`` group); ``{id}`` of a segment id.
    stem : str or None
        ``{stem}`` of a segment id (default ``file_id``).
    log : object with a ``warnings`` list, optional
        Receives a warning when a time column contradicts the file's stated sampling interval.

    Returns
    -------
    list of Record
        Unvalidated; t [s] from 0 per test and per segment when built from ``fs`` or the file's interval.
    """
    plan = tab.plan or plan_columns(list(tab.columns), spec, tab.source, tab.positional, tab.test is not None,
                                    tab.dt_meta, positions=False)  # a container's columns are named, not numbered
    tab.plan = plan
    cols = _Columns(tab, spec, plan)
    ids, bounds = _segments(tab, spec, plan, cols, file_id, stem or file_id)
    if "t" in plan.roles:
        tt = cols.env[plan.roles["t"]] * (factor("t", spec.units.get("t")) * spec.scale.get("t", 1.0))
        _check_time_step(tt, tab.dt_meta, tab.source, log)
    out = []
    for rid, (s, e) in zip(ids, bounds):
        t = cols.values(plan.roles["t"], "t", s, e) if "t" in plan.roles else np.arange(e - s) * float(plan.dt)
        chans = {c: cols.values(cols.symbol(c), c, s, e) for c in plan.channels}
        covs = {k: reduce_value(cols.values(cols.symbol(sym), sym, s, e), stat)
                for k, (stat, sym) in plan.reduce.items()}
        out.append(Record(rid, t, cols.values(plan.roles["x"], "x", s, e), cols.values(plan.roles["F"], "F", s, e),
                          channels=chans, covariates=covs))
    return out


def id_source(tab: RawTable, spec: ReaderSpec) -> str:
    """Where the test ids of a table came from: ``column`` (a test column), ``segment`` (split files),
    ``container`` (a group or key of the file) or ``file`` (the file name)."""
    roles = tab.plan.roles if tab.plan is not None else (tab.roles or {})
    if "test" in roles:
        return "column"
    if spec.splits:
        return "segment"
    return "container" if tab.test is not None else "file"
