"""``one_thread`` runs a block with every loaded BLAS library and scikit-learn's OpenMP on one thread, and restores
the counts after."""
from __future__ import annotations

import os

import pytest
from threadpoolctl import threadpool_info, threadpool_limits

from chainid.infra.threads import one_thread


def _threads(api: str) -> set[int]:
    return {i["num_threads"] for i in threadpool_info() if i["user_api"] == api}


@pytest.mark.skipif((os.cpu_count() or 1) < 2, reason="one core: BLAS and OpenMP run one thread anyway")
def test_blas_and_openmp_run_one_thread_inside_and_their_former_counts_after():
    import sklearn.ensemble  # noqa: F401  (its OpenMP runtime loaded, so that the outer limit reaches it)

    with threadpool_limits(limits=2, user_api="blas"), threadpool_limits(limits=2, user_api="openmp"):
        assert _threads("blas") == {2} and _threads("openmp") == {2}
        with one_thread():
            assert _threads("blas") == {1} and _threads("openmp") == {1}
        assert _threads("blas") == {2} and _threads("openmp") == {2}
