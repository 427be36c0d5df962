"""Every binary reader checks the size a file declares against the memory limit before it reads the data
(:func:`chainid.records.formats.check_memory`): a MAT file (its variables' shapes), a TDMS file (its channels'
lengths) and a JSON file (its size in bytes, one value per 2 bytes) over the limit is one error naming the file, the
declared number of values, the memory needed (2 x 8 bytes per value) and the limit, and the reader proper
(``scipy.io.loadmat``, ``TdmsFile.read``, ``json.load``) is never called.  (HDF5: test_binary_safety.py.)

No test allocates the declared size: the MAT file is 12 kB with its three vectors' dimensions rewritten to
40,000 x 50,000 in the file layout (MAT v5: the dimensions sub-element is the int32 tag (5, 8) followed by the two
dimensions), against a limit set to 1 GiB (so the message does not depend on the machine); the TDMS and JSON files
are small real files against a limit monkeypatched down to a few kB.
References: the counts and sizes written into the files here, the GiB figures by hand (bytes / 2³⁰), and the limit's
boundary (exactly the bytes needed is read, one byte less is refused).
"""
from __future__ import annotations

import json
import struct

import numpy as np
import pytest
import scipy.io

from chainid.records import formats
from chainid.records.reader import read_any
from chainid.records.spec import spec_from_options

N = 500
T = np.arange(N) * 0.01
SPEC = spec_from_options(units="x=mm")


def _limit(monkeypatch, n_bytes: int) -> None:
    monkeypatch.setattr(formats, "available_memory", lambda: n_bytes)


def _never(what: str):
    def boom(*a, **k):
        raise AssertionError(f"{what} was called before the memory check refused the file")
    return boom


def test_a_mat_file_declaring_three_40000_by_50000_matrices_is_refused_before_loadmat(tmp_path, monkeypatch):
    small = tmp_path / "small.mat"
    scipy.io.savemat(small, {"t": T, "x": 1 + T, "F": 100 + T})  # uncompressed (1, 500) rows
    dims = struct.pack("<iiii", 5, 8, 1, N)  # miINT32, 8 bytes, dims 1 x 500
    raw = small.read_bytes()
    assert raw.count(dims) == 3
    p = tmp_path / "huge.mat"
    p.write_bytes(raw.replace(dims, struct.pack("<iiii", 5, 8, 40_000, 50_000)))  # 2e9 values each
    assert p.stat().st_size < 20_000
    _limit(monkeypatch, 2**30)
    monkeypatch.setattr(scipy.io, "loadmat", _never("scipy.io.loadmat"))
    # 3 x 2e9 values, 2 x 8 bytes each: 9.6e10 B = 89.4 GiB, over the 1 GiB limit
    with pytest.raises(ValueError, match=r"huge\.mat: the MAT file's variables declares 6,000,000,000 values; reading "
                                         r"them needs about 89\.4 GiB, over the 1 GiB of memory available"):
        read_any(p, SPEC)


def test_a_tdms_file_over_the_limit_is_refused_before_it_is_read(tmp_path, monkeypatch):
    from nptdms import ChannelObject, GroupObject, TdmsFile, TdmsWriter

    p = tmp_path / "daq.tdms"
    with TdmsWriter(p) as w:
        w.write_segment([GroupObject("g"), ChannelObject("g", "t", T), ChannelObject("g", "x", 1 + T),
                         ChannelObject("g", "F", 100 + T)])
    need = 2 * 8 * 3 * N  # 24,000 B
    _limit(monkeypatch, need)  # exactly enough: read
    (rec,) = read_any(p, SPEC)
    assert np.array_equal(rec.F, 100 + T)
    _limit(monkeypatch, 4096)
    monkeypatch.setattr(TdmsFile, "read", _never("TdmsFile.read"))
    # 24,000 B = 2.24e-05 GiB; 4096 B = 3.81e-06 GiB
    with pytest.raises(ValueError, match=r"daq\.tdms: the TDMS file's channels declares 1,500 values; reading them "
                                         r"needs about 2\.24e-05 GiB, over the 3\.81e-06 GiB of memory available"):
        read_any(p, SPEC)
    _limit(monkeypatch, need - 1)  # one byte short
    with pytest.raises(ValueError, match=r"daq\.tdms: the TDMS file's channels declares 1,500 values"):
        read_any(p, SPEC)


def test_a_json_file_over_the_limit_is_refused_before_it_is_parsed(tmp_path, monkeypatch):
    p = tmp_path / "run.json"
    p.write_text(json.dumps({"t": T.tolist(), "x": (1 + T).tolist(), "F": (100 + T).tolist()}))
    assert p.stat().st_size == 11_946  # so it declares 11,946 // 2 = 5,973 values, 2 x 8 x 5,973 = 95,568 B
    _limit(monkeypatch, 95_568)  # exactly enough: parsed
    (rec,) = read_any(p, SPEC)
    assert np.array_equal(rec.x, 1 + T)
    _limit(monkeypatch, 95_567)  # one byte short
    monkeypatch.setattr(json, "load", _never("json.load"))
    # 95,568 B = 8.90e-05 GiB
    with pytest.raises(ValueError, match=r"run\.json: the JSON file's size declares 5,973 values; reading them needs "
                                         r"about 8\.9e-05 GiB, over the 8\.9e-05 GiB of memory available"):
        read_any(p, SPEC)
    _limit(monkeypatch, 4096)
    with pytest.raises(ValueError, match=r"run\.json: .* over the 3\.81e-06 GiB of memory available"):
        read_any(p, SPEC)
