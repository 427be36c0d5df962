"""From a file's named columns to chainid's records: the roles of :class:`~chainid.records.spec.ReaderSpec`
(which column is test, t, x, F), units (to s, mm, N), sign factors, a time axis from ``fs``, tests split by id.

Every reader (:mod:`.textread`, :mod:`.formats`) returns :class:`RawTable` objects; :func:`records_from_table`
turns each into :class:`~chainid.records.record.Record` objects, in one place for every format.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from chainid.records.record import Record
from chainid.records.spec import ReaderSpec
from chainid.records.units import factor

__all__ = ["RawTable", "resolve_roles", "records_from_table"]

_ROLE_NAMES = {"test": "test id", "t": "time", "x": "displacement", "F": "force"}


@dataclass
class RawTable:
    """The columns of one file (or of one group of a file) before any mapping.

    Attributes
    ----------
    source : str
        File (and group) for messages.
    columns : dict
        Column/channel name -> 1-D array (floats, or strings for a test id column), in file order.
    test : str or None
        Test id given by the container (an HDF5/TDMS group, a JSON key); None = from the file name.
    positional : bool
        The names are the 1-based positions "1", "2", ... (a headerless text file).
    roles : dict or None
        Role -> column name when the reader has already resolved them (it read only those columns).
    """

    source: str
    columns: dict[str, np.ndarray] = field(default_factory=dict)
    test: str | None = None
    positional: bool = False
    roles: dict[str, str] | None = None


def resolve_roles(names: list[str], spec: ReaderSpec, source: str, positional: bool = False,
                  skip_test: bool = False) -> dict[str, str]:
    """Role -> column name for the roles present: the spec's mapping, else a column named like the role.

    Positions (ints) in ``spec.columns`` are 1-based.  Raises ValueError naming the file, the role, the
    missing name and the columns there are.  ``skip_test``: the container gave the test id.
    """
    out: dict[str, str] = {}
    for role in ("t", "x", "F") if skip_test else ("test", "t", "x", "F"):
        want = spec.columns.get(role)
        if want is None:
            if role in names and not positional:
                out[role] = role
            continue
        if isinstance(want, int):
            if want > len(names):
                raise ValueError(f"{source}: --columns {role}={want}: the file has {len(names)} column(s) "
                                 f"(valid positions 1..{len(names)})")
            out[role] = names[want - 1]
        elif want in names and not positional:
            out[role] = want
        else:
            have = "no header (give 1-based positions, e.g. F=1,x=2)" if positional else f"columns {names}"
            raise ValueError(f"{source}: --columns {role}={want}: no {_ROLE_NAMES[role]} column named {want!r}; "
                             f"the file has {have}")
    for role in ("x", "F"):
        if role not in out:
            have = "no header: give positions, e.g. --columns F=1,x=2" if positional else \
                f"columns {names}: give --columns {role}=NAME"
            raise ValueError(f"{source}: no {_ROLE_NAMES[role]} column {role!r}; the file has {have}")
    if "t" not in out and spec.fs is None:
        have = "no header" if positional else f"columns {names}"
        raise ValueError(f"{source}: no time column 't' ({have}); give --columns t=NAME, or --fs HZ for a file "
                         "sampled at a constant rate")
    if "t" in out and spec.fs is not None:
        raise ValueError(f"{source}: both a time column ({out['t']!r}) and --fs {spec.fs:g} Hz; give one of them")
    used = [v for v in out.values()]
    dup = sorted({v for v in used if used.count(v) > 1})
    if dup:
        raise ValueError(f"{source}: column(s) {dup} mapped to more than one role ({out})")
    return out


def _numeric(a: np.ndarray, source: str, name: str, role: str) -> np.ndarray:
    try:
        v = np.asarray(a, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{source}: column {name!r} ({role}) is not numeric") from None
    if v.ndim != 1:
        raise ValueError(f"{source}: column {name!r} ({role}) has shape {v.shape}; expected one dimension")
    bad = np.flatnonzero(~np.isfinite(v))
    if bad.size:
        i = int(bad[0])
        raise ValueError(f"{source}: column {name!r} ({role}) value {float(v[i])!r} at row {i + 1} (of {v.size}) "
                         f"is not finite ({bad.size} such value(s))")
    return v if v.flags.writeable else v.copy()  # zero-copy Arrow/HDF5 views are read-only


def records_from_table(tab: RawTable, spec: ReaderSpec, file_id: str) -> list[Record]:
    """The records of one table: mapped, converted to s, mm, N, scaled, split by test id.

    Parameters
    ----------
    tab : RawTable
        Columns of one file or group.
    spec : ReaderSpec
        Roles, units, fs, scale.
    file_id : str
        Test id when the table has no test column and the container gives none (the file stem or the
        ``id_pattern`` group).

    Returns
    -------
    list of Record
        Unvalidated; t [s] from 0 per test when built from ``fs``.
    """
    names = list(tab.columns)
    roles = tab.roles if tab.roles is not None else resolve_roles(names, spec, tab.source, tab.positional,
                                                                         tab.test is not None)
    data = {}
    for role in ("t", "x", "F"):
        if role in roles:
            v = _numeric(tab.columns[roles[role]], tab.source, roles[role], role)
            k = factor(role, spec.units.get(role)) * spec.scale.get(role, 1.0)
            data[role] = v * k if k != 1.0 else v
    n = {r: a.size for r, a in data.items()}
    if len(set(n.values())) > 1:
        raise ValueError(f"{tab.source}: columns have different lengths {n}")
    size = next(iter(n.values()))
    if size == 0:
        raise ValueError(f"{tab.source}: no data rows")
    if "test" in roles:
        ids = np.asarray(tab.columns[roles["test"]]).astype(str)
        if ids.size != size:
            raise ValueError(f"{tab.source}: test column has {ids.size} rows, the data {size}")
        ids = np.char.strip(ids)
        change = np.flatnonzero(ids[1:] != ids[:-1]) + 1
        starts = np.concatenate(([0], change))
        ends = np.concatenate((change, [size]))
        run_ids = [str(ids[s]) for s in starts]
        seen: set[str] = set()
        for s, rid in zip(starts, run_ids):
            if not rid:
                raise ValueError(f"{tab.source}: row {s + 1}: empty test id")
            if rid in seen:
                raise ValueError(f"{tab.source}: row {s + 1}: test {rid!r}: rows are not contiguous "
                                 "(the test appears again after other tests)")
            seen.add(rid)
    else:
        starts, ends, run_ids = np.array([0]), np.array([size]), [tab.test if tab.test is not None else file_id]
    out = []
    for rid, s, e in zip(run_ids, starts, ends):
        s, e = int(s), int(e)
        t = data["t"][s:e] if "t" in data else np.arange(e - s) / float(spec.fs)  # type: ignore[arg-type]
        out.append(Record(rid, t, data["x"][s:e], data["F"][s:e]))
    return out
