"""The blocks of the CSV float kernel (chainid.infra.floattext): each block's offset and reserved size as its
docstring states."""
from __future__ import annotations




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
