"""The line's element tables (chainid.dynamics.line_tables): the stiffest tangent of each memory element, which the
stable step must see, against the elements' laws by hand.  Units mm, N, kg."""
from __future__ import annotations

import numpy as np
import pytest

from chainid.dynamics import ChainLine
from chainid.dynamics.line_tables import element_stiffness


@pytest.mark.parametrize("r", [0.25, 0.5, 0.75, 1.0])
def test_a_bouc_wen_element_is_stiffest_unloading_at_max_1_2r_times_its_yield_slope(r):
    """Bouc–Wen (F_y = 5 N, x_y = 0.1 mm, n = 2, r) in a line of two 5-link segments: the stiffest tangent is
    unloading, max(1, 2r)·F_y/x_y, per segment scaled as the line scales its elements (reference links / links
    per segment = 16/5): 160 N/mm for r <= 0.5, 240 at 0.75, 320 at 1 (by hand)."""
    line = ChainLine(n_links=10, n_masses=2, pretension_N=1000.0, bouc_wen=((5.0, 0.1, 2.0, r),))
    scale = line.reference_links() / line.links_per_segment()
    assert scale.tolist() == [3.2, 3.2]
    np.testing.assert_allclose(element_stiffness(line), max(1.0, 2 * r) * 5.0 / 0.1 * scale, rtol=1e-12)
