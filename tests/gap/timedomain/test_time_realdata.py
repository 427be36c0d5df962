"""The real earthquake records of the BRFD friction damper (ARTS-Laboratory, CC BY-SA 4.0; see
shared/realdata/friction-damper/SOURCE.md) in the time domain: not refused, the noise floor from the records
themselves, the chatter while sliding.  Skipped when the shared data are absent (found through CHAINID_SHARED or
next to the repository)."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.gap import diagnose
from repo_paths import REALDATA

EQ = REALDATA / "friction-damper" / "brfd_ds2_earthquake_imperialvalley.csv"


@pytest.mark.slow
@pytest.mark.skipif(not EQ.is_file(), reason="shared real data not present")
def test_earthquake_records_are_diagnosed_in_the_time_domain():
    from chainid.records.files import read_records

    recs = read_records(EQ, validate=False, allow_compression=True)
    res = diagnose(recs, [], None, holdout_blocks=4, quiet=True)
    assert res["route"] == "time"
    assert not res["excluded"]
    # the force is written in steps of q ≈ 3.56 N (SOURCE.md): the estimator must see the lattice and not return
    # a whole number of steps (the plain median of a lattice-valued Δ²F).  Independent reference: the Gaussian-
    # corrected RMS of the central 90 % of Δ²F (a second moment, not a median; the friction jumps trimmed), /√6
    from scipy.stats import norm

    z = norm.ppf(0.95)
    var_trim = 1 - 2 * z * norm.pdf(z) / 0.9
    for r, t in zip(recs, res["tests"]):
        d2 = np.diff(r.F, 2)
        a = np.abs(d2 - np.median(d2))
        ref = math.sqrt(np.mean(d2[a <= np.quantile(a, 0.9)] ** 2) / var_trim / 6)
        assert t["sigma_N"] == pytest.approx(ref, rel=0.12)
        assert t["sigma_N"] >= 3.56 / math.sqrt(12)  # at least the quantisation error itself
    # the damper chatters while it slides (SOURCE: a friction band brake); reported in `where`, not named
    assert any(f["kind"] == "chatter" for f in res["where"])
    assert "chatter" not in res["verdict"]
