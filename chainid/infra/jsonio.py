"""Strict JSON text: NaN/±inf → ``null``, numpy → Python (no unit involved).

Writers use :func:`chainid.infra.fileio.write_json` (atomic, ``"-"`` = stdout); this module only makes text.
"""
from __future__ import annotations

import json
import math
import os
from typing import Any

__all__ = ["to_jsonable", "dumps_json", "json_default"]


def to_jsonable(o: Any) -> Any:
    """Plain-Python copy of ``o`` for strict JSON: NaN/±inf → None, numpy → Python, tuples → lists.

    Dict keys become strings; keys starting with ``_`` are kept (callers drop private keys themselves).
    """
    if isinstance(o, dict):
        return {str(k): to_jsonable(v) for k, v in o.items()}
    if isinstance(o, (list, tuple)):
        return [to_jsonable(v) for v in o]
    if o is None or isinstance(o, (bool, str)):
        return o
    if isinstance(o, int):
        return int(o)
    if isinstance(o, float):
        v = float(o)
        return v if math.isfinite(v) else None
    if isinstance(o, os.PathLike):
        return os.fspath(o)
    if hasattr(o, "tolist"):  # numpy scalar or array
        return to_jsonable(o.tolist())
    if hasattr(o, "item"):
        return to_jsonable(o.item())
    raise TypeError(f"not JSON serialisable: {type(o).__name__}")


def dumps_json(doc: Any, indent: int | None = 2) -> str:
    """Strict JSON text of ``doc`` (no NaN/Infinity tokens; non-finite numbers are ``null``)."""
    return json.dumps(to_jsonable(doc), indent=indent, ensure_ascii=False, allow_nan=False)


def json_default(o: Any) -> Any:
    """``default=`` hook of :func:`json.dumps` for numpy scalars and arrays."""
    import numpy as np

    if isinstance(o, (np.floating, np.integer)):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    raise TypeError(f"not JSON serialisable: {type(o)}")
