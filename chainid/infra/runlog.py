"""The warnings of one command run: printed once on stderr and carried into the run's JSON ``warnings``.

A command of the ``chainid`` CLI runs inside :func:`collecting`.  In that block

* :func:`warn` prints ``chainid <command>: warning: <message>`` on stderr (once per distinct message) and
  records the message;
* every Python warning that would be shown (``warnings.warn`` in the library: plausibility, a load beyond the
  chain's limits, a model-file value that is valid but implausible, a run check) is printed and recorded the
  same way instead of Python's two-line ``file:line: Category: message`` form;
* :func:`note` prints ``chainid <command>: note: <message>`` (information, not recorded);
* :func:`merge_warnings` adds the recorded messages, in order and without repeats, to a JSON document's
  ``warnings`` list: :func:`chainid.infra.fileio.write_json` calls it for every document it writes, so a
  warning printed on stderr is also in the JSON (one rule for every command).

Outside a run (the library used from Python) :func:`warn` issues a Python ``UserWarning`` and nothing is
recorded.  No unit is involved.
"""
from __future__ import annotations

import contextlib
import sys
import warnings
from dataclasses import dataclass, field
from typing import Any, Iterator

__all__ = ["warn", "note", "collecting", "collected", "merge_warnings", "active"]


@dataclass
class _Run:
    command: str
    messages: list[str] = field(default_factory=list)


_RUNS: list[_Run] = []


def active() -> bool:
    """True inside :func:`collecting` (a CLI run)."""
    return bool(_RUNS)


def _emit(run: _Run, message: str) -> None:
    msg = str(message).strip()
    if not msg or msg in run.messages:
        return
    run.messages.append(msg)
    print(f"chainid {run.command}: warning: {msg}", file=sys.stderr, flush=True)


def warn(message: str) -> None:
    """Report an implausible (but valid) input or result: on stderr and in the run's JSON ``warnings``.

    Outside a CLI run: a Python ``UserWarning`` with the same text.
    """
    if _RUNS:
        _emit(_RUNS[-1], message)
    else:
        warnings.warn(str(message), UserWarning, stacklevel=2)


def note(message: str) -> None:
    """Print an informational note on stderr: ``chainid <command>: note: <message>`` inside a CLI run (the same
    prefix as its warnings and errors), ``note: <message>`` outside one.  A note is not a warning: it is not
    recorded in the JSON."""
    prefix = f"chainid {_RUNS[-1].command}: " if _RUNS else ""
    print(f"{prefix}note: {str(message).strip()}", file=sys.stderr, flush=True)


def collected() -> list[str]:
    """The messages recorded so far in the current run (empty outside a run)."""
    return list(_RUNS[-1].messages) if _RUNS else []


def merge_warnings(doc: Any) -> Any:
    """``doc`` with the run's recorded warnings appended to ``doc["warnings"]`` (a dict; not repeated).

    Other documents (lists, ``None``) and documents outside a run are returned unchanged.
    """
    msgs = collected()
    if not msgs or not isinstance(doc, dict):
        return doc
    have = doc.get("warnings")
    if have is not None and not isinstance(have, list):
        return doc
    out = list(have or [])
    out += [m for m in msgs if m not in out]
    return {**doc, "warnings": out}


@contextlib.contextmanager
def collecting(command: str) -> Iterator[list[str]]:
    """Run a command with its warnings collected (see the module docstring); yields the message list."""
    run = _Run(str(command))

    def show(message: Any, category: Any, filename: str, lineno: int, file: Any = None, line: Any = None) -> None:
        _emit(run, str(message))

    _RUNS.append(run)
    try:
        with warnings.catch_warnings():  # (restores the filters and showwarning on exit)
            # every occurrence reaches ``show`` (which prints each distinct message once): Python's default
            # "once per code location" would hide a second test's message, or a second run's in one process
            warnings.filterwarnings("always", category=UserWarning)
            warnings.filterwarnings("always", category=RuntimeWarning)
            warnings.showwarning = show
            yield run.messages
    finally:
        _RUNS.remove(run)
