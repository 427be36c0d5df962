"""One thread for chainid's many small linear-algebra products and its one small learner.

chainid's matrices are small: a diagnosis' Gram matrices have one row per amplitude (at most a few tens), and it
makes tens of thousands of such products per selection.  OpenBLAS' threads cost more than they give on them: they
wait for each other, and spin against every other busy process on the cores.  Measured on this project's 2-core
machine with one other busy process, one fit and one score of a 2-million-sample set: 1.17 s and 0.79 s with the
default two threads, 0.68 s and 0.14 s with one; at 500 000 samples the two are equal
(``python benchmarks/blas_threads.py --samples 125000``, and ``--samples 31250``).  The model-free check's
gradient-boosted trees (scikit-learn, OpenMP) on at most 10 000 samples behave the same: 0.21–0.31 s with two
OpenMP threads and 0.11–0.13 s with one, beside one other busy process.

:func:`one_thread` limits BLAS and OpenMP to one thread in this process while a block runs (threadpoolctl), and
restores the limits after.  The diagnosis (:func:`chainid.gap.diagnose`, whichever command or caller runs it) runs
inside it; process-level parallelism (forked workers, a process pool, dask) is what uses the other cores.
"""

from __future__ import annotations

import contextlib
from typing import Iterator

__all__ = ["one_thread"]


@contextlib.contextmanager
def one_thread() -> Iterator[None]:
    """Run the block with BLAS (OpenBLAS, MKL, BLIS) and OpenMP limited to one thread: any that threadpoolctl
    controls among the libraries loaded when the block starts (numpy's, scipy's and scikit-learn's are loaded
    first)."""
    import numpy  # noqa: F401  (threadpoolctl reaches only the libraries loaded: numpy's and scipy's BLAS,
    import scipy.linalg  # noqa: F401  scikit-learn's OpenMP)
    import sklearn.ensemble  # noqa: F401
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"), threadpool_limits(limits=1, user_api="openmp"):
        yield
