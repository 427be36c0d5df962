"""A short row deep in a text file that pyarrow parses in several blocks on several threads.

pyarrow's handler of irregular rows knows their line numbers on one thread only, so the reader parses such a file
again on one thread to put each short row back at its place.  Reference: the numbers the test wrote, and a hand
parse of the short row's line."""
from __future__ import annotations

import numpy as np

from chainid.records.reader import read_any
from chainid.records.spec import spec_from_options

N = 120_000  # 4.4 MB of text: five of pyarrow's 1 MiB blocks


def test_a_short_row_keeps_its_place_in_a_file_parsed_in_several_blocks(tmp_path):
    short = 100_000  # in the fourth block
    t = np.arange(N) * 0.001
    x, F = np.sin(t), 100.0 * np.cos(t)
    rows = [f"{a:.6f},{b:.9f},{c:.9f}" + ("" if i == short else ",") for i, (a, b, c) in enumerate(zip(t, x, F))]
    p = tmp_path / "long.csv"
    p.write_text("t,x,F,Events\n" + "\n".join(rows) + "\n")
    assert p.stat().st_size > 4 * (1 << 20)
    (rec,) = read_any(p, spec_from_options(columns="t=t,x=x,F=F"))
    assert rec.t.size == N
    line = rows[short].split(",")
    assert (rec.t[short], rec.x[short], rec.F[short]) == (float(line[0]), float(line[1]), float(line[2]))
    np.testing.assert_allclose(rec.x, x, rtol=0, atol=5e-10)  # 9 decimals written
    np.testing.assert_allclose(rec.F, F, rtol=0, atol=5e-10)
