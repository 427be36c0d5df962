"""The canonical records writer (chainid.records.writer): ids a CSV can hold, blocks written bit-exact with and
without the numba kernel."""
from __future__ import annotations

import numpy as np
import pytest

from chainid.records.record import Record


@pytest.mark.parametrize("bad, words", [
    ("a,b", "must not contain commas, quotes or newlines"), ('a"b', "must not contain"), ("a\nb", "must not contain"),
    ("", "must be non-empty without leading/trailing spaces"), (" a", "must be non-empty"), ("a ", "must be non-empty"),
])
def test_writer_refuses_ids_a_csv_cannot_hold(tmp_path, bad, words):
    from chainid.records.writer import write_canonical

    r = Record(bad, np.arange(3.0), np.ones(3), np.ones(3))
    with pytest.raises(ValueError, match=words):
        write_canonical(tmp_path / "o.csv", [r])
    assert not (tmp_path / "o.csv").exists()


def test_writer_refuses_a_repeated_id_and_an_unknown_format(tmp_path):
    from chainid.records.writer import write_canonical

    r = Record("a", np.arange(3.0), np.ones(3), np.ones(3))
    with pytest.raises(ValueError, match="test id 'a' appears twice; test ids must be unique"):
        write_canonical(tmp_path / "o.csv", [r, r])
    with pytest.raises(ValueError, match="output format 'xlsx' is invalid; valid: 'csv', 'parquet'"):
        write_canonical(tmp_path / "o.x", [r], fmt="xlsx")


@pytest.mark.slow
@pytest.mark.parametrize("arrow", [True, False])
def test_writer_blocks_round_trip_bit_exact(tmp_path, monkeypatch, arrow):
    """Rows over several of the writer's blocks (2^16 plain, 2^19 arrow), and two tests: every float64 reads back
    bit-exact, in order, with the header ``test,t,x,F``."""
    import sys

    if not arrow:
        monkeypatch.setitem(sys.modules, "pyarrow", None)
        monkeypatch.setitem(sys.modules, "pyarrow.csv", None)
    from chainid.records.writer import write_canonical

    n = (1 << 19) + 7 if arrow else (1 << 16) * 2 + 5
    rng = np.random.default_rng(1)
    t = np.cumsum(rng.uniform(1e-4, 2e-3, n))
    a = Record("A", t, rng.normal(2.2, 0.3, n) * np.pi, rng.normal(1e4, 3e3, n) / 3.0)
    b = Record("B2", t[:10].copy(), np.full(10, 1 / 3), np.full(10, 2 / 3))
    p = write_canonical(tmp_path / "o.csv", [a, b])
    with open(p, "rb") as fh:
        assert fh.readline() == b"test,t,x,F\n"
    data = np.genfromtxt(p, delimiter=",", skip_header=1, dtype=None, encoding="ascii",
                         names=("test", "t", "x", "F")) if n < 200_000 else None
    if data is not None:
        ids = data["test"]
        assert (ids[:n] == "A").all() and (ids[n:] == "B2").all()
        for k in ("t", "x", "F"):
            np.testing.assert_array_equal(data[k][:n], getattr(a, k))
            np.testing.assert_array_equal(data[k][n:], getattr(b, k))
    else:
        import pyarrow.csv as pacsv

        tb = pacsv.read_csv(p)
        assert tb.column("test").to_pylist()[n - 1:n + 1] == ["A", "B2"]
        for k in ("t", "x", "F"):
            col = tb.column(k).to_numpy()
            np.testing.assert_array_equal(col[:n], getattr(a, k))
            np.testing.assert_array_equal(col[n:], getattr(b, k))


@pytest.mark.parametrize("arrow", [True, False])
def test_writer_without_the_kernel_round_trips_over_several_blocks(tmp_path, monkeypatch, arrow):
    """With the numba kernel off (``NUMBA_DISABLE_JIT=1``) the CSV is written by pyarrow in blocks of rows, or
    without pyarrow by ``%.17g``: 2 507 and 10 rows in blocks of 1 000 read back bit-exact, in order, under the
    header ``test,t,x,F``.  Bug caught: the block end ``i + rows`` → ``i / rows`` (the pyarrow path had no test:
    the other round-trip tests run with the kernel)."""
    import sys

    import chainid.infra.floattext as ft
    import chainid.records.writer as w

    monkeypatch.setattr(ft, "jit_enabled", lambda: False)
    monkeypatch.setattr(w, "_ROWS_PER_WRITE", 1000)
    monkeypatch.setattr(w, "_BLOCK", 1000)
    if not arrow:
        monkeypatch.setitem(sys.modules, "pyarrow", None)
        monkeypatch.setitem(sys.modules, "pyarrow.csv", None)
    rng = np.random.default_rng(2)
    n = 2507
    t = np.cumsum(rng.uniform(1e-4, 2e-3, n))
    a = Record("A", t, rng.normal(2.2, 0.3, n) * np.pi, rng.normal(1e4, 3e3, n) / 3.0)
    b = Record("B2", t[:10].copy(), np.full(10, 1 / 3), np.full(10, 2 / 3))
    p = w.write_canonical(tmp_path / "o.csv", [a, b])
    lines = p.read_text(encoding="ascii").splitlines()
    assert lines[0] == "test,t,x,F" and len(lines) == 1 + n + 10
    rows = [ln.split(",") for ln in lines[1:]]
    assert [r[0] for r in rows] == ["A"] * n + ["B2"] * 10
    for k, col in (("t", 1), ("x", 2), ("F", 3)):
        vals = np.array([float(r[col]) for r in rows])
        np.testing.assert_array_equal(vals[:n], getattr(a, k))
        np.testing.assert_array_equal(vals[n:], getattr(b, k))
