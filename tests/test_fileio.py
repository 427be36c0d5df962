"""chainid.infra.fileio: target checks, atomic writes, strict JSON, injective file names, deferred SIGINT."""
from __future__ import annotations

import json
import math
import os
import re
import signal
from pathlib import Path

import numpy as np
import pytest

from chainid.infra import fileio
from chainid.infra.fileio import OutputError


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
