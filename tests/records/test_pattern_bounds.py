"""User regular expressions cannot hang the reader: a repeat inside a repeat is refused when the spec is built,
and any other catastrophic pattern runs against a 1 s budget (an error naming the pattern), here on a long file
name where Python's ``re`` alone would take longer than the age of the universe."""
from __future__ import annotations

import time

import numpy as np
import pytest

from chainid.records.reader import read_any
from chainid.records.record import Record
from chainid.records.spec import ReaderSpec, spec_from_options
from chainid.records.writer import write_canonical


@pytest.mark.parametrize("pat", [r"(a+)+$", r"(\w*)*x", r"((ab)*c)+", r"(?:x{1,3})+"])
def test_a_repeat_inside_a_repeat_is_refused_naming_the_option(pat):
    with pytest.raises(ValueError, match=r"reader id_pattern = .*: a repeat inside a repeat"):
        ReaderSpec(id_pattern=pat)
    for key in ("header_marker", "split_events"):
        with pytest.raises(ValueError, match=rf"reader {key} = .*: a repeat inside a repeat"):
            ReaderSpec(**{key: pat})


def test_ordinary_patterns_are_accepted():
    for pat in (r"run_(\d+)", r"(?P<id>\w+)_(\d{2})", r"_([0-9.]+)bar$", r"^Sample Number", "DAQ Pause"):
        ReaderSpec(id_pattern=pat)


def test_an_exponential_pattern_on_a_long_file_name_stops_within_the_budget(tmp_path):
    name = "a" * 60 + "!.csv"
    t = np.arange(32) * 0.01
    write_canonical(tmp_path / name, [Record("A", t, 1 + t, 100 + t)])
    t0 = time.perf_counter()
    with pytest.raises(ValueError, match=r"--id-pattern '\(a\|a\)\+\$' took over 1 s on 'aaaa.*catastrophic "
                                         r"backtracking"):
        read_any(tmp_path / name, spec_from_options(id_pattern=r"(a|a)+$", units="x=mm"))
    assert time.perf_counter() - t0 < 5.0
