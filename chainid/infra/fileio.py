"""Output files: target checks, atomic writes, strict JSON, safe file names, SIGINT.

Every command writes through this module so that the guarantees hold everywhere:

* **checked first**: :func:`check_output_file` / :func:`check_output_dir` refuse,
  before any work, a target that exists (without ``force``), a file where a
  folder is expected or the reverse, or a folder that cannot be written — with
  a :class:`OutputError` (a ``ValueError``) naming the option and the path;
* **atomic**: :func:`atomic_open` writes to a temporary file in the target's
  folder, flushes and fsyncs it, then renames it over the target
  (``os.replace``; without ``force`` a no-clobber ``os.link``).  A reader sees
  the old file or the new one, never a part; an exception or SIGINT removes the
  temporary file; two concurrent writers leave one whole file;
* **strict JSON**: :func:`dumps_json` turns NaN/±inf into ``null`` and numpy
  scalars/arrays into Python values, then ``json.dumps(..., allow_nan=False)``;
* **injective file names**: :func:`safe_filename` ("T 1", "T_1", "T/1" → three names);
* **SIGINT**: :func:`deferred_sigint` holds Ctrl-C back while a rename sequence
  runs; ``chainid.cli.parser`` turns ``KeyboardInterrupt`` into one line and rc 130.

No unit is involved here except sizes in bytes.
"""
from __future__ import annotations

import contextlib
import hashlib
import json
import math
import os
import re
import signal
import sys
import tempfile
import threading
from pathlib import Path
from typing import IO, Any, Iterator

__all__ = [
    "OutputError",
    "EXIT_INTERRUPTED",
    "check_output_file",
    "check_output_dir",
    "atomic_open",
    "atomic_write_text",
    "to_jsonable",
    "dumps_json",
    "write_json",
    "save_figure",
    "safe_filename",
    "deferred_sigint",
    "interrupted",
]

#: Exit code of a command stopped by SIGINT (128 + 2, the shell convention).
EXIT_INTERRUPTED = 130


class OutputError(ValueError):
    """An output target that cannot or must not be written (the CLI prints it and exits 2)."""


def _nearest_existing(p: Path) -> Path:
    q = p
    while not q.exists() and q != q.parent:
        q = q.parent
    return q


def _check_parent_writable(p: Path, what: str) -> None:
    """The folder that will hold ``p`` (or its nearest existing ancestor) must be a writable directory."""
    parent = p.parent if str(p.parent) else Path(".")
    anc = _nearest_existing(parent)
    if not anc.is_dir():
        raise OutputError(f"{what} {str(p)!r}: {str(anc)!r} is not a directory")
    if not os.access(anc, os.W_OK | os.X_OK):
        raise OutputError(f"{what} {str(p)!r}: folder {str(anc)!r} is not writable")
    # os.access says yes to root and knows nothing of read-only mounts: probe for real
    try:
        fd, probe = tempfile.mkstemp(prefix=".chainid-probe-", dir=anc)
    except OSError as exc:
        raise OutputError(f"{what} {str(p)!r}: folder {str(anc)!r} is not writable ({exc.strerror})") from None
    os.close(fd)
    os.unlink(probe)


def check_output_file(path: str | os.PathLike[str], force: bool = False, what: str = "output") -> Path:
    """Check, before any work, that ``path`` may be written as a file.

    Parameters
    ----------
    path : str or PathLike
        Target file.  Missing parent folders are allowed (they are created on write).
    force : bool
        Allow replacing an existing file.
    what : str
        Name of the option for the message (e.g. ``"--json"``).

    Returns
    -------
    Path

    Raises
    ------
    OutputError
        If the target is a directory, exists and ``force`` is False, or its folder
        is not a writable directory.
    """
    p = Path(path)
    if p.is_dir():
        raise OutputError(f"{what} {str(p)!r} is a directory; give a file name")
    if p.exists() and not force:
        raise OutputError(f"{what} file {str(p)!r} already exists; refusing to overwrite it (use --force)")
    _check_parent_writable(p, what)
    return p


def check_output_dir(path: str | os.PathLike[str], what: str = "--plots", files: Any = (),
                     force: bool = False) -> Path:
    """Check, before any work, that ``path`` can be a folder receiving ``files``.

    Parameters
    ----------
    path : str or PathLike
        Target folder (created on write if missing).
    what : str
        Option name for the message.
    files : iterable of str
        File names that will be written into the folder; each must not exist
        unless ``force`` (nor be a directory).
    force : bool
        Allow replacing existing files of those names.

    Returns
    -------
    Path

    Raises
    ------
    OutputError
        If ``path`` is an existing non-directory, is not writable, or a named
        file exists without ``force``.
    """
    d = Path(path)
    if d.exists() and not d.is_dir():
        raise OutputError(f"{what} {str(d)!r} is a file; give a folder")
    if d.is_dir():
        if not os.access(d, os.W_OK | os.X_OK):
            raise OutputError(f"{what} folder {str(d)!r} is not writable")
        _check_parent_writable(d / "x", what)
    else:
        _check_parent_writable(d, what)
    names = list(files)
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise OutputError(f"{what}: two outputs would share the file name(s) {dup}")
    for n in names:
        check_output_file(d / n, force=force, what=what)
    return d


@contextlib.contextmanager
def deferred_sigint() -> Iterator[None]:
    """Hold SIGINT back for the duration of the block; raise KeyboardInterrupt after it if one came.

    A no-op outside the main thread (Python delivers signals there only).
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    got: list[int] = []

    def handler(signum: int, frame: Any) -> None:
        got.append(signum)

    old = signal.signal(signal.SIGINT, handler)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, old)
    if got:
        raise KeyboardInterrupt


def _fsync_dir(d: Path) -> None:
    try:
        fd = os.open(d, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def _commit(tmp: str, p: Path, force: bool, what: str) -> None:
    """Rename the finished temporary file onto ``p`` (no-clobber unless ``force``)."""
    with deferred_sigint():
        try:
            if force:
                os.replace(tmp, p)
            else:
                try:
                    os.link(tmp, p)  # atomic and fails if p appeared meanwhile
                except FileExistsError:
                    os.unlink(tmp)
                    raise OutputError(f"{what} file {str(p)!r} already exists; refusing to overwrite it "
                                      f"(use --force)") from None
                except OSError:  # no hard links here (some network/FAT file systems)
                    if p.exists():
                        os.unlink(tmp)
                        raise OutputError(f"{what} file {str(p)!r} already exists; refusing to overwrite it "
                                          f"(use --force)") from None
                    os.replace(tmp, p)
                else:
                    os.unlink(tmp)
        except OutputError:
            raise
        except OSError as exc:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
            raise OutputError(f"{what} {str(p)!r} cannot be written: {exc.strerror or exc}") from None
    _fsync_dir(p.parent)


@contextlib.contextmanager
def atomic_open(path: str | os.PathLike[str], mode: str = "w", *, force: bool = False, what: str = "output",
                encoding: str | None = "utf-8", newline: str | None = None) -> Iterator[IO[Any]]:
    """Open a temporary file beside ``path``; on a clean exit it replaces ``path`` atomically.

    Parameters
    ----------
    path : str or PathLike
        Target file; missing parent folders are created.
    mode : {"w", "wb"}
        Text or binary.
    force : bool
        Replace an existing target; otherwise an existing target (even one that
        appeared while writing) is an :class:`OutputError` and nothing is changed.
    what : str
        Option name for messages.
    encoding, newline
        As for :func:`open` (text mode only).

    Yields
    ------
    file object
        Write to it; do not close it.

    Raises
    ------
    OutputError
        Target checks (see :func:`check_output_file`) or an OS error while writing.
    """
    if mode not in ("w", "wb"):
        raise ValueError(f"mode = {mode!r} is invalid: valid values 'w', 'wb'")
    p = Path(path)
    check_output_file(p, force=force, what=what)
    try:
        p.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{p.name}.", suffix=".tmp", dir=p.parent)
    except OSError as exc:
        raise OutputError(f"{what} {str(p)!r} cannot be written: {exc.strerror or exc}") from None
    try:
        kw = {} if "b" in mode else {"encoding": encoding, "newline": newline}
        with os.fdopen(fd, mode, **kw) as fh:
            yield fh
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, 0o666 & ~_umask())
        _commit(tmp, p, force, what)
    except BaseException as exc:  # incl. KeyboardInterrupt: the temporary file goes, the target is untouched
        with contextlib.suppress(OSError):
            os.unlink(tmp)  # (already gone if the rename happened)
        if isinstance(exc, OSError):
            raise OutputError(f"{what} {str(p)!r} cannot be written: {exc.strerror or exc}") from None
        raise


def _umask() -> int:
    m = os.umask(0)
    os.umask(m)
    return m


def atomic_write_text(path: str | os.PathLike[str], text: str, force: bool = False, what: str = "output") -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically; see :func:`atomic_open`."""
    with atomic_open(path, "w", force=force, what=what) as fh:
        fh.write(text)
    return Path(path)


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


def write_json(doc: Any, target: str | os.PathLike[str] | None, force: bool = False,
               what: str = "--json") -> Path | None:
    """Write ``doc`` as strict JSON to ``target`` atomically ("-" = stdout, None = nothing).

    Returns
    -------
    Path or None
        The file written (None for stdout or no target).
    """
    if target is None:
        return None
    text = dumps_json(doc)
    if str(target) == "-":
        print(text)
        return None
    return atomic_write_text(target, text + "\n", force=force, what=what)


def save_figure(fig: Any, path: str | os.PathLike[str], force: bool = True, what: str = "figure",
                **savefig_kw: Any) -> Path:
    """``fig.savefig`` through :func:`atomic_open` (format from the suffix of ``path``)."""
    p = Path(path)
    fmt = savefig_kw.pop("format", None) or (p.suffix[1:] or "png")
    with atomic_open(p, "wb", force=force, what=what) as fh:
        fig.savefig(fh, format=fmt, **savefig_kw)
    return p


_UNSAFE = re.compile(r"[^A-Za-z0-9_.-]+")


def safe_filename(name: str, prefix: str = "", suffix: str = "", max_len: int = 80) -> str:
    """A portable file name for an arbitrary id: ``prefix + slug + suffix``.

    The slug keeps ``A-Z a-z 0-9 _ . -``; when it differs from ``name`` (or
    starts with a dot, or is long) a short hash of ``name`` is appended, so that
    "T 1", "T_1" and "T/1" give three different names.
    """
    name = str(name)
    slug = _UNSAFE.sub("_", name)[:max_len]
    if slug != name or not slug or slug.startswith("."):
        h = hashlib.sha256(name.encode("utf-8", "surrogatepass")).hexdigest()[:8]
        slug = f"{slug.lstrip('.') or 'id'}-{h}"
    return f"{prefix}{slug}{suffix}"


def interrupted(command: str) -> int:
    """Print the one-line SIGINT message of ``chainid <command>`` and return 130."""
    print(f"chainid {command}: interrupted; no partial output was written", file=sys.stderr, flush=True)
    return EXIT_INTERRUPTED

def json_default(o: Any) -> Any:
    """``default=`` hook of :func:`json.dumps` for numpy scalars and arrays."""
    import numpy as np

    if isinstance(o, (np.floating, np.integer)):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    raise TypeError(f"not JSON serialisable: {type(o)}")
