"""One file, several tests: segments cut at event rows (``split_events``) or at time gaps (``split_gap``), their
test ids (``segment_id``, ``segment_ids``), the per-segment offsets (``zero``) and covariates (``reduce``).

* **Events**: a row whose events cell matches the pattern is the *last* row of its segment; the next row starts
  a new one (a DAQ's ``DAQ Pause`` row ends a segment).  Empty segments are dropped.
* **Gaps**: a time step over ``split_gap`` seconds (time after units and scale) cuts between the two samples.
* **Ids**: ``segment_id`` formats ``{stem}`` (the file name without suffix), ``{id}`` (the file's test id),
  ``{segment}`` (1-based) and ``{label}`` (the k-th of ``segment_ids``, whose count must match).
* **Offsets** (after units, before scale): ``first`` the segment's first sample, ``first:N`` the mean of its
  first N samples, ``mean``, ``median``.
"""
from __future__ import annotations

import numpy as np

from chainid.records.patterns import bounded_search, check_pattern
from chainid.records.readerspec import ReaderSpec, parse_zero

__all__ = ["split_points", "segment_ids", "zero_offset", "reduce_value"]


def split_points(size: int, events: np.ndarray | None = None, pattern: str | None = None,
                 t: np.ndarray | None = None, gap: float | None = None) -> list[tuple[int, int]]:
    """``[(start, end), ...]`` row ranges of the segments (see the module docstring)."""
    cuts: set[int] = set()
    if events is not None and pattern is not None:
        rx = check_pattern(pattern, "--split-events")
        ev = np.asarray(events, dtype=object)
        for i in np.flatnonzero(ev != ""):
            cell = str(ev[i]).strip()
            if cell and bounded_search(rx, cell, "--split-events"):
                cuts.add(int(i) + 1)
    if t is not None and gap is not None:
        cuts.update((np.flatnonzero(np.diff(t) > gap) + 1).tolist())
    bounds = [0, *sorted(c for c in cuts if 0 < c < size), size]
    return [(a, b) for a, b in zip(bounds[:-1], bounds[1:]) if b > a]


def segment_ids(n: int, file_id: str, stem: str, spec: ReaderSpec, source: str) -> list[str]:
    """The test ids of ``n`` segments of one file.

    Raises
    ------
    ValueError
        ``segment_ids`` of another count than the segments found (naming both).
    """
    labels = spec.segment_ids
    if labels is not None and len(labels) != n:
        raise ValueError(f"{source}: {n} segment(s) found but --segment-ids gives {len(labels)} label(s) "
                         f"{list(labels)}; the count must match (check --split-events / --split-gap)")
    tpl = spec.segment_id or ("{id}_{label}" if labels else "{id}_{segment}")
    return [tpl.format(stem=stem, id=file_id, segment=k + 1, label=labels[k] if labels else "") for k in range(n)]


def zero_offset(v: np.ndarray, how: str, what: str) -> float:
    """The offset ``how`` (``first``, ``first:N``, ``mean``, ``median``) of one segment's values.

    Raises
    ------
    ValueError
        ``first:N`` on a segment of fewer than N samples (naming the column and both counts).
    """
    kind, n = parse_zero(how, f"--zero {what}")
    if kind == "first":
        if v.size < n:
            raise ValueError(f"--zero {what}=first:{n}: the segment has only {v.size} sample(s)")
        return float(np.mean(v[:n]))
    return float(np.mean(v) if kind == "mean" else np.median(v))


def reduce_value(v: np.ndarray, stat: str) -> float:
    """One covariate from one segment's values: ``mean``, ``median``, ``first``, ``last``, ``min`` or ``max``."""
    if v.size == 0:
        return float("nan")
    return float({"mean": np.mean, "median": np.median, "first": lambda a: a[0], "last": lambda a: a[-1],
                  "min": np.min, "max": np.max}[stat](v))
