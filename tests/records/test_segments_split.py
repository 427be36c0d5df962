"""One file, several tests: split at event rows or at time gaps, segment ids from a template and labels, offsets
(``zero``) in the stated order units -> zero -> scale, and per-file column maps (``[[files]]``) in one glob.
References: the volts the test wrote (daq_files) with the authors' scaling done here by hand."""
from __future__ import annotations

import numpy as np
import pytest

from chainid.records.reader import read_any
from chainid.records.spec import load_profile, spec_from_options
from daq_files import write_daq

MR = dict(skip_rows=6, split_events="DAQ Pause", zero="x=first:20", scale="x=10,F=980.665",
          segment_ids="0,0.5,1", segment_id="{stem}_i{label}", covariates=["I_A=_i([0-9.]+)$"])


def test_split_at_pause_ids_offset_gain_and_current(tmp_path):
    p = tmp_path / "ME2mm5Hz.txt"
    ref = write_daq(p, [200, 150, 120])
    recs = read_any(p, spec_from_options(columns="x=CHANNEL1,F=CHANNEL0", **MR))
    assert [r.test for r in recs] == ["ME2mm5Hz_i0", "ME2mm5Hz_i0.5", "ME2mm5Hz_i1"]
    assert [r.covariates for r in recs] == [{"I_A": 0.0}, {"I_A": 0.5}, {"I_A": 1.0}]
    for r, seg in zip(recs, ref):
        v = seg["disp"]
        rest = sum(v[:20]) / 20
        np.testing.assert_allclose(r.x, [10.0 * (a - rest) for a in v], rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(r.F, [980.665 * a for a in seg["force"]], rtol=1e-15)
        np.testing.assert_allclose(r.t, (seg["sample"] - seg["sample"][0]) * 0.005, rtol=0, atol=1e-15)


def test_label_count_must_match_the_segments(tmp_path):
    p = tmp_path / "ME.txt"
    write_daq(p, [100, 100, 100])
    with pytest.raises(ValueError, match=r"ME\.txt: 3 segment\(s\) found but --segment-ids gives 2 label\(s\) "
                                         r"\['a', 'b'\]; the count must match"):
        read_any(p, spec_from_options(columns="x=CHANNEL1,F=CHANNEL0", skip_rows=6, split_events="DAQ Pause",
                                      segment_ids="a,b"))
    recs = read_any(p, spec_from_options(columns="x=CHANNEL1,F=CHANNEL0", skip_rows=6, split_events="DAQ Pause"))
    assert [r.test for r in recs] == ["ME_1", "ME_2", "ME_3"]  # the default template {id}_{segment}


def test_split_at_time_gaps_and_restart_time_with_zero_first(tmp_path):
    p = tmp_path / "g.csv"
    t = np.concatenate([np.arange(100) * 0.01, 1.5 + np.arange(80) * 0.01, 3.0 + np.arange(60) * 0.01]).tolist()
    p.write_text("t,x,F\n" + "".join(f"{a!r},{1.0 + a!r},{2.0 * a!r}\n" for a in t))
    recs = read_any(p, spec_from_options(units="t=s", split_gap=0.2))
    assert [r.t.size for r in recs] == [100, 80, 60] and [r.test for r in recs] == ["g_1", "g_2", "g_3"]
    np.testing.assert_array_equal(recs[1].t, t[100:180])  # absolute times kept
    again = read_any(p, spec_from_options(units="t=s", split_gap=0.2, zero="t=first"))
    np.testing.assert_allclose(again[2].t, [a - t[180] for a in t[180:]], rtol=0, atol=1e-15)
    q = tmp_path / "q.csv"
    q.write_text("x,F\n" + "".join(f"{1.0 + i},{2.0 * i}\n" for i in range(30)))
    with pytest.raises(ValueError, match=r"q\.csv: --split-gap needs a time column"):
        read_any(q, spec_from_options(fs=100.0, split_gap=0.2))


def test_units_then_zero_then_scale(tmp_path):
    p = tmp_path / "u.csv"
    v = [0.1 * ((i * 37) % 11) for i in range(50)]
    p.write_text("t,x,F\n" + "".join(f"{0.01 * i!r},{a!r},{100.0 + i!r}\n" for i, a in enumerate(v)))
    (rec,) = read_any(p, spec_from_options(units="x=in", zero="x=mean", scale="x=-2"))
    inch = [25.4 * a for a in v]
    mean = sum(inch) / len(inch)
    np.testing.assert_allclose(rec.x, [-2.0 * (a - mean) for a in inch], rtol=1e-12, atol=1e-12)
    (med,) = read_any(p, spec_from_options(zero="x=median"))
    np.testing.assert_allclose(med.x, [a - sorted(v)[24] / 2 - sorted(v)[25] / 2 for a in v], atol=1e-15)
    with pytest.raises(ValueError, match=r"--zero x=first:60: the segment has only 50 sample\(s\)"):
        read_any(p, spec_from_options(zero="x=first:60"))


def test_files_rules_map_columns_per_file_and_the_command_line_wins(tmp_path):
    a = write_daq(tmp_path / "ME2mm5Hz.txt", [90, 90], force_first=True, seed=1)
    b = write_daq(tmp_path / "ME10mm2Hz.txt", [90, 90], force_first=False, seed=2)
    prof = tmp_path / "mr.toml"
    prof.write_text('skip_rows = 6\nsplit_events = "DAQ Pause"\n[columns]\nx = "CHANNEL1"\nF = "CHANNEL0"\n'
                    '[[files]]\npattern = "*mm2Hz.txt"\ncolumns = { x = "CHANNEL0", F = "CHANNEL1" }\n')
    recs = read_any(str(tmp_path / "ME*.txt"), load_profile(prof))
    by = {r.test: r for r in recs}
    for stem, ref in (("ME2mm5Hz", a), ("ME10mm2Hz", b)):
        for k, seg in enumerate(ref, start=1):
            np.testing.assert_array_equal(by[f"{stem}_{k}"].x, seg["disp"])
            np.testing.assert_array_equal(by[f"{stem}_{k}"].F, seg["force"])
    forced = read_any(str(tmp_path / "ME*.txt"), spec_from_options(prof, columns="x=CHANNEL1,F=CHANNEL0"))
    np.testing.assert_array_equal({r.test: r for r in forced}["ME10mm2Hz_1"].x, b[0]["force"])  # as told
