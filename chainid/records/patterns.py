"""User regular expressions that cannot hang: test ids from file names (``--id-pattern``), covariates from test ids
(``--covariate``), event splits (``--split-events``) and header markers (``--header-marker``).

Python's ``re`` backtracks: ``(a+)+$`` on a name of 40 ``a`` and a ``!`` takes longer than the age of the
universe.  Two bounds, both applied:

* **refused up front**: a pattern with a repeat inside a repeat (``(a+)+``, ``(\\w*)*``, ``(a|ab)+c*`` nesting), the
  classic exponential form, is refused when the spec is built, with an error naming the option;
* **a time budget**: each search runs with a 1 s budget (:data:`BUDGET_S`; a ``SIGALRM`` timer, which the regex
  engine honours, when called from the main thread) and the subject is capped at :data:`MAX_SUBJECT` characters;
  a search over the budget is an error naming the pattern and the subject, never a hang.  (Off the main thread only
  the up-front refusal applies.)
"""
from __future__ import annotations

import re
import signal
import threading
from typing import Any

__all__ = ["BUDGET_S", "MAX_SUBJECT", "check_pattern", "bounded_search"]

#: Seconds one search may take.
BUDGET_S = 1.0
#: Longest subject searched (file names, test ids, event cells, header lines), characters.
MAX_SUBJECT = 4096


def _parser() -> Any:
    try:
        import re._parser as p  # Python >= 3.11
    except ImportError:  # pragma: no cover - Python 3.10
        import sre_parse as p  # type: ignore[no-redef]
    return p


def _nested_repeat(items: Any, inside: bool, p: Any) -> bool:
    """True when a repeat of more than one occurrence contains another such repeat."""
    consts = p if hasattr(p, "MAX_REPEAT") else __import__("re._constants", fromlist=["x"])
    repeats = {getattr(consts, n) for n in ("MAX_REPEAT", "MIN_REPEAT", "POSSESSIVE_REPEAT") if hasattr(consts, n)}
    for op, av in items:
        if op in repeats:
            lo, hi, sub = av
            many = hi is None or hi > 1 or hi == getattr(consts, "MAXREPEAT", -1)
            if many and inside:
                return True
            if _nested_repeat(sub, inside or many, p):
                return True
        elif op == getattr(consts, "SUBPATTERN", None):
            if _nested_repeat(av[-1], inside, p):
                return True
        elif op == getattr(consts, "BRANCH", None):
            if any(_nested_repeat(b, inside, p) for b in av[1]):
                return True
        elif op in {getattr(consts, n, None) for n in ("ASSERT", "ASSERT_NOT")}:
            if _nested_repeat(av[1], inside, p):
                return True
        elif op == getattr(consts, "ATOMIC_GROUP", None):
            if _nested_repeat(av, inside, p):
                return True
    return False


def check_pattern(pattern: str, what: str) -> re.Pattern:
    """Compile a user pattern, refusing syntax errors and nested repeats (see the module docstring).

    Raises
    ------
    ValueError
        Naming the option (``what``), the pattern and the reason.
    """
    try:
        rx = re.compile(pattern)
    except re.error as exc:
        raise ValueError(f"{what} = {pattern!r} is not a regular expression ({exc})") from None
    try:
        p = _parser()
        tree = p.parse(pattern)
    except Exception:  # the stdlib parser accepted it above; a private-API change must not stop the reader
        return rx
    if _nested_repeat(list(tree), False, p):
        raise ValueError(f"{what} = {pattern!r}: a repeat inside a repeat (like (a+)+ or (\\w*)*) can take "
                         "exponential time; write it without the nesting (e.g. (a+)+ -> a+)")
    return rx


class _Budget(Exception):
    pass


def _alarm(signum: int, frame: Any) -> None:  # pragma: no cover - timing
    raise _Budget()


def bounded_search(rx: re.Pattern, subject: str, what: str) -> re.Match | None:
    """``rx.search(subject)`` within :data:`BUDGET_S` seconds, the subject capped at :data:`MAX_SUBJECT`.

    Raises
    ------
    ValueError
        The subject is longer than the cap, or the search ran over the budget (naming the option, the pattern
        and the start of the subject).
    """
    if len(subject) > MAX_SUBJECT:
        raise ValueError(f"{what} {rx.pattern!r}: the text searched is {len(subject)} characters, over "
                         f"{MAX_SUBJECT} (starts {subject[:60]!r})")
    if threading.current_thread() is not threading.main_thread() or not hasattr(signal, "setitimer"):
        return rx.search(subject)
    old = signal.signal(signal.SIGALRM, _alarm)
    try:
        signal.setitimer(signal.ITIMER_REAL, BUDGET_S)
        try:
            return rx.search(subject)
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0.0)
    except _Budget:
        raise ValueError(f"{what} {rx.pattern!r} took over {BUDGET_S:g} s on {subject[:60]!r} (catastrophic "
                         "backtracking); simplify the pattern") from None
    finally:
        signal.signal(signal.SIGALRM, old)
