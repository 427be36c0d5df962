"""A diagnosis with resampling runs inside a daemonic worker process (a benchmark's pool, a dask worker), which
may not start children: the resamples then run in that process.  Every case of a benchmark run with
``--resamples 200`` failed with 'daemonic processes are not allowed to have children' before."""
from __future__ import annotations

import multiprocessing as mp
import warnings

import numpy as np
import pytest

import recovery_cases as rc

pytestmark = pytest.mark.slow


def _job(queue) -> None:  # noqa: ANN001
    from chainid.gap.core.resample import POOL_MIN
    from chainid.gap.diagnose import diagnose

    recs = rc.linear_random(lambda mo, t: 2.0 * np.sign(mo(t)[1]), n=1500, band=(0.5, 4.0), seed=3)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res = diagnose(recs, ["r4"], None, quiet=True, effects=["friction"], max_combo=1, resamples=POOL_MIN,
                           seed=1)
        queue.put(("ok", res["verdict"], res["stability"]["resamples"]))
    except Exception as exc:  # the failure itself is the finding
        queue.put(("error", repr(exc), 0))


def test_resampling_runs_inside_a_daemonic_worker():
    from chainid.gap.core.resample import POOL_MIN

    ctx = mp.get_context("spawn")  # a fresh interpreter: forking a threaded test worker (xdist) can deadlock
    q = ctx.Queue()
    p = ctx.Process(target=_job, args=(q,), daemon=True)
    p.start()
    status, verdict, n = q.get(timeout=300)
    p.join(30)
    assert status == "ok", verdict
    assert (verdict, n) == ("friction", POOL_MIN)
