"""More pins of chainid.infra (issue 20 §5: own-seed mutation survivors 813–).  No units (bytes, counts)."""
from __future__ import annotations


def test_a_loaded_kernel_module_is_returned_without_probing_the_cache_again(monkeypatch):
    """``load_kernel_module`` on a module it loaded before returns that module at once: numba's cache locators are
    not probed again (a probe compiles a stub and builds a cache object, ~0.3 ms, and
    ``chainid.model.kernels.power_module`` loads on every use).  Bug caught: the early return's condition
    negated (every call re-probed)."""
    import chainid.infra.numba_cache as nc

    first = nc.load_kernel_module("contact_power")
    calls = []
    monkeypatch.setattr(nc, "_choose_cache", lambda py_file: calls.append(py_file) or "default")
    assert nc.load_kernel_module("contact_power") is first
    assert calls == [] and first._chainid_cache_mode == nc.cache_mode()


# --- weak spots of fileio.py: the documented messages and branches --------------------------------------------
import os  # noqa: E402
import threading  # noqa: E402

import pytest  # noqa: E402

from chainid.infra import fileio  # noqa: E402
from chainid.infra.fileio import OutputError  # noqa: E402


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


def test_private_temp_cache_folder_is_the_users_own_or_a_fresh_one(tmp_path, monkeypatch):
    """The fallback numba cache folder is ``<tmp>/chainid-numba-<uid>``, created with mode 0700; a folder of that
    name that others may write (mode 0777) is not trusted: a fresh ``mkdtemp`` folder is used instead."""
    import stat
    import tempfile

    import chainid.infra.numba_cache as nc

    monkeypatch.setattr(tempfile, "gettempdir", lambda: str(tmp_path))
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    own = tmp_path / f"chainid-numba-{os.getuid()}"
    assert nc._private_temp_dir() == str(own)
    assert stat.S_IMODE(os.stat(own).st_mode) & 0o077 == 0
    os.chmod(own, 0o777)
    other = nc._private_temp_dir()
    assert other != str(own) and os.path.basename(other).startswith("chainid-numba-")
    assert os.path.dirname(other) == str(tmp_path) and stat.S_IMODE(os.stat(other).st_mode) == 0o700


def test_cache_warnings_are_given_once_per_key_as_one_line():
    """``_warn_once``: a NumbaCacheWarning (a RuntimeWarning) per key, the second call with the same key silent,
    another key warned again; line 0 so no source line is printed under it."""
    import warnings

    import chainid.infra.numba_cache as nc

    key = f"test-key-{os.getpid()}-{id(object())}"
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        nc._warn_once(key, "first")
        nc._warn_once(key, "again")
        nc._warn_once(key + "-2", "other")
    assert [str(w.message) for w in got] == ["first", "other"]
    assert all(issubclass(w.category, nc.NumbaCacheWarning) and w.lineno == 0 for w in got)
    assert issubclass(nc.NumbaCacheWarning, RuntimeWarning)


def test_njit_cached_gives_the_recovering_cache_with_and_without_options():
    """``njit_cached`` as ``@njit_cached`` and as ``@njit_cached(**options)``: a compiled dispatcher whose disk
    cache is the recovering one (an unreadable entry is a miss), computing the function."""
    import chainid.infra.numba_cache as nc

    if nc.cache_mode() == "nojit":  # pragma: no cover - NUMBA_DISABLE_JIT=1: plain functions
        pytest.skip("numba JIT disabled")

    @nc.njit_cached
    def twice(v):
        return 2.0 * v

    @nc.njit_cached(fastmath=True)
    def thrice(v):
        return 3.0 * v

    assert twice(1.5) == 3.0 and thrice(1.5) == 4.5
    for disp in (twice, thrice):
        assert type(disp._cache).__name__ in ("_RecoveringCache", "NullCache")


# --- survivors of the blind seed-23 run ------------------------------------------------------------------------
def test_format_rows_writes_block_b_at_the_documented_offset():
    """``format_rows``' docstring: block b sits at ``out[b·cap:]`` with cap = block_rows·(len(prefix) +
    n_cols·(MAX_CHARS + 1)) + 32, its length in ``lens[b]``.  Two blocks of 2 rows (prefix "T1", 2 columns):
    a reader that slices at the documented offsets gets each block's rows, and the values read back are the
    doubles written (Python's float(), the other method).  Bug caught: the pad 32 → 31 (every block after the
    first moved one byte)."""
    import numpy as np

    from chainid.infra.floattext import MAX_CHARS, format_rows

    cols = np.array([[0.1, -2.5e-7, 3.0, 6.02e23], [12345.678, 0.0, -0.125, 7.0]])
    prefix = np.frombuffer(b"T1", np.uint8)
    block_rows, nc = 2, 2
    cap = block_rows * (2 + nc * (MAX_CHARS + 1)) + 32
    out = np.zeros(2 * cap, np.uint8)
    lens = np.zeros(2, np.int64)
    ovr = np.full(8, -1, np.int32)
    format_rows(cols, prefix, out, block_rows, lens, ovr, np.zeros(0, np.uint8), np.zeros(1, np.int64))
    rows = []
    for b in range(2):
        text = out[b * cap: b * cap + lens[b]].tobytes().decode()
        rows += [line.split(",") for line in text.splitlines()]
    assert (ovr == -1).all()  # all ordinary doubles: none left to the exact fallback
    assert [r[0] for r in rows] == ["T1"] * 4
    assert [[float(v) for v in r[1:]] for r in rows] == cols.T.tolist()


def test_probe_reads_the_whole_eight_byte_length():
    """A dask handshake starts with an 8-byte little-endian length, which the probe accepts in (0, 1 MiB]: seven
    bytes of 16 and, in a second read, an eighth byte 1 make 16 + 2^56, refused (the message shows all 8 bytes).
    Bug caught: the read loop stopping at 7 bytes (the length read as 16: accepted)."""
    import re

    from fake_servers import greeting_listener

    from chainid.infra.parallel import probe_scheduler

    greeting = [(16).to_bytes(7, "little"), b"\x01"]  # the eighth byte 0.1 s after the first seven
    with greeting_listener(lambda: greeting, hold_s=0.3) as address:
        with pytest.raises(ValueError, match=re.escape(
                r"answered '\\x10\\x00\\x00\\x00\\x00\\x00\\x00\\x01'..., not a dask handshake")):
            probe_scheduler(address, timeout=3.0)


def test_csv_chunks_blocks_hold_their_longest_rows_with_a_four_byte_prefix():
    """Each block of ``csv_chunks`` reserves block_rows·(len(prefix) + n_cols·(MAX_CHARS + 1)) + 32 bytes: 64 rows
    of ``TEST,<24 chars>,<24 chars>`` (54 bytes each, 3456 per block) fit in 3616.  256 such rows in 4 blocks read
    back exactly (float(), the other method).  Bug caught: ``len(prefix) + …`` → ``len(prefix) | …`` (4 | 52 = 52:
    3360 bytes, each block's last rows overwritten by the next block)."""
    import numpy as np

    from chainid.infra.floattext import csv_chunks

    rng = np.random.default_rng(3)
    a = -(1.0 + rng.random(256)) * 1e-123  # 24 characters each, e.g. -1.2345678901234567e-123
    b = -(1.0 + rng.random(256)) * 1e-155
    assert min(len(repr(v)) for v in a) >= 23
    text = b"".join(bytes(p) for p in csv_chunks(b"TEST", [a, b], block_rows=64)).decode()
    rows = [r.split(",") for r in text.splitlines()]
    assert len(rows) == 256 and {r[0] for r in rows} == {"TEST"}
    assert [float(r[1]) for r in rows] == a.tolist() and [float(r[2]) for r in rows] == b.tolist()
