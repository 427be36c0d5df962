"""Computed channels: ``NAME = EXPRESSION`` over a file's columns (``F = c7 - c6*51.875``), checked against a
whitelist and evaluated by numexpr (never by Python's ``eval``).

An expression may use

* numbers (``51.875``, ``1e-3``), the operators ``+ - * / **`` and parentheses, comparisons (``< <= > >= == !=``)
  and ``& | ~`` inside ``where``;
* the functions :data:`FUNCTIONS` (``abs``, ``sqrt``, ``exp``, ``log``, ``log10``, ``sin``, ``cos``, ``tan``,
  ``arcsin``, ``arccos``, ``arctan``, ``arctan2``, ``sinh``, ``cosh``, ``tanh``, ``where``);
* columns: ``cN`` is the file's N-th column (1-based), a column whose name is a Python identifier by that name
  (``F_meas``), and any name computed by another expression (in any order; a cycle is an error).

Anything else (attributes, subscripts, strings, lambdas, other functions, unknown names) is refused before
anything is evaluated, with an error naming the symbol and what is known.  Expressions see the numbers as the file
has them (before ``units``, ``zero`` and ``scale``, which then apply to the computed column like to any other).
"""
from __future__ import annotations

import ast
import re
from dataclasses import dataclass
from typing import Mapping

import numpy as np

__all__ = ["FUNCTIONS", "Derived", "parse_derived", "parse_derive_text", "order_derived", "evaluate"]

#: Functions an expression may call (all elementwise; numexpr's names).
FUNCTIONS = ("abs", "sqrt", "exp", "log", "log10", "sin", "cos", "tan", "arcsin", "arccos", "arctan", "arctan2",
             "sinh", "cosh", "tanh", "where")
_ARITY = {"arctan2": 2, "where": 3}
_OPS = (ast.Expression, ast.BinOp, ast.UnaryOp, ast.Compare, ast.Name, ast.Load, ast.Constant, ast.Call,
        ast.Add, ast.Sub, ast.Mult, ast.Div, ast.Pow, ast.USub, ast.UAdd, ast.Lt, ast.LtE, ast.Gt, ast.GtE,
        ast.Eq, ast.NotEq, ast.BitAnd, ast.BitOr, ast.Invert)
_IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
_MAX_LEN = 2000


@dataclass(frozen=True)
class Derived:
    """One computed channel: its name, the expression as written, and the symbols it reads."""

    name: str
    expr: str
    symbols: tuple[str, ...]


def parse_derived(name: str, expr: str, what: str = "derive") -> Derived:
    """Check one ``NAME = EXPRESSION`` against the whitelist (see the module docstring).

    Raises
    ------
    ValueError
        A name that is not an identifier, a syntax error, or anything outside the whitelist, naming it.
    """
    name = str(name).strip()
    text = str(expr).strip()
    if not _IDENT.match(name):
        raise ValueError(f"{what} {name!r}: the name of a computed column must be an identifier "
                         "(letters, digits, _; e.g. F or p_bar)")
    if not text or len(text) > _MAX_LEN:
        raise ValueError(f"{what} {name} = {text[:60]!r}: give an expression of 1..{_MAX_LEN} characters")
    try:
        tree = ast.parse(text, mode="eval")
    except SyntaxError as exc:
        raise ValueError(f"{what} {name} = {text!r}: not an expression ({exc.msg})") from None
    syms: list[str] = []
    for node in ast.walk(tree):  # first the kinds of node, then what the allowed ones hold
        if not isinstance(node, _OPS):
            kind = type(node).__name__
            raise ValueError(f"{what} {name} = {text!r}: {kind!r} is not allowed; use numbers, column names, "
                             f"+ - * / ** and the functions {', '.join(FUNCTIONS)}")
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and (isinstance(node.value, bool)
                                               or not isinstance(node.value, (int, float))):
            raise ValueError(f"{what} {name} = {text!r}: the constant {node.value!r} is not a number")
        if isinstance(node, ast.Call):
            fn = node.func.id if isinstance(node.func, ast.Name) else None
            if fn not in FUNCTIONS or node.keywords:
                shown = fn or ast.unparse(node.func)
                raise ValueError(f"{what} {name} = {text!r}: unknown function {shown!r}; valid: "
                                 f"{', '.join(FUNCTIONS)}")
            if len(node.args) != _ARITY.get(fn, 1):
                raise ValueError(f"{what} {name} = {text!r}: {fn}() takes {_ARITY.get(fn, 1)} argument(s), "
                                 f"got {len(node.args)}")
        if isinstance(node, ast.Name) and not _is_call_name(tree, node) and node.id not in syms:
            syms.append(node.id)
    return Derived(name, text, tuple(syms))


def _is_call_name(tree: ast.AST, name: ast.Name) -> bool:
    return any(isinstance(n, ast.Call) and n.func is name for n in ast.walk(tree))


def parse_derive_text(text: str) -> tuple[str, str]:
    """``"F = c7 - c6*51.875"`` -> ``("F", "c7 - c6*51.875")`` (the ``--derive`` option's form)."""
    name, eq, expr = str(text).partition("=")
    if not eq or not name.strip() or not expr.strip() or expr.lstrip().startswith("="):
        raise ValueError(f"--derive {text!r} is not NAME = EXPRESSION (e.g. 'F = F_meas - p*51.875')")
    return name.strip(), expr.strip()


def order_derived(items: Mapping[str, str], known: set[str], what: str = "derive") -> list[Derived]:
    """The computed channels in an order where each one's inputs exist (file columns ``known`` or earlier ones).

    Raises
    ------
    ValueError
        An unknown symbol (naming it, the expression and the known columns), a name that is also a file column,
        or a cycle.
    """
    parsed = {n: parse_derived(n, e, what) for n, e in items.items()}
    for n in parsed:
        if n in known:
            raise ValueError(f"{what} {n}: the file already has a column {n!r}; give the computed column another "
                             "name")
    for d in parsed.values():
        for s in d.symbols:
            if s not in known and s not in parsed:
                shown = ", ".join(sorted(known)) if len(known) < 40 else ", ".join(sorted(known)[:40]) + ", ..."
                raise ValueError(f"{what} {d.name} = {d.expr!r}: unknown symbol {s!r}; known columns: {shown}"
                                 f"{'; computed: ' + ', '.join(parsed) if len(parsed) > 1 else ''}")
    out: list[Derived] = []
    done: set[str] = set()
    todo = dict(parsed)
    while todo:
        ready = [d for d in todo.values() if all(s in known or s in done for s in d.symbols)]
        if not ready:
            raise ValueError(f"{what}: the computed columns {sorted(todo)} depend on each other in a cycle")
        for d in ready:
            out.append(d)
            done.add(d.name)
            del todo[d.name]
    return out


def evaluate(d: Derived, columns: Mapping[str, np.ndarray], source: str) -> np.ndarray:
    """The values of one computed channel (float64, same length as its inputs) by numexpr.

    Raises
    ------
    ValueError
        numexpr missing (naming the package), inputs of different lengths, or a result that is not finite
        (naming the first row).
    """
    try:
        import numexpr
    except ImportError:
        raise ValueError("computed columns (--derive) need the Python package 'numexpr', which is not installed: "
                         "pip install numexpr") from None
    local = {s: np.asarray(columns[s], dtype=float) for s in d.symbols}
    sizes = {a.size for a in local.values()}
    if len(sizes) > 1:
        raise ValueError(f"{source}: derive {d.name}: its inputs have different lengths {sorted(sizes)}")
    try:
        with np.errstate(all="ignore"):
            v = numexpr.evaluate(d.expr, local_dict=local, global_dict={})
    except (KeyError, ValueError, TypeError, SyntaxError, ZeroDivisionError) as exc:
        raise ValueError(f"{source}: derive {d.name} = {d.expr!r} cannot be evaluated ({exc})") from None
    v = np.asarray(v, dtype=float)
    if v.ndim == 0:
        n = next(iter(sizes)) if sizes else 0
        v = np.full(n, float(v))
    bad = np.flatnonzero(~np.isfinite(v))
    if bad.size:
        i = int(bad[0])
        raise ValueError(f"{source}: derive {d.name} = {d.expr!r} is {float(v[i])!r} at data row {i + 1} "
                         f"({bad.size} non-finite value(s)): a division by zero or a log of a negative number?")
    return v
