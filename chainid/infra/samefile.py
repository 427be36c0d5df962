"""Output targets against the run's other files: an output that is an input of the same run, or two outputs that
are one file, are refused before any work (no unit involved).  Re-exported by :mod:`chainid.infra.fileio`."""
from __future__ import annotations

import contextlib
import os
import stat
from typing import Any

__all__ = ["OutputError", "check_inputs_not_outputs", "check_outputs_distinct"]


class OutputError(ValueError):
    """An output target that cannot or must not be written (the CLI prints it and exits 2)."""


def _error(msg: str) -> ValueError:
    return OutputError(msg)


def _is_char_device(path: Any) -> bool:
    try:
        return stat.S_ISCHR(os.stat(path).st_mode)
    except OSError:
        return False


def check_inputs_not_outputs(outputs: Any, inputs: Any) -> None:
    """Refuse an output that is an input of the same run (the same file: ``os.path.samefile``).

    Parameters
    ----------
    outputs, inputs : iterable of (what, path)
        Option name and path; None paths, ``"-"`` and paths that do not exist are skipped.

    Raises
    ------
    OutputError
        Naming both options and the path.
    """
    def existing(pairs: Any) -> list[tuple[str, str]]:
        out = []
        for what, path in pairs:
            if path is None or str(path) == "-":
                continue
            if os.path.exists(path):
                out.append((what, os.fspath(path)))
        return out

    ins = existing(inputs)
    for what_o, out in existing(outputs):
        for what_i, inp in ins:
            try:
                same = os.path.samefile(out, inp)
            except OSError:
                continue
            if same:
                raise _error(f"{what_o} {out!r} is the input {what_i} {inp!r} of this run; refusing to "
                                  "overwrite an input (give another output file)")


def check_outputs_distinct(outputs: Any) -> None:
    """Refuse two outputs of one run that name the same file (the second write would replace the first).

    Parameters
    ----------
    outputs : iterable of (what, path)
        Option name and path; None and ``"-"`` are skipped, and so is a character device (``/dev/null``, a
        terminal: written through, never replaced).  The same file: the same real path, or
        ``os.path.samefile`` when both exist (hard links included).

    Raises
    ------
    OutputError
        Naming both options and the path.
    """
    seen: list[tuple[str, str]] = []
    for what, path in outputs:
        if path is None or str(path) == "-" or _is_char_device(path):
            continue
        p = os.fspath(path)
        for what0, p0 in seen:
            same = os.path.realpath(p) == os.path.realpath(p0)
            if not same and os.path.exists(p) and os.path.exists(p0):
                with contextlib.suppress(OSError):
                    same = os.path.samefile(p, p0)
            if same:
                raise _error(f"{what} {p!r} is the same file as {what0} {p0!r}: one run cannot write both "
                                  "there; give two different files")
        seen.append((what, p))
