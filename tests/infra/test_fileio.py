"""chainid.infra.fileio: target checks, atomic writes and their mode, strict JSON (``--json -`` on the real stdout),
injective file names, figures, deferred SIGINT."""
from __future__ import annotations

import json
import math
import os
import re
import signal
import stat
import threading
from pathlib import Path

import numpy as np
import pytest

from chainid.infra import fileio
from chainid.infra.fileio import OutputError, check_output_file, json_to_stdout, write_json


def _strict_loads(text: str):
    def bad(tok: str):
        raise AssertionError(f"non-JSON token {tok}")

    return json.loads(text, parse_constant=bad)


def test_safe_filename_is_injective_and_portable():
    ids = ["T 1", "T_1", "T/1", "T\\1", "t 1", "..", ".", "", "é", "x" * 300]
    names = [fileio.safe_filename(i, "loop_", ".png") for i in ids]
    assert len(set(names)) == len(ids)
    for n in names:
        assert re.fullmatch(r"loop_[A-Za-z0-9_.-]+\.png", n), n
        assert len(n) < 120
    assert fileio.safe_filename("T_1") == "T_1"  # a file-safe id is kept as it is


def test_dumps_json_is_strict_and_converts_numpy():
    doc = {"a": math.nan, "b": math.inf, "c": np.float64(-np.inf), "d": np.array([1.5, np.nan]),
           "e": np.int64(3), "f": np.bool_(True), "g": (1, 2.0), 5: "k"}
    out = _strict_loads(fileio.dumps_json(doc))
    assert out == {"a": None, "b": None, "c": None, "d": [1.5, None], "e": 3, "f": True, "g": [1, 2.0], "5": "k"}
    assert type(out["e"]) is int and type(out["f"]) is bool


def test_write_json_refuses_existing_and_directory(tmp_path):
    p = tmp_path / "a.json"
    fileio.write_json({"x": 1.0}, p)
    with pytest.raises(OutputError, match="already exists"):
        fileio.write_json({"x": 2.0}, p)
    assert _strict_loads(p.read_text()) == {"x": 1.0}
    fileio.write_json({"x": 2.0}, p, force=True)
    assert _strict_loads(p.read_text()) == {"x": 2.0}
    with pytest.raises(OutputError, match="is a directory"):
        fileio.write_json({}, tmp_path)


def test_check_output_file_parent_is_a_file(tmp_path):
    (tmp_path / "f").write_text("x")
    with pytest.raises(OutputError, match="is not a directory"):
        fileio.check_output_file(tmp_path / "f" / "out.json", what="--json")


@pytest.mark.skipif(not Path("/proc/self").is_dir(), reason="needs Linux /proc (a folder nobody can create files in)")
def test_check_output_file_unwritable_folder():
    with pytest.raises(OutputError, match="not writable"):
        fileio.check_output_file("/proc/chainid-test.json", what="--json")


@pytest.mark.skipif(os.name != "posix" or os.geteuid() == 0, reason="root ignores folder permissions")
def test_check_output_file_read_only_folder(tmp_path):
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o500)
    try:
        with pytest.raises(OutputError, match="not writable"):
            fileio.check_output_file(ro / "a.json", what="--json")
    finally:
        ro.chmod(0o700)


def test_check_output_dir(tmp_path):
    (tmp_path / "file").write_text("x")
    with pytest.raises(OutputError, match="is a file"):
        fileio.check_output_dir(tmp_path / "file", "--plots")
    d = tmp_path / "d"
    d.mkdir()
    (d / "a.png").write_bytes(b"old")
    with pytest.raises(OutputError, match="already exists"):
        fileio.check_output_dir(d, "--plots", ["a.png"])
    fileio.check_output_dir(d, "--plots", ["a.png"], force=True)
    with pytest.raises(OutputError, match="share the file name"):
        fileio.check_output_dir(d, "--plots", ["b.png", "b.png"])


def test_atomic_open_error_leaves_target_and_no_temp(tmp_path):
    p = tmp_path / "out.csv"
    p.write_text("old\n")
    with pytest.raises(RuntimeError):
        with fileio.atomic_open(p, force=True) as fh:
            fh.write("new, partial")
            raise RuntimeError("fault mid-write")
    assert p.read_text() == "old\n"
    assert sorted(x.name for x in tmp_path.iterdir()) == ["out.csv"]


def test_atomic_open_keyboard_interrupt_leaves_nothing(tmp_path):
    p = tmp_path / "out.csv"
    with pytest.raises(KeyboardInterrupt):
        with fileio.atomic_open(p) as fh:
            fh.write("partial")
            raise KeyboardInterrupt
    assert list(tmp_path.iterdir()) == []


def test_atomic_open_no_clobber_when_target_appears_meanwhile(tmp_path):
    p = tmp_path / "out.csv"
    with pytest.raises(OutputError, match="already exists"):
        with fileio.atomic_open(p) as fh:
            fh.write("mine\n")
            p.write_text("someone else's\n")  # appears while we write
    assert p.read_text() == "someone else's\n"
    assert sorted(x.name for x in tmp_path.iterdir()) == ["out.csv"]


def test_two_interleaved_writers_leave_one_whole_file(tmp_path):
    """Two concurrent --force writers into one file: the result is one of the two, never a mix."""
    p = tmp_path / "out.csv"
    a = [f"A,{i}\n" for i in range(2000)]
    b = [f"B,{i}\n" for i in range(2000)]
    with fileio.atomic_open(p, force=True) as fa, fileio.atomic_open(p, force=True) as fb:
        for la, lb in zip(a, b):
            fa.write(la)
            fb.write(lb)
    text = p.read_text()
    assert text in ("".join(a), "".join(b))
    assert sorted(x.name for x in tmp_path.iterdir()) == ["out.csv"]


def test_save_figure_writes_a_png(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])
    p = fileio.save_figure(fig, tmp_path / "f.png", force=False, dpi=50)
    plt.close(fig)
    assert p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    fig, _ = plt.subplots()
    with pytest.raises(OutputError, match="already exists"):
        fileio.save_figure(fig, p, force=False)
    plt.close(fig)


def test_deferred_sigint_holds_ctrl_c_until_the_block_ends():
    done = []
    with pytest.raises(KeyboardInterrupt):
        with fileio.deferred_sigint():
            os.kill(os.getpid(), signal.SIGINT)
            for _ in range(1000):  # the signal would be delivered here without the guard
                pass
            done.append(True)
    assert done == [True]


def test_json_dash_goes_to_the_real_stdout_and_text_to_stderr(capsys):
    with json_to_stdout():
        print("a text table")
        assert write_json({"c_e": float("nan"), "n": [1, 2]}, "-") is None
        print("wrote -")
    cap = capsys.readouterr()
    assert json.loads(cap.out) == {"c_e": None, "n": [1, 2]}  # NaN is written as null (strict JSON)
    assert "a text table" not in cap.out and "a text table\n" in cap.err and "wrote -" in cap.err
    # outside the block: stdout as usual
    write_json({"a": 1}, "-")
    print("after")
    cap = capsys.readouterr()
    assert cap.out.endswith("}\nafter\n") and json.loads(cap.out[: -len("after\n")]) == {"a": 1}


def test_output_in_folders_still_to_be_made(tmp_path):
    p = tmp_path / "a" / "b" / "c" / "out.json"
    assert check_output_file(p, what="--json") == p
    (tmp_path / "f").write_text("x")
    with pytest.raises(OutputError, match=r"--json .*f/b/out.json.*'.*/f' is not a directory"):
        check_output_file(tmp_path / "f" / "b" / "out.json", what="--json")
    # a relative name in the current folder
    assert check_output_file("rel_out.json", what="--json").name == "rel_out.json"


def test_safe_filename_by_hand_and_save_figure_format(tmp_path, capsys):
    import hashlib

    from chainid.infra.fileio import EXIT_INTERRUPTED, interrupted, safe_filename, save_figure

    def h(s):
        return hashlib.sha256(s.encode()).hexdigest()[:8]

    assert safe_filename("T/1", "loop_", ".png") == f"loop_T_1-{h('T/1')}.png"
    assert safe_filename(".hidden") == f"hidden-{h('.hidden')}"
    assert safe_filename("") == f"id-{h('')}"
    assert safe_filename("a" * 100) == "a" * 80 + f"-{h('a' * 100)}"
    assert safe_filename("a" * 80) == "a" * 80 and safe_filename("x.y-z_1") == "x.y-z_1"
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])
    p = save_figure(fig, tmp_path / "f.svg")
    assert p == tmp_path / "f.svg" and b"<svg" in p.read_bytes()[:500]
    q = save_figure(fig, tmp_path / "noext", format="pdf")
    assert q.read_bytes().startswith(b"%PDF")
    r = save_figure(fig, tmp_path / "plain")
    assert r.read_bytes().startswith(b"\x89PNG")  # no suffix: PNG
    plt.close(fig)
    assert interrupted("simulate") == EXIT_INTERRUPTED == 130
    assert capsys.readouterr().err == "chainid simulate: interrupted; no partial output was written\n"


@pytest.mark.parametrize("umask,expected", [(0o022, 0o644), (0o077, 0o600), (0o002, 0o664)])
def test_atomic_write_mode_follows_umask(tmp_path, umask, expected):
    """A written file gets 0o666 & ~umask, as open() would give it (mkstemp alone gives 0o600).
    Bugs caught: the chmod dropped, the umask ignored (0o666) or applied twice/inverted."""
    old = os.umask(umask)
    try:
        p = fileio.atomic_write_text(tmp_path / "out.txt", "x\n")
        fileio.write_json({"a": 1}, str(tmp_path / "out.json"))
    finally:
        os.umask(old)
    assert stat.S_IMODE(os.stat(p).st_mode) == expected
    assert stat.S_IMODE(os.stat(tmp_path / "out.json").st_mode) == expected
    assert os.umask(old) == old  # the helper leaves the process umask as it was
    os.umask(old)


@pytest.mark.parametrize("name", [".", "..", ".hidden", "...", ".a.b"])
def test_safe_filename_never_hidden_or_a_directory(name):
    """Ids that start with a dot give a visible name that is neither '.' nor '..', with a hash suffix
    (distinct ids stay distinct).  Bugs caught: the leading-dot rule dropped, lstrip removed, hash not added."""
    out = fileio.safe_filename(name)
    assert not out.startswith(".") and out not in (".", "..")
    assert re.fullmatch(r"[A-Za-z0-9_.-]+-[0-9a-f]{8}", out), out


def test_safe_filename_dot_ids_distinct():
    ids = [".", "..", ".hidden", "hidden", "id"]
    names = {fileio.safe_filename(i) for i in ids}
    assert len(names) == len(ids)
    assert fileio.safe_filename("hidden") == "hidden"  # a safe id is kept as it is


def test_commit_without_hard_links_still_refuses_to_overwrite(tmp_path, monkeypatch):
    """On a file system without hard links (os.link raises EPERM) the no-clobber commit falls back to a checked
    rename: a new target is written, an existing one is refused and kept, and no temporary file is left.
    Bug caught: the existence check inverted."""
    import errno

    def no_link(*a, **k):
        raise OSError(errno.EPERM, "Operation not permitted")

    monkeypatch.setattr(fileio.os, "link", no_link)
    p = fileio.atomic_write_text(tmp_path / "a.txt", "new\n")
    assert p.read_text() == "new\n"
    q = tmp_path / "b.txt"
    with pytest.raises(fileio.OutputError, match="already exists"):
        with fileio.atomic_open(q) as fh:
            fh.write("ours\n")
            q.write_text("appeared meanwhile\n")  # another process wrote the target while we were writing
    assert q.read_text() == "appeared meanwhile\n" and sorted(os.listdir(tmp_path)) == ["a.txt", "b.txt"]


def test_output_checks_name_the_option_and_the_path(tmp_path):
    """Each refusal is one line naming the option (``what``) and the path, as the module docstring promises."""
    d = tmp_path / "d"
    d.mkdir()
    with pytest.raises(OutputError, match=rf"^--json '{d}' is a directory; give a file name$"):
        fileio.check_output_file(d, what="--json")
    f = tmp_path / "f.json"
    f.write_text("{}")
    with pytest.raises(OutputError, match=rf"^--json file '{f}' already exists; refusing to overwrite it "
                                          r"\(use --force\)$"):
        fileio.check_output_file(f, what="--json")
    assert fileio.check_output_file(f, force=True, what="--json") == f
    assert str(fileio.check_output_file("-")) == "-"  # stdout: nothing to check
    with pytest.raises(OutputError, match=rf"^--plots '{f}' is a file; give a folder$"):
        fileio.check_output_dir(f, "--plots")
    with pytest.raises(OutputError, match=r"^--plots: two outputs would share the file name\(s\) \['a.png', "
                                          r"'b.png'\]$"):
        fileio.check_output_dir(d, "--plots", ["b.png", "a.png", "b.png", "a.png", "c.png"])
    with pytest.raises(OutputError, match=rf"^--out '{f}/x.csv': '{f}' is not a directory$"):
        fileio.check_output_file(f / "x.csv", what="--out")
    assert fileio.check_output_dir(tmp_path / "new" / "deeper", "--plots", ["a.png"]) == tmp_path / "new" / "deeper"


def test_atomic_open_takes_text_or_binary_only(tmp_path):
    """``mode`` is "w" or "wb"; "a" (append: not atomic) is refused naming the value; "wb" writes bytes."""
    with pytest.raises(ValueError, match=r"^mode = 'a' is invalid: valid values 'w', 'wb'$"):
        with fileio.atomic_open(tmp_path / "a.txt", "a"):
            pass
    assert not (tmp_path / "a.txt").exists()
    with fileio.atomic_open(tmp_path / "b.bin", "wb") as fh:
        fh.write(b"\x00\x01")
    assert (tmp_path / "b.bin").read_bytes() == b"\x00\x01"


def test_write_json_targets(tmp_path, capsys):
    """``write_json``: None writes nothing and returns None; "-" prints the strict JSON and a newline to stdout and
    returns None; a path is written atomically and returned."""
    assert fileio.write_json({"a": 1}, None) is None
    assert fileio.write_json({"a": float("nan")}, "-") is None
    assert capsys.readouterr().out == '{\n  "a": null\n}\n'
    p = fileio.write_json([1, 2], tmp_path / "o.json")
    assert p == tmp_path / "o.json" and p.read_text() == "[\n  1,\n  2\n]\n"
    assert os.listdir(tmp_path) == ["o.json"]


def test_replace_file_renames_onto_a_regular_file_and_refuses_a_fifo(tmp_path):
    """``replace_file`` renames a finished file over a regular one; a special target (a FIFO) is refused naming
    it, and both files stay."""
    src, dst = tmp_path / "new", tmp_path / "old"
    src.write_text("new")
    dst.write_text("old")
    fileio.replace_file(src, dst)
    assert dst.read_text() == "new" and not src.exists()
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    src.write_text("x")
    with pytest.raises(OutputError, match=rf"^report '{fifo}' is a FIFO, not a regular file; refusing to replace"):
        fileio.replace_file(src, fifo, what="report")
    assert src.read_text() == "x" and fileio._special_kind(fifo) == "FIFO"


def test_deferred_sigint_outside_the_main_thread_is_a_no_op():
    """Python delivers signals to the main thread only, and ``signal.signal`` raises elsewhere: in another thread
    the block just runs (no error)."""
    out = []

    def work():
        try:
            with fileio.deferred_sigint():
                out.append("ran")
        except Exception as exc:  # pragma: no cover - the bug
            out.append(repr(exc))

    th = threading.Thread(target=work)
    th.start()
    th.join()
    assert out == ["ran"]
