"""Files are sacred: only ever touch what is ours.

* ``--force`` onto a device or FIFO writes through it (never renames over it); a FIFO without a reader and
  other special files are refused;
* an output that is an input of the same run is an error (exit 2, one line);
* ``report --force`` never replaces a file it did not write, nor its data.

The character device is a private ``/dev/null`` twin made with ``mknod`` in the test's folder (root only),
so a regression cannot replace the machine's ``/dev/null``."""
from __future__ import annotations

import json
import os
import select
import stat
import threading

import pytest

from chainid.cli import main
from chainid.infra import fileio
from chainid.infra.fileio import OutputError


def _null_device(tmp_path):
    p = tmp_path / "null"
    try:
        os.mknod(p, stat.S_IFCHR | 0o666, os.makedev(1, 3))
    except (PermissionError, OSError, AttributeError):
        pytest.skip("mknod of a character device needs root")
    return p


def _is_chr(p) -> bool:
    return stat.S_ISCHR(os.stat(p).st_mode)


def test_force_writes_through_a_character_device(tmp_path, capsys):
    dev = _null_device(tmp_path)
    assert main(["stiffness", "--x", "2.2", "--json", str(dev), "--force"]) == 0
    assert _is_chr(dev)  # still the device, not a JSON file renamed over it
    fileio.write_json({"a": 1}, dev, force=True)
    assert _is_chr(dev)
    assert not [p for p in tmp_path.iterdir() if p.name != "null"]  # no temporary file left
    # without --force an existing target is refused, as any file is
    assert main(["stiffness", "--x", "2.2", "--json", str(dev)]) == 2
    assert "already exists" in capsys.readouterr().err


def test_force_onto_a_fifo_without_reader_is_refused_at_once(tmp_path, capsys):
    fifo = tmp_path / "ff"
    os.mkfifo(fifo)
    with pytest.raises(OutputError, match="FIFO with no reader"):
        fileio.write_json({"a": 1}, fifo, force=True)  # would block forever if opened for writing blocking
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)
    assert main(["stiffness", "--x", "2.2", "--json", str(fifo), "--force"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1].startswith("chainid stiffness: error: --json") and "FIFO with no reader" in err[-1]
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)


def test_force_onto_a_fifo_with_reader_writes_through(tmp_path):
    fifo = tmp_path / "ff"
    os.mkfifo(fifo)
    got: list[bytes] = []
    opened = threading.Event()

    def reader() -> None:
        # O_RDWR: open without waiting for a writer (Linux), and no EOF before the writer came
        fd = os.open(fifo, os.O_RDWR)
        opened.set()
        buf = b""
        try:
            while True:
                r, _, _ = select.select([fd], [], [], 10)
                if not r:
                    break
                buf += os.read(fd, 65536)
                try:
                    json.loads(buf)
                    break
                except ValueError:
                    continue
        finally:
            os.close(fd)
            got.append(buf)

    th = threading.Thread(target=reader, daemon=True)
    th.start()
    assert opened.wait(5)
    fileio.write_json({"a": 1.5}, fifo, force=True)
    th.join(5)
    assert not th.is_alive()
    assert json.loads(got[0]) == {"a": 1.5}
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)


def test_other_special_files_are_refused(tmp_path):
    import socket

    sock_path = tmp_path / "s.sock"
    s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    try:
        s.bind(str(sock_path))
        with pytest.raises(OutputError, match="is a socket"):
            fileio.check_output_file(sock_path, force=True, what="--json")
    finally:
        s.close()
    with pytest.raises(OutputError, match="not a regular file"):
        fileio.replace_file(tmp_path / "x", sock_path)


def test_check_inputs_not_outputs_same_file_links_and_others(tmp_path):
    a = tmp_path / "a.csv"
    a.write_text("x")
    (tmp_path / "hard.csv").hardlink_to(a)
    (tmp_path / "sym.csv").symlink_to(a)
    for out in (a, tmp_path / "hard.csv", tmp_path / "sym.csv"):
        with pytest.raises(OutputError, match=r"--json .* is the input DATA"):
            fileio.check_inputs_not_outputs([("--json", str(out))], [("DATA", str(a))])
    # another file, a new file, stdout and None are fine
    (tmp_path / "b.csv").write_text("x")
    fileio.check_inputs_not_outputs([("--json", str(tmp_path / "b.csv")), ("--json", str(tmp_path / "new")),
                                     ("--json", "-"), ("--json", None)], [("DATA", str(a))])


@pytest.fixture(scope="module")
def records_csv(tmp_path_factory):
    d = tmp_path_factory.mktemp("io")
    p = d / "d.csv"
    assert main(["simulate", str(p), "--cycles", "4", "--samples-per-cycle", "32"]) == 0
    return p


@pytest.mark.parametrize("argv, what", [
    (["identify", "{d}", "--json", "{d}", "--force"], "--json"),
    (["identify", "{d}", "--write-side", "{d}", "--force"], "--write-side"),
    (["identify", "{d}", "--json", "{link}", "--force"], "--json"),
    (["diagnose", "--resamples", "0", "{d}", "--holdout", "3", "--json", "{d}", "--force"], "--json"),
    (["diagnose", "--resamples", "0", "{d}", "--holdout", "3", "--save-model", "{d}", "--force"], "--save-model"),
    (["predict", "{d}", "{d}", "--json", "{d}", "--force"], "--json"),
    (["simulate", "{d}", "--plan", "{d}", "--force"], "OUT"),
    (["stiffness", "--x", "2.2", "--chain", "{d}", "--json", "{d}", "--force"], "--json"),
])
def test_cli_output_that_is_an_input_is_refused(records_csv, tmp_path, capsys, argv, what):
    d = tmp_path / "data.csv"
    d.write_bytes(records_csv.read_bytes())
    link = tmp_path / "link.csv"
    link.symlink_to(d)
    before = d.read_bytes()
    capsys.readouterr()
    rc = main([a.format(d=d, link=link) for a in argv])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2
    assert len(err) == 1 and f"error: {what} " in err[0] and "is the input" in err[0], err
    assert d.read_bytes() == before


def test_cli_simulate_onto_its_plan_keeps_the_plan(tmp_path, capsys):
    plan = tmp_path / "plan.csv"
    plan.write_text("test,omega,x0,A\n1,1.0,2.2,0.25\n")
    assert main(["simulate", str(plan), "--plan", str(plan), "--force"]) == 2
    assert plan.read_text() == "test,omega,x0,A\n1,1.0,2.2,0.25\n"
    assert "OUT" in capsys.readouterr().err


def test_report_force_never_replaces_a_file_it_did_not_write(tmp_path, capsys):
    from chainid.report.build import MANIFEST, _swap_in, run_report

    out = tmp_path / "rep"
    out.mkdir()
    (out / "report.md").write_text("my own notes")
    with pytest.raises(OutputError, match="was not written by chainid report"):
        run_report(out, force=True)  # refused before any step runs
    assert main(["report", "--out", str(out), "--force"]) == 2
    assert (out / "report.md").read_text() == "my own notes"
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "has no manifest .chainid-manifest.json" in err[0], err
    # the final move: a figure of the user's is refused, one listed in the manifest is replaced
    (out / "report.md").unlink()
    (out / "figures").mkdir()
    (out / "figures" / "a.png").write_text("user's figure")
    tmp = tmp_path / "build"
    (tmp / "figures").mkdir(parents=True)
    (tmp / "figures" / "a.png").write_text("new figure")
    (tmp / "report.md").write_text("new report")
    with pytest.raises(OutputError, match="a.png.*not written by chainid report"):
        _swap_in(tmp, out)
    assert (out / "figures" / "a.png").read_text() == "user's figure"
    assert not (out / "report.md").exists()
    (out / MANIFEST).write_text(json.dumps({"files": ["figures/a.png"]}))
    _swap_in(tmp, out)
    assert (out / "figures" / "a.png").read_text() == "new figure"
    assert (out / "report.md").read_text() == "new report"


def test_report_never_replaces_its_data(tmp_path):
    from chainid.report.build import MANIFEST, _swap_in

    out = tmp_path / "rep"
    (out / "json").mkdir(parents=True)
    data = out / "json" / "d.csv"
    data.write_text("test,t,x,F\n")
    (out / MANIFEST).write_text(json.dumps({"files": ["json/d.csv"]}))  # an old report wrote that name
    tmp = tmp_path / "build"
    tmp.mkdir()
    (tmp / "report.md").write_text("new")
    with pytest.raises(OutputError, match="is the input --data"):
        _swap_in(tmp, out, [("--data", str(data))])  # it would be removed as stale
    assert data.read_text() == "test,t,x,F\n"
