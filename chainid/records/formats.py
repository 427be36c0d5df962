"""Record files other than delimited text: JSON arrays, MATLAB ``.mat`` (v7.3 through h5py), HDF5, LabVIEW TDMS,
Parquet.  Each becomes one or more :class:`~chainid.records.table.RawTable` (one per test).

Containers are searched for the columns a spec needs (``x`` and ``F``, by their mapped names): the variables /
datasets / channels at the top level form one table; otherwise every group (HDF5 group, TDMS group, MATLAB
struct, JSON object or list item) that holds them is one test, named by the group (a single group takes the
file's test id).  A name may be a path, ``run1/force``.

h5py and npTDMS are optional (``pip install "chainid[formats]"``); a missing one is a one-line error naming the
extra.  Parquet uses pyarrow, a dependency of chainid.
"""
from __future__ import annotations

import importlib
import json
from pathlib import Path
from typing import Any, Callable, Mapping

import numpy as np

from chainid.records.spec import ReaderSpec
from chainid.records.table import RawTable

__all__ = ["SUFFIXES", "format_of", "optional_module", "read_container"]

#: File suffix -> format.
SUFFIXES = {".json": "json", ".mat": "mat", ".h5": "hdf5", ".hdf5": "hdf5", ".hdf": "hdf5", ".he5": "hdf5",
            ".tdms": "tdms", ".parquet": "parquet", ".pq": "parquet"}
_EXTRA = 'pip install "chainid[formats]"'


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


def _get(obj: Any, name: str) -> Any:
    cur = obj
    for part in (p for p in name.split("/") if p):
        if not _is_group(cur) or part not in cur.keys():
            return None
        cur = cur[part]
    return None if _is_group(cur) else cur


def _tables(obj: Any, source: str, spec: ReaderSpec, file_id: str, keyed: bool) -> list[RawTable]:
    """Tables of a nested container (dicts / lists of dicts / h5py groups)."""
    wanted = {}
    for role in ("test", "t", "x", "F"):
        name = spec.columns.get(role, role)
        if isinstance(name, int):
            raise ValueError(f"{source}: --columns {role}={name}: positions are for headerless text files; "
                             "give the variable/dataset/channel name")
        wanted[role] = name

    def walk(node: Any, where: str, key: str | None) -> list[tuple[str | None, str, dict]]:
        if isinstance(node, list) and node and all(_is_group(v) for v in node):
            out = []
            for i, v in enumerate(node):
                out += walk(v, f"{where}[{i}]", f"{file_id}_{i + 1}")
            return out
        if not _is_group(node):
            return []
        if _get(node, wanted["x"]) is not None and _get(node, wanted["F"]) is not None:
            cols = {wanted[r]: _get(node, wanted[r]) for r in wanted if _get(node, wanted[r]) is not None}
            return [(key, where, cols)]
        out = []
        for k in node.keys():
            out += walk(node[k], f"{where}/{k}", str(k))
        return out

    found = walk(obj, source, None)
    if not found:
        top = list(obj.keys()) if _is_group(obj) else f"a {type(obj).__name__}"
        raise ValueError(f"{source}: no {wanted['x']!r} and {wanted['F']!r} columns found (top level: {top}); "
                         "name them with --columns x=NAME,F=NAME")
    tabs = []
    for key, where, cols in found:
        test = None
        tcol = cols.get(wanted["test"])
        if tcol is not None and np.ndim(tcol) == 0:  # a scalar id beside the arrays
            test = str(np.asarray(tcol).item() if not isinstance(tcol, str) else tcol)
            cols.pop(wanted["test"])
        elif len(found) > 1 or keyed:
            test = key
        tabs.append(RawTable(where, cols, test))
    return tabs


def _json(path: Path) -> Any:
    try:
        with path.open(encoding="utf-8-sig") as fh:
            return json.load(fh)
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path}: not a JSON file ({exc})") from None


def _mat(path: Path) -> Any:
    import scipy.io

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
        f = nptdms.TdmsFile.read(str(path))
    except Exception as exc:  # npTDMS raises many types on a corrupt file: one line, no traceback
        raise ValueError(f"{path}: not a readable TDMS file ({exc})") from None
    return {g.name: {c.name: c[:] for c in g.channels()} for g in f.groups()}


def _parquet(path: Path) -> Any:
    pq = optional_module("pyarrow.parquet", f"{path} (Parquet)", "pip install pyarrow (a dependency of chainid)")
    try:
        table = pq.read_table(path)
    except Exception as exc:  # pyarrow raises its own error types
        raise ValueError(f"{path}: not a readable Parquet file ({exc})") from None
    return {name: table.column(name).to_numpy() for name in table.column_names}


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
        for tab in tabs:  # read lazily opened datasets now (before the file closes)
            tab.columns = {k: (_squeeze(np.asarray(v)) if not isinstance(v, list) else v)
                           for k, v in tab.columns.items()}
        return tabs
    finally:
        if hasattr(obj, "close"):
            obj.close()
