"""Which columns of a file a :class:`~chainid.records.spec.ReaderSpec` uses, and as what: the roles (test, t, x, F,
events), the computed columns and the symbols their expressions read, the kept channels and the reduced covariates.

Symbols: ``cN`` is always the file's N-th column (1-based); a column whose name is a Python identifier (and not of
the form ``cN``) is also reachable by its name; computed columns by theirs.  A role maps to a file column (by name
or position) or to a computed column; unmapped roles are looked up by their own name (``F`` computed by ``derive``
is the force).
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field

from chainid.records.derive import Derived, order_derived
from chainid.records.readerspec import ReaderSpec, parse_reduce

__all__ = ["ColumnPlan", "plan_columns", "symbol_table"]

_ROLE_NAMES = {"test": "test id", "t": "time", "x": "displacement", "F": "force", "events": "events"}
_IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
_POS = re.compile(r"c(\d+)\Z")


@dataclass
class ColumnPlan:
    """The columns one table needs.

    Attributes
    ----------
    roles : dict
        Role -> column key (a file column name, or a computed column's name).
    derived : list of Derived
        Computed columns in evaluation order.
    symbols : dict
        Symbol used by an expression, ``keep`` or ``reduce`` -> file column name (computed names map to
        themselves).
    numeric : list of str
        File columns read as numbers.
    text : list of str
        File columns read as text (test ids, events).
    channels : tuple of str
        Symbols kept as per-sample channels.
    reduce : dict
        Covariate -> (statistic, symbol).
    dt : float or None
        Time step [s] when there is no time column (``fs`` or the file's metadata).
    """

    roles: dict[str, str] = field(default_factory=dict)
    derived: list[Derived] = field(default_factory=list)
    symbols: dict[str, str] = field(default_factory=dict)
    numeric: list[str] = field(default_factory=list)
    text: list[str] = field(default_factory=list)
    channels: tuple[str, ...] = ()
    reduce: dict[str, tuple[str, str]] = field(default_factory=dict)
    dt: float | None = None

    def use(self) -> dict[str, str]:
        """Key -> file column for the text readers: ``test`` and ``events`` are read as text, every other key
        (a role's name, else ``numK``) as numbers."""
        out = {r: self.roles[r] for r in ("test", "events") if r in self.roles}
        role_of = {v: r for r, v in self.roles.items() if r in ("t", "x", "F")}
        for k, n in enumerate(self.numeric):
            out[role_of.get(n, f"num{k}")] = n
        return out


def symbol_table(names: list[str], positional: bool, positions: bool = True) -> dict[str, str]:
    """Symbol -> column name: ``c1..cN`` by position (text files: ``positions``), identifiers (not of the form
    ``cN``) by name."""
    out = {f"c{j + 1}": n for j, n in enumerate(names)} if positions else {}
    if not positional:
        for n in names:
            if _IDENT.match(n) and not _POS.match(n):
                out[n] = n
    return out


def _role_columns(names: list[str], spec: ReaderSpec, source: str, positional: bool, skip_test: bool,
                  derived: set[str], hint: str) -> dict[str, str]:
    out: dict[str, str] = {}
    wanted = ["t", "x", "F"] if skip_test else ["test", "t", "x", "F"]
    if spec.split_events is not None:
        wanted.append("events")
    for role in wanted:
        want = spec.columns.get(role)
        if want is None:
            if role in derived:
                out[role] = role
            elif role in names and not positional:
                out[role] = role
            elif role == "events" and not positional:
                ev = [n for n in names if n.strip().lower() in ("events", "event")]
                if ev:
                    out[role] = ev[0]
            continue
        if isinstance(want, int):
            if want > len(names):
                raise ValueError(f"{source}: --columns {role}={want}: the file has {len(names)} column(s) "
                                 f"(valid positions 1..{len(names)}){hint}")
            out[role] = names[want - 1]
        elif want in derived or (want in names and not positional):
            out[role] = want
        else:
            have = "no header (give 1-based positions, e.g. F=1,x=2)" if positional else f"columns {names}"
            calc = re.search(r"[-+*/()]", want) is not None
            raise ValueError(f"{source}: --columns {role}={want}: no {_ROLE_NAMES[role]} column named {want!r}; "
                             f"the file has {have}{hint}"
                             + (f" (a computed column: --derive '{role} = ...', e.g. '{role} = c7 - c6*51.875')"
                                if calc else ""))
    for role in ("x", "F"):
        if role not in out:
            have = "no header: give positions, e.g. --columns F=1,x=2" if positional else \
                f"columns {names}: give --columns {role}=NAME"
            raise ValueError(f"{source}: no {_ROLE_NAMES[role]} column {role!r}; the file has {have}{hint}")
    if spec.split_events is not None and "events" not in out:
        raise ValueError(f"{source}: --split-events needs the events column: no column named Events; give "
                         f"--columns events=NAME (the file has {'no header' if positional else names}){hint}")
    return out


def plan_columns(names: list[str], spec: ReaderSpec, source: str, positional: bool = False,
                 skip_test: bool = False, dt_meta: float | None = None, hint: str = "",
                 positions: bool = True) -> ColumnPlan:
    """The plan of one table whose columns are ``names`` (see :class:`ColumnPlan`); ``positions``: ``cN`` symbols
    name the N-th column (text files; a container's datasets are named, never numbered).

    Raises
    ------
    ValueError
        Naming the file, the role or symbol, and the columns there are: a missing or ambiguous column, no time
        column and no time step, both a time column and ``fs``, a column mapped to two roles, an unknown symbol in
        an expression, ``keep`` or ``reduce``.
    """
    syms = symbol_table(names, positional, positions)
    derived = order_derived(spec.derive, set(syms), "derive") if spec.derive else []
    dnames = {d.name for d in derived}
    roles = _role_columns(names, spec, source, positional, skip_test, dnames, hint)
    if "t" not in roles and spec.fs is None and dt_meta is None:
        have = "no header" if positional else f"columns {names}"
        raise ValueError(f"{source}: no time column 't' ({have}); give --columns t=NAME, or --fs HZ for a file "
                         f"sampled at a constant rate{hint}")
    if "t" in roles and spec.fs is not None:
        raise ValueError(f"{source}: both a time column ({roles['t']!r}) and --fs {spec.fs:g} Hz; give one of them")
    used = [v for r, v in roles.items() if r != "events"]
    dup = sorted({v for v in used if used.count(v) > 1})
    if dup:
        raise ValueError(f"{source}: column(s) {dup} mapped to more than one role ({roles})")
    reduce = {k: parse_reduce(v) for k, v in spec.reduce.items()}
    known = {**syms, **{n: n for n in dnames}}
    for what, sym in [("keep", s) for s in spec.keep] + [(f"reduce {k}", s) for k, (_, s) in reduce.items()]:
        if sym not in known:
            raise ValueError(f"{source}: {what}: unknown column {sym!r}; known: {', '.join(sorted(known))}{hint}")
    text = [roles[r] for r in ("test", "events") if r in roles]
    numeric: list[str] = []
    for col in [v for r, v in roles.items() if r in ("t", "x", "F")] + \
            [syms[s] for d in derived for s in d.symbols if s in syms] + \
            [known[s] for s in spec.keep] + [known[s] for _, s in reduce.values()]:
        if col not in dnames and col not in numeric:
            numeric.append(col)
    clash = sorted(set(numeric) & set(text))
    if clash:
        raise ValueError(f"{source}: column(s) {clash} are used both as text (test id, events) and as numbers")
    dt = 1.0 / spec.fs if spec.fs is not None else (dt_meta if "t" not in roles else None)
    return ColumnPlan(roles, derived, {s: known[s] for s in known}, numeric, text, tuple(spec.keep), reduce, dt)
