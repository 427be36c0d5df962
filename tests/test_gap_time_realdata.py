"""Issue 18 on the real earthquake records of the BRFD friction damper (ARTS-Laboratory, CC BY-SA 4.0; see
../shared/realdata/friction-damper/SOURCE.md): not refused, the noise floor from the records themselves, the
chatter while sliding.  Skipped when the shared data are absent."""
from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np
import pytest

from chainid.gap import diagnose

_ROOTS = [Path(os.environ.get("CHAINID_REALDATA", "/nonexistent")), Path(__file__).parents[2] / "shared" / "realdata"
          / "friction-damper", Path("/work/shared/realdata/friction-damper")]
EQ = next((r / "brfd_ds2_earthquake_imperialvalley.csv" for r in _ROOTS
           if (r / "brfd_ds2_earthquake_imperialvalley.csv").is_file()), Path("/nonexistent"))


@pytest.mark.skipif(not EQ.is_file(), reason="shared real data not present")
def test_earthquake_records_are_diagnosed_in_the_time_domain():
    from chainid.records.files import read_records

    recs = read_records(EQ, validate=False, allow_compression=True)
    res = diagnose(recs, [], None, holdout_blocks=4, quiet=True)
    assert res["route"] == "time"
    assert not res["excluded"]
    # independent reference for the noise floor: the force is written in steps of q ≈ 3.56 N (SOURCE.md); with
    # white noise below one step, Δ²F takes the values 0, ±q, ±2q… and its median absolute value is q or 2q,
    # so σ = 1.4826·MAD/√6 is a whole multiple of 1.4826·q/√6
    q = float(np.median(np.diff(np.unique(np.round(recs[0].F, 2)))))
    unit = 1.4826 * q / math.sqrt(6.0)
    for t in res["tests"]:
        assert t["sigma_N"] / unit == pytest.approx(round(t["sigma_N"] / unit), abs=0.05)
    # the damper chatters while it slides (SOURCE: a friction band brake); reported in `where`, not named
    assert any(f["kind"] == "chatter" for f in res["where"])
    assert "chatter" not in res["verdict"]
