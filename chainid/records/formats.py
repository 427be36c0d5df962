"""Record files other than delimited text: JSON arrays, MATLAB ``.mat`` (v7.3 through h5py), HDF5, LabVIEW TDMS,
Parquet.  Each becomes one or more :class:`~chainid.records.table.RawTable` (one per test).

Containers are searched for the columns a spec needs (``x`` and ``F``, by their mapped names): the variables /
datasets / channels at the top level form one table; otherwise every group (HDF5 group, TDMS group, MATLAB
struct, JSON object or list item) that holds them is one test, named by the group (a single group takes the
file's test id).  A name may be a path, ``run1/force``.

h5py and npTDMS are optional (``pip install "chainid[formats]"``); a missing one is a one-line error naming the
extra.  Parquet uses pyarrow, a dependency of chainid.

Safety: the size the file declares for the columns read (HDF5 dataset shapes, Parquet row counts, MAT variable
shapes, TDMS channel lengths, a JSON file's size) is checked before anything is read: reading needs about twice
their float64 size, refused with one error when that exceeds the memory available (:func:`check_memory`).  An HDF5
external link (to another file) or dangling link, a JSON integer beyond the float range, and JSON nested deeper
than :data:`MAX_DEPTH` are one error each; boolean or complex columns are refused by :mod:`.table`.
"""
from __future__ import annotations

import importlib
import json
import math
import os
from pathlib import Path
from typing import Any, Callable, Mapping

import numpy as np

from chainid.records.spec import ReaderSpec
from chainid.records.table import RawTable

__all__ = ["SUFFIXES", "MAX_DEPTH", "format_of", "optional_module", "available_memory", "check_memory",
           "read_container"]

#: File suffix -> format.
SUFFIXES = {".json": "json", ".mat": "mat", ".h5": "hdf5", ".hdf5": "hdf5", ".hdf": "hdf5", ".he5": "hdf5",
            ".tdms": "tdms", ".parquet": "parquet", ".pq": "parquet"}
_EXTRA = 'pip install "chainid[formats]"'
#: Deepest nesting of groups searched (and of JSON accepted).
MAX_DEPTH = 64


def available_memory() -> int:
    """Bytes of memory available to this process now (``MemAvailable`` of /proc/meminfo, else the free pages)."""
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return int(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):  # pragma: no cover - no way to know: do not refuse
        return 1 << 62


def check_memory(n_values: int, source: str, what: str) -> None:
    """Refuse reading ``n_values`` numbers when about twice their float64 size exceeds the memory available.

    Raises
    ------
    ValueError
        Naming the file, what declared the size, the bytes needed and available.
    """
    need = 2 * 8 * int(n_values)
    have = available_memory()
    if need > have:
        raise ValueError(f"{source}: {what} declares {n_values:,d} values; reading them needs about "
                         f"{need / 2**30:.3g} GiB, over the {have / 2**30:.3g} GiB of memory available: refusing to "
                         "read (a corrupt size, or split the file)")


def format_of(path: Path, spec: ReaderSpec) -> str:
    """The format of a file: ``spec.format``, else by suffix (anything else is text)."""
    return spec.format or SUFFIXES.get(path.suffix.lower(), "text")


def optional_module(name: str, what: str, install: str = _EXTRA) -> Any:
    """Import an optional reader, or a one-line ValueError naming what to install (default the extra)."""
    try:
        return importlib.import_module(name)
    except ImportError:
        raise ValueError(f"reading {what} needs the Python package {name.split('.')[0]!r}, which is not installed: "
                         f"{install}") from None


def _is_group(v: Any) -> bool:
    return isinstance(v, Mapping) or (hasattr(v, "keys") and not hasattr(v, "shape"))


def _child(node: Any, key: str, where: str) -> Any:
    """``node[key]``, refusing HDF5 external links (another file) and naming a dangling link."""
    get = getattr(node, "get", None)
    if get is not None and hasattr(node, "file"):  # an h5py group: look at the link before following it
        link = get(key, getlink=True)
        kind = type(link).__name__
        if kind == "ExternalLink":
            raise ValueError(f"{where}/{key}: an HDF5 external link to {link.filename!r}:{link.path!r}; chainid reads "
                             "only the file given (copy the data into it)")
        try:
            return node[key]
        except (KeyError, OSError, ValueError) as exc:
            target = getattr(link, "path", "?")
            raise ValueError(f"{where}/{key}: a dangling HDF5 link (to {target!r}): {exc}") from None
    return node[key]


def _get(obj: Any, name: str, where: str = "") -> Any:
    cur = obj
    for part in (p for p in name.split("/") if p):
        if not _is_group(cur) or part not in cur.keys():
            return None
        cur = _child(cur, part, where)
        where = f"{where}/{part}"
    return None if _is_group(cur) else cur


def _raw(name: str, spec: ReaderSpec, seen: frozenset = frozenset()) -> list[str]:
    """The stored names a column needs: itself, or the inputs of its expression when it is computed."""
    if name not in spec.derive:
        return [name]
    if name in seen:
        return []
    from chainid.records.derive import parse_derived

    out: list[str] = []
    for sym in parse_derived(name, spec.derive[name]).symbols:
        out += [n for n in _raw(sym, spec, seen | {name}) if n not in out]
    return out


def _wanted(spec: ReaderSpec, source: str) -> tuple[dict[str, str], list[str], list[str]]:
    """Role -> stored name, the anchors a table must hold (x's and F's inputs), and every stored name needed."""
    from chainid.records.readerspec import parse_reduce

    roles: dict[str, str] = {}
    for role in ("test", "t", "x", "F") + (("events",) if spec.split_events else ()):
        name = spec.columns.get(role, role if role != "events" else "Events")
        if isinstance(name, int):
            raise ValueError(f"{source}: --columns {role}={name}: positions are for headerless text files; "
                             "give the variable/dataset/channel name")
        roles[role] = name
    anchors = _raw(roles["x"], spec) + [n for n in _raw(roles["F"], spec) if n not in _raw(roles["x"], spec)]
    need: list[str] = []
    for n in [*roles.values(), *spec.keep, *(parse_reduce(v)[1] for v in spec.reduce.values())]:
        need += [m for m in _raw(n, spec) if m not in need]
    return roles, anchors, need


def _tables(obj: Any, source: str, spec: ReaderSpec, file_id: str, keyed: bool) -> list[RawTable]:
    """Tables of a nested container (dicts / lists of dicts / h5py groups)."""
    roles, anchors, need = _wanted(spec, source)

    def walk(node: Any, where: str, key: str | None, depth: int) -> list[tuple[str | None, str, dict]]:
        if depth > MAX_DEPTH:
            raise ValueError(f"{where}: groups nested deeper than {MAX_DEPTH} levels")
        if isinstance(node, list) and node and all(_is_group(v) for v in node):
            out = []
            for i, v in enumerate(node):
                out += walk(v, f"{where}[{i}]", f"{file_id}_{i + 1}", depth + 1)
            return out
        if not _is_group(node):
            return []
        if all(_get(node, a, where) is not None for a in anchors):
            cols = {n: v for n in need if (v := _get(node, n, where)) is not None}
            return [(key, where, cols)]
        out = []
        for k in node.keys():
            out += walk(_child(node, k, where), f"{where}/{k}", str(k), depth + 1)
        return out

    found = walk(obj, source, None, 0)
    if not found:
        top = list(obj.keys()) if _is_group(obj) else f"a {type(obj).__name__}"
        names = " and ".join(repr(a) for a in anchors)
        raise ValueError(f"{source}: no {names} columns found (top level: {top}); name them with --columns "
                         "x=NAME,F=NAME")
    tabs = []
    for key, where, cols in found:
        test = None
        tcol = cols.get(roles["test"])
        if tcol is not None and np.ndim(tcol) == 0:  # a scalar id beside the arrays
            test = str(np.asarray(tcol).item() if not isinstance(tcol, str) else tcol)
            cols.pop(roles["test"])
        elif len(found) > 1 or keyed:
            test = key
        tabs.append(RawTable(where, cols, test))
    return tabs


def _big_int(text: str) -> float:
    v = float(text)
    if not math.isfinite(v):
        raise ValueError(f"a JSON integer of {len(text)} digits ({text[:20]}...) is beyond the float range")
    return v


def _json(path: Path) -> Any:
    check_memory(path.stat().st_size // 2, str(path), "the JSON file's size")  # ~ a number per 4 bytes, 3 copies
    try:
        with path.open(encoding="utf-8-sig") as fh:
            return json.load(fh, parse_int=_big_int)
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path}: not a JSON file ({exc})") from None
    except ValueError as exc:
        raise ValueError(f"{path}: {exc}") from None
    except RecursionError:
        raise ValueError(f"{path}: JSON nested too deeply (more than Python's recursion limit); records are "
                         f"at most {MAX_DEPTH} levels deep") from None


def _mat(path: Path) -> Any:
    import scipy.io

    try:
        sizes = [math.prod(shape) for _, shape, _ in scipy.io.whosmat(str(path))]
    except Exception:  # v7.3 (HDF5: sizes checked from the datasets) or corrupt (loadmat says so below)
        sizes = []
    check_memory(sum(sizes), str(path), "the MAT file's variables")
    try:
        doc = scipy.io.loadmat(str(path), squeeze_me=True, simplify_cells=True)
    except NotImplementedError:  # MATLAB v7.3 files are HDF5
        h5py = optional_module("h5py", f"{path} (a MATLAB v7.3 file)")
        try:
            return h5py.File(path, "r")  # vectors are (1, N) datasets: squeezed when read
        except OSError as exc:
            raise ValueError(f"{path}: not a readable MATLAB v7.3 file ({exc})") from None
    except Exception as exc:  # scipy's readers raise many types on a corrupt file: one line, no traceback
        raise ValueError(f"{path}: not a readable MATLAB .mat file ({exc})") from None
    return {k: v for k, v in doc.items() if not k.startswith("__")}


def _hdf5(path: Path) -> Any:
    h5py = optional_module("h5py", f"{path} (HDF5)")
    try:
        return h5py.File(path, "r")
    except OSError as exc:
        raise ValueError(f"{path}: not a readable HDF5 file ({exc})") from None


def _tdms(path: Path) -> Any:
    nptdms = optional_module("nptdms", f"{path} (LabVIEW TDMS)")
    try:
        meta = nptdms.TdmsFile.read_metadata(str(path))
        n = sum(len(c) for g in meta.groups() for c in g.channels())
    except Exception as exc:  # npTDMS raises many types on a corrupt file: one line, no traceback
        raise ValueError(f"{path}: not a readable TDMS file ({exc})") from None
    check_memory(n, str(path), "the TDMS file's channels")
    try:
        f = nptdms.TdmsFile.read(str(path))
    except Exception as exc:  # npTDMS raises many types on a corrupt file: one line, no traceback
        raise ValueError(f"{path}: not a readable TDMS file ({exc})") from None
    return {g.name: {c.name: c[:] for c in g.channels()} for g in f.groups()}


class _ParquetColumn:
    """One column of a Parquet file, read when converted to an array (its size is known from the metadata)."""

    def __init__(self, path: Path, name: str, n: int) -> None:
        self.path, self.name, self.shape, self.ndim = path, name, (n,), 1

    def __array__(self, dtype: Any = None, copy: Any = None) -> np.ndarray:
        import pyarrow.parquet as pq

        try:
            a = pq.read_table(self.path, columns=[self.name]).column(self.name).to_numpy()
        except Exception as exc:  # pyarrow raises its own error types
            raise ValueError(f"{self.path}: column {self.name!r} cannot be read ({exc})") from None
        return a if dtype is None else a.astype(dtype)


def _parquet(path: Path) -> Any:
    pq = optional_module("pyarrow.parquet", f"{path} (Parquet)", "pip install pyarrow (a dependency of chainid)")
    try:
        with pq.ParquetFile(path) as f:
            n, names = f.metadata.num_rows, f.schema_arrow.names
    except Exception as exc:  # pyarrow raises its own error types
        raise ValueError(f"{path}: not a readable Parquet file ({exc})") from None
    return {name: _ParquetColumn(path, name, n) for name in names}


_OPENERS: dict[str, Callable[[Path], Any]] = {"json": _json, "mat": _mat, "hdf5": _hdf5, "tdms": _tdms,
                                               "parquet": _parquet}


def _squeeze(a: np.ndarray) -> np.ndarray:
    """A (1, N) or (N, 1) array (MATLAB vectors) as (N,); anything else unchanged."""
    return a.ravel() if a.ndim == 2 and 1 in a.shape else a


def read_container(path: Path, fmt: str, spec: ReaderSpec, file_id: str) -> list[RawTable]:
    """The tables of one non-text file.

    Parameters
    ----------
    path : Path
        The file.
    fmt : str
        ``json``, ``mat``, ``hdf5``, ``tdms`` or ``parquet``.
    spec : ReaderSpec
        Column names of the roles (positions are refused: they are for headerless text).
    file_id : str
        The file's test id (stem or ``--id-pattern`` group).
    """
    obj = _OPENERS[fmt](path)
    try:
        keyed = fmt == "json" and isinstance(obj, dict) and all(_is_group(v) for v in obj.values())
        tabs = _tables(obj, str(path), spec, file_id, keyed)
        lazy = sum(math.prod(v.shape) for tab in tabs for v in tab.columns.values()
                   if hasattr(v, "shape") and not isinstance(v, np.ndarray))
        check_memory(lazy, str(path), "the file's datasets")
        for tab in tabs:  # read lazily opened datasets now (before the file closes)
            tab.columns = {k: (_squeeze(np.asarray(v)) if not isinstance(v, list) else v)
                           for k, v in tab.columns.items()}
        return tabs
    finally:
        if hasattr(obj, "close"):
            obj.close()
