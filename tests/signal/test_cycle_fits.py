"""Per-segment least squares (chainid.signal.cycles) against a hand computation."""
from __future__ import annotations

import numpy as np
import pytest


def test_segment_lstsq_by_hand():
    """Two segments, regressors (1, u), two targets: segment 0 holds y = 2 + 3u exactly (β = 2, 3; RSS 0);
    segment 1 holds y = (0, 1, 5) at u = (0, 1, 2): the least-squares line by hand is −1/2 + 5/2·u with RSS
    (1/2)² + (1)² + (1/2)² = 1.5.  A segment marked invalid gets β = 0, so its RSS is Σ y²."""
    from chainid.signal.cycles import segment_lstsq

    seg = np.array([0, 0, 0, 1, 1, 1])
    u = np.array([0.0, 1.0, 2.0, 0.0, 1.0, 2.0])
    y = np.array([2.0, 5.0, 8.0, 0.0, 1.0, 5.0])
    beta, rss = segment_lstsq(seg, 2, (np.ones(6), u), (y, 2 * y), rss=True)
    assert beta.shape == (2, 2, 2) and rss.shape == (2, 2)
    np.testing.assert_allclose(beta[:, :, 0], [[2.0, 3.0], [-0.5, 2.5]], atol=1e-12)
    np.testing.assert_allclose(beta[:, :, 1], [[4.0, 6.0], [-1.0, 5.0]], atol=1e-12)
    np.testing.assert_allclose(rss, [[0.0, 0.0], [1.5, 6.0]], atol=1e-12)
    beta, rss = segment_lstsq(seg, 2, (np.ones(6), u), (y,), valid=np.array([True, False]), rss=True)
    np.testing.assert_allclose(beta[1, :, 0], [0.0, 0.0])
    assert rss[1, 0] == pytest.approx(0.0 + 1.0 + 25.0)
    b2, none = segment_lstsq(seg, 2, (np.ones(6), u), (y,))
    assert none is None and np.allclose(b2[0, :, 0], [2.0, 3.0])
