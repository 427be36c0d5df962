"""``one_blas_thread`` runs a block with every loaded BLAS library on one thread and restores the count after."""
from __future__ import annotations

import os

import pytest
from threadpoolctl import threadpool_info, threadpool_limits

from chainid.infra.threads import one_blas_thread


def _blas_threads() -> set[int]:
    return {i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"}


@pytest.mark.skipif((os.cpu_count() or 1) < 2, reason="one core: BLAS runs one thread anyway")
def test_blas_runs_one_thread_inside_and_its_former_count_after():
    with threadpool_limits(limits=2, user_api="blas"):
        assert _blas_threads() == {2}
        with one_blas_thread():
            assert _blas_threads() == {1}
        assert _blas_threads() == {2}
