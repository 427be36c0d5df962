"""Record files that must be one clear error, never a traceback, a 15 GiB allocation or a silent wrong number:
hidden files in a directory or glob (skipped), an HDF5 dataset declaring 2·10⁹ rows, dangling and external HDF5
links, a JSON integer beyond float, deeply nested JSON, boolean or complex columns."""
from __future__ import annotations

import json
import time

import numpy as np
import pytest

from chainid.records.reader import read_any
from chainid.records.record import Record
from chainid.records.spec import spec_from_options
from chainid.records.writer import write_canonical

h5py = pytest.importorskip("h5py")
T = np.arange(64) * 0.01


def test_hidden_files_of_a_directory_or_glob_are_not_read(tmp_path):
    write_canonical(tmp_path / "A.csv", [Record("A", T, 1 + T, 100 + T)])
    (tmp_path / ".junk.csv").write_text("garbage,,\n\x00\x01")
    (tmp_path / ".~lock.A.csv#").write_text(",root,host,26.11.2026 16:39,file:///root;")
    spec = spec_from_options(units="x=mm")
    assert [r.test for r in read_any(tmp_path, spec)] == ["A"]
    assert [r.test for r in read_any(str(tmp_path / "*.csv"), spec)] == ["A"]


def test_an_hdf5_dataset_declaring_two_billion_rows_is_refused_before_reading(tmp_path):
    p = tmp_path / "huge.h5"
    with h5py.File(p, "w") as f:
        for name in ("t", "x", "F"):  # declared, never written: a tiny file
            f.create_dataset(name, shape=(2_000_000_000,), dtype="f8", chunks=(1 << 20,))
    assert p.stat().st_size < 1_000_000
    t0 = time.perf_counter()
    with pytest.raises(ValueError, match=r"huge\.h5: the file's datasets declares 6,000,000,000 values; reading them "
                                         r"needs about 89.4 GiB, over the .* GiB of memory available"):
        read_any(p, spec_from_options(units="x=mm"))
    assert time.perf_counter() - t0 < 10.0


def test_dangling_and_external_hdf5_links_are_one_error(tmp_path):
    p = tmp_path / "links.h5"
    with h5py.File(p, "w") as f:
        f["t"], f["x"] = T, 1 + T
        f["F"] = h5py.SoftLink("/nowhere/F")
    with pytest.raises(ValueError, match=r"links\.h5/F: a dangling HDF5 link \(to '/nowhere/F'\)"):
        read_any(p, spec_from_options(units="x=mm"))
    (tmp_path / "other.h5").unlink(missing_ok=True)
    with h5py.File(p, "w") as f:
        f["t"], f["x"] = T, 1 + T
        f["F"] = h5py.ExternalLink("other.h5", "/F")
    with pytest.raises(ValueError, match=r"links\.h5/F: an HDF5 external link to 'other\.h5':'/F'; chainid reads only "
                                         r"the file given"):
        read_any(p, spec_from_options(units="x=mm"))


def test_json_integer_beyond_float_and_deep_nesting(tmp_path):
    p = tmp_path / "big.json"
    p.write_text('{"t": [0, 1, 2], "x": [1, 2, 3], "F": [1, 2, 1' + "0" * 400 + "]}")
    with pytest.raises(ValueError, match=r"big\.json: a JSON integer of 401 digits \(10000000000000000000\.\.\.\) is "
                                         r"beyond the float range"):
        read_any(p, spec_from_options(units="x=mm"))
    q = tmp_path / "deep.json"
    q.write_text("[" * 200_000 + "]" * 200_000)
    with pytest.raises(ValueError, match=r"deep\.json: JSON nested too deeply"):
        read_any(q, spec_from_options(units="x=mm"))
    r = tmp_path / "nest.json"
    doc: dict = {"t": T.tolist(), "x": (1 + T).tolist(), "F": (2 + T).tolist()}
    for _ in range(80):
        doc = {"g": doc, "other": {"a": 1}}
    r.write_text(json.dumps({"root": {"a": 1}, "z": doc}))
    with pytest.raises(ValueError, match=r"groups nested deeper than 64 levels"):
        read_any(r, spec_from_options(units="x=mm"))


def test_boolean_or_complex_columns_are_refused_naming_column_and_dtype(tmp_path):
    import pyarrow as pa
    import pyarrow.parquet as pq
    import scipy.io

    pq.write_table(pa.table({"t": T, "x": T > 0.3, "F": 100 + T}), tmp_path / "b.parquet")
    with pytest.raises(ValueError, match=r"b\.parquet: column 'x' \(x\) has dtype bool \(boolean\)"):
        read_any(tmp_path / "b.parquet", spec_from_options(units="x=mm"))
    with h5py.File(tmp_path / "c.h5", "w") as f:
        f["t"], f["x"], f["F"] = T, 1 + T, (100 + T) * (1 + 1j)
    with pytest.raises(ValueError, match=r"c\.h5: column 'F' \(F\) has dtype complex128 \(complex\)"):
        read_any(tmp_path / "c.h5", spec_from_options(units="x=mm"))
    scipy.io.savemat(tmp_path / "m.mat", {"t": T * (1 + 0j), "x": 1 + T, "F": 100 + T})
    with pytest.raises(ValueError, match=r"m\.mat: column 't' \(t\) has dtype complex128 \(complex\)"):
        read_any(tmp_path / "m.mat", spec_from_options(units="x=mm"))
    (tmp_path / "j.json").write_text(json.dumps({"t": T.tolist(), "x": (1 + T).tolist(), "F": [True] * 64}))
    with pytest.raises(ValueError, match=r"j\.json: column 'F' \(F\) has dtype bool \(boolean\)"):
        read_any(tmp_path / "j.json", spec_from_options(units="x=mm"))
