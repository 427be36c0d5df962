"""infra contracts (issue 20 §2 and §5, mutation survivors of infra): ``--json -`` routes the JSON alone to the
real stdout, an output in folders still to be made is fine while a file in its path is not, a closed stderr means
no progress bar, and the dask handshake check (an 8-byte little-endian length of at most 1 MiB) with what a
server that passes it but speaks no dask makes of a run: one line, within the time bound."""
from __future__ import annotations

import io
import json
import sys
import time

import pytest

from chainid.infra.fileio import OutputError, check_output_file, json_to_stdout, write_json
from chainid.infra.parallel import dask_available, probe_scheduler, run_cases
from chainid.infra.progress import progress_enabled, progress_iter
from fake_servers import greeting_listener


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


class _Tty(io.StringIO):
    def isatty(self):
        return True


def test_progress_only_on_an_open_terminal(monkeypatch):
    monkeypatch.setattr(sys, "stderr", _Tty())
    assert progress_enabled() is True and progress_enabled(quiet=True) is False
    closed = io.StringIO()
    closed.close()
    with pytest.raises(ValueError):
        closed.isatty()  # on a closed file: ValueError
    monkeypatch.setattr(sys, "stderr", closed)
    assert progress_enabled() is False
    assert list(progress_iter(iter([3, 1, 2]), desc="x")) == [3, 1, 2]
    monkeypatch.setattr(sys, "stderr", object())  # no isatty at all
    assert progress_enabled() is False
    monkeypatch.setattr(sys, "stderr", io.StringIO())  # a pipe or a log
    assert progress_enabled() is False


@pytest.fixture
def greeter():
    """A TCP listener that greets every connection with the given bytes, then closes it after 0.3 s."""
    payload = {"bytes": b""}
    with greeting_listener(lambda: payload["bytes"], hold_s=0.3) as address:
        yield address, payload


def _le(n: int) -> bytes:
    return n.to_bytes(8, "little")


def test_probe_accepts_lengths_up_to_one_mib(greeter):
    address, payload = greeter
    for n in (1, 300, 1 << 20):
        payload["bytes"] = _le(n)
        probe_scheduler(address, timeout=3.0)  # a dask-like greeting: accepted
    for n in (0, (1 << 20) + 1):
        payload["bytes"] = _le(n)
        with pytest.raises(ValueError, match="the server there answered .*not a dask handshake"):
            probe_scheduler(address, timeout=3.0)


@pytest.mark.skipif(not dask_available(), reason="needs dask.distributed")
@pytest.mark.parametrize("greeting", [
    _le(1 << 20),  # a valid length, then the connection closes (dask: CommClosedError, an OSError)
    _le(16) + _le(1) + _le(0),  # frames that msgpack cannot unpack (ValueError)
    _le(17) + _le(1) + _le(1) + b"\x01",  # (TypeError inside dask's reader)
    _le(100) + b"\x00" * 100,  # (IndexError inside dask's reader)
    _le(8) + b"\xc1" * 8,  # (struct.error inside dask's reader)
], ids=["closed", "ValueError", "TypeError", "IndexError", "struct.error"])
def test_a_server_that_passes_the_probe_but_is_not_dask_is_one_line(greeter, capsys, greeting):
    address, payload = greeter
    payload["bytes"] = greeting
    probe_scheduler(address, timeout=3.0)
    t0 = time.monotonic()
    with pytest.raises(ValueError) as ei:
        run_cases(abs, [1, -2], scheduler=address, progress=False)
    assert time.monotonic() - t0 < 15.0
    msg = str(ei.value)
    assert msg.startswith(f"scheduler = {address!r} is invalid: no dask scheduler answers at that address (")
    assert "\n" not in msg
    assert "CRITICAL" not in capsys.readouterr().err  # dask's deserialisation traceback is held back


def test_to_jsonable_by_hand():
    import math
    from pathlib import Path

    import numpy as np

    from chainid.infra.jsonio import dumps_json, json_default, to_jsonable

    doc = {1: (np.float64(1.5), np.int32(-3), np.bool_(True)), "a": [math.inf, -math.inf, math.nan, 2.0],
           "p": Path("/x/y.csv"), "arr": np.array([[1, 2], [3, 4]]), "t": True, "n": None, "s": "é", "i": 7}
    out = to_jsonable(doc)
    assert out == {"1": [1.5, -3, True], "a": [None, None, None, 2.0], "p": "/x/y.csv", "arr": [[1, 2], [3, 4]],
                   "t": True, "n": None, "s": "é", "i": 7}
    assert type(out["1"][1]) is int and type(out["1"][2]) is bool and out["t"] is True
    with pytest.raises(TypeError, match="not JSON serialisable: object"):
        to_jsonable(object())
    assert dumps_json({"a": [1, math.nan]}, indent=None) == '{"a": [1, null]}'
    assert dumps_json({"s": "é"}) == '{\n  "s": "é"\n}'  # UTF-8 kept, two-space indent
    assert json.dumps({"v": np.float32(0.5), "k": np.int64(3), "a": np.arange(2)}, default=json_default) == \
        '{"v": 0.5, "k": 3, "a": [0, 1]}'
    with pytest.raises(TypeError, match="not JSON serialisable"):
        json_default(object())


def test_lazy_exports_import_on_first_use_and_cache():
    from chainid.infra.lazy import exports

    ns: dict = {"already": 1}
    getattr_, dir_ = exports("chainid.infra", {"dumps_json": "jsonio", "exports": "lazy"}, ns)
    from chainid.infra.jsonio import dumps_json

    assert getattr_("dumps_json") is dumps_json and ns["dumps_json"] is dumps_json  # cached in the namespace
    with pytest.raises(AttributeError, match="module 'chainid.infra' has no attribute 'nope'"):
        getattr_("nope")
    assert dir_() == ["already", "dumps_json", "exports"]


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
