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
* **only ever touch what is ours**: a target that exists and is not a regular file is never renamed
  over.  With ``force``, a character device (``/dev/null``, a terminal) is written through, as
  ``cat > /dev/null`` does; a FIFO is written through only when a reader is already there (it is opened
  non-blocking: a FIFO without a reader would hang the run, so it is refused); a block device, socket
  or other special file is refused.  :func:`check_inputs_not_outputs` refuses an output that is an
  input of the same run (same file, ``os.path.samefile``);
* **strict JSON**: :func:`dumps_json` turns NaN/±inf into ``null`` and numpy
  scalars/arrays into Python values, then ``json.dumps(..., allow_nan=False)``;
* **injective file names**: :func:`safe_filename` ("T 1", "T_1", "T/1" → three names);
* **SIGINT**: :func:`deferred_sigint` holds Ctrl-C back while a rename sequence
  runs; ``chainid.cli.parser`` turns ``KeyboardInterrupt`` into one line and rc 130.

No unit is involved here except sizes in bytes.
"""
from __future__ import annotations

import contextlib
import errno
import hashlib
import os
import re
import signal
import stat
import sys
import tempfile
import threading
from pathlib import Path
from typing import IO, Any, Iterator

from chainid.infra.jsonio import dumps_json, json_default, to_jsonable
from chainid.infra.samefile import OutputError, check_inputs_not_outputs, check_outputs_distinct

__all__ = [
    "OutputError",
    "check_inputs_not_outputs",
    "check_outputs_distinct",
    "replace_file",
    "EXIT_INTERRUPTED",
    "check_output_file",
    "check_output_dir",
    "atomic_open",
    "atomic_write_text",
    "to_jsonable",
    "dumps_json",
    "json_default",
    "write_json",
    "json_to_stdout",
    "save_figure",
    "safe_filename",
    "deferred_sigint",
    "interrupted",
]

#: Exit code of a command stopped by SIGINT (128 + 2, the shell convention).
EXIT_INTERRUPTED = 130


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


def _special_kind(p: Path) -> str | None:
    """None for a missing path or a regular file (symlinks followed); else what it is ("FIFO", ...)."""
    try:
        mode = os.stat(p).st_mode
    except OSError:
        return None
    if stat.S_ISREG(mode) or stat.S_ISDIR(mode):
        return None
    if stat.S_ISCHR(mode):
        return "character device"
    if stat.S_ISFIFO(mode):
        return "FIFO"
    if stat.S_ISBLK(mode):
        return "block device"
    if stat.S_ISSOCK(mode):
        return "socket"
    return "special file"


#: Special files written through (never replaced) with ``force``; any other special file is refused.
WRITE_THROUGH = ("character device", "FIFO")


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
    if str(path) == "-":  # stdout (write_json); nothing to check
        return p
    if p.is_dir():
        raise OutputError(f"{what} {str(p)!r} is a directory; give a file name")
    if p.exists() and not force:
        raise OutputError(f"{what} file {str(p)!r} already exists; refusing to overwrite it (use --force)")
    kind = _special_kind(p)
    if kind is not None:  # written through with force, never renamed over (see the module notes)
        if kind not in WRITE_THROUGH:
            raise OutputError(f"{what} {str(p)!r} is a {kind}, not a regular file; refusing to write to it")
        if not os.access(p, os.W_OK):
            raise OutputError(f"{what} {str(p)!r} is a {kind} that cannot be written")
        return p
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
    if _special_kind(p) is not None:  # a device or FIFO: written through, never replaced
        with _open_through(p, mode, what, encoding, newline) as fh:
            yield fh
        return
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


@contextlib.contextmanager
def _open_through(p: Path, mode: str, what: str, encoding: str | None,
                  newline: str | None) -> Iterator[IO[Any]]:
    """Write into an existing character device or FIFO (``cat > /dev/null``); a FIFO needs a reader now."""
    kind = _special_kind(p)
    flags = os.O_WRONLY | (os.O_NONBLOCK if kind == "FIFO" else 0)
    try:
        fd = os.open(p, flags)
    except OSError as exc:
        if exc.errno == errno.ENXIO:
            raise OutputError(f"{what} {str(p)!r} is a FIFO with no reader; refusing to wait for one "
                              "(start the reader first)") from None
        raise OutputError(f"{what} {str(p)!r} cannot be written: {exc.strerror or exc}") from None
    if kind == "FIFO":  # the reader is there: ordinary blocking writes from now on
        os.set_blocking(fd, True)
    kw = {} if "b" in mode else {"encoding": encoding, "newline": newline}
    try:
        with os.fdopen(fd, mode, **kw) as fh:
            yield fh
    except OSError as exc:
        raise OutputError(f"{what} {str(p)!r} cannot be written: {exc.strerror or exc}") from None


def replace_file(src: str | os.PathLike[str], dst: str | os.PathLike[str], what: str = "output") -> None:
    """Rename the finished file ``src`` onto ``dst`` (same file system); a special ``dst`` is refused.

    For builders that write a whole folder first (``chainid report``): the one place where a finished
    file is renamed over an existing one.
    """
    kind = _special_kind(Path(dst))
    if kind is not None:
        raise OutputError(f"{what} {os.fspath(dst)!r} is a {kind}, not a regular file; refusing to replace it")
    os.replace(src, dst)


def _umask() -> int:
    m = os.umask(0)
    os.umask(m)
    return m


def atomic_write_text(path: str | os.PathLike[str], text: str, force: bool = False, what: str = "output") -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically; see :func:`atomic_open`."""
    with atomic_open(path, "w", force=force, what=what) as fh:
        fh.write(text)
    return Path(path)


def write_json(doc: Any, target: str | os.PathLike[str] | None, force: bool = False,
               what: str = "--json") -> Path | None:
    """Write ``doc`` as strict JSON to ``target`` atomically ("-" = stdout, None = nothing).

    Inside a CLI run, a dict ``doc`` gets the run's warnings (:func:`chainid.infra.runlog.merge_warnings`).

    Returns
    -------
    Path or None
        The file written (None for stdout or no target).
    """
    if target is None:
        return None
    from chainid.infra.runlog import merge_warnings

    text = dumps_json(merge_warnings(doc))  # a CLI run's warnings printed on stderr are in its JSON too
    if str(target) == "-":
        out = _JSON_STDOUT[-1] if _JSON_STDOUT else sys.stdout
        out.write(text + "\n")
        out.flush()
        return None
    return atomic_write_text(target, text + "\n", force=force, what=what)


#: The real stdout while :func:`json_to_stdout` is active (the JSON's only channel).
_JSON_STDOUT: list[IO[str]] = []


@contextlib.contextmanager
def json_to_stdout() -> Iterator[None]:
    """``--json -``: inside the block, the JSON (:func:`write_json` to ``"-"``) alone goes to stdout.

    Every other ``print`` (tables, notes, "wrote ...") goes to stderr, so ``chainid X --json - | jq``
    parses.
    """
    _JSON_STDOUT.append(sys.stdout)
    try:
        with contextlib.redirect_stdout(sys.stderr):
            yield
    finally:
        _JSON_STDOUT.pop()


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
